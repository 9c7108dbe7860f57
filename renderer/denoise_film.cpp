#include "renderer/denoise_film.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>

#include "renderer/core/log.h"
#include "renderer/film/half_buffers.h"

namespace kiln {

namespace {

// A pixel whose half holds no sample (a 1-spp render) takes the other half's values: the two
// then agree there and the denoiser leaves the pixel nearly as it is.
void borrowEmptyHalf(denoise::Halves& halves, int x, int y, const float samples[2]) {
    for (int h = 0; h < 2; ++h)
        if (samples[h] == 0 && samples[1 - h] > 0)
            std::copy_n(halves.half[1 - h].at(x, y), kHalfChannels, halves.half[h].at(x, y));
}

}  // namespace

denoise::Halves halvesOf(const Film& film, int layer) {
    denoise::Halves halves;
    for (denoise::Image& half : halves.half)
        half = denoise::Image(film.width(), film.height(), kHalfChannels);
    // Each pixel from its own sums: rows in parallel give the same image for any thread count.
    denoise::parallelChunks(
        size_t(film.height()),
        [&](size_t y0, size_t y1) {
            for (int y = int(y0); y < int(y1); ++y)
                for (int x = 0; x < film.width(); ++x) {
                    float samples[2];
                    for (int h = 0; h < 2; ++h) {
                        float* values = halves.half[h].at(x, y);
                        film.halfMean(x, y, h, values);
                        // The layer's colour and variance in place of the beauty's first channels.
                        if (layer >= 0) film.layerHalfMean(x, y, h, size_t(layer), values);
                        samples[h] = float(film.halfSamples(x, y, h));
                    }
                    borrowEmptyHalf(halves, x, y, samples);
                }
        },
        4);
    return halves;
}

std::shared_ptr<const std::vector<Color>> denoiseFilm(const Film& film,
                                                      const denoise::Options& options, int layer) {
    // The halves read inside the denoiser's threads (options.threads), as the denoising itself.
    return std::make_shared<const std::vector<Color>>(
        std::move(denoise::denoiseAll(
                      1, [&](size_t) { return halvesOf(film, layer); }, options)
                      .front()));
}

void denoiseForOutputs(const Film& film, int threads, ExrOptions& exr, Metadata& meta) {
    denoise::Options options;
    options.threads = threads;
    auto start = std::chrono::steady_clock::now();
    const std::vector<DenoisedLayer>& denoised = film.layout().denoisedLayers();
    // The beauty, then each layer, sharing the prefiltered features.
    std::vector<std::vector<Color>> images = denoise::denoiseAll(
        denoised.size() + 1, [&film](size_t i) { return halvesOf(film, int(i) - 1); }, options);
    exr.denoised = std::make_shared<const std::vector<Color>>(std::move(images[0]));
    std::string layers;
    for (size_t l = 0; l < denoised.size(); ++l) {
        exr.denoisedLayers[denoised[l].name] =
            std::make_shared<const std::vector<Color>>(std::move(images[l + 1]));
        if (!layers.empty()) layers += ',';
        layers += denoised[l].name;
    }
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    meta["denoised"] = denoise::describe(options);
    if (!layers.empty()) meta["denoised_aovs"] = layers;
    meta["denoise_seconds"] = fmt::format("{:.3f}", seconds);
    logInfo("denoised {}x{}{} in {:.2f}s", film.width(), film.height(),
            layers.empty() ? "" : " (beauty, " + layers + ")", seconds);
}

namespace {

// The channel names of half h in the film's order, a layer's colour channels in place of the
// beauty's.
std::vector<std::string> halfChannelNames(int h, const std::string& layer) {
    std::vector<std::string> names = halfBufferChannels(h);
    if (!layer.empty()) {
        std::vector<std::string> own = layerHalfChannels(h, layer);
        std::copy(own.begin(), own.end(), names.begin());
    }
    return names;
}

// Their channels in the file; throws naming the first one missing.
std::vector<int> halfChannelsIn(const ExrImage& exr, int h, const std::string& layer,
                                const std::string& path) {
    const std::vector<std::string> names = halfChannelNames(h, layer);
    std::vector<int> at;
    for (const std::string& name : names) {
        int c = exr.channel(name);
        if (c < 0 && !layer.empty() && at.size() < size_t(kLayerHalfChannels))
            throw DenoiseInputError(path + ": carries no half-buffers of the AOV '" + layer +
                                    "' (render it with kiln render --denoise --denoise-aovs " +
                                    layer + ")");
        if (c < 0)
            throw DenoiseInputError(
                path + ": " +
                (h == 0 && at.empty()
                     ? std::string("carries no half-buffers (render it with kiln render "
                                   "--denoise)")
                     : "incomplete half-buffers: no channel " + name));
        at.push_back(c);
    }
    return at;
}

std::string pixelText(int x, int y) {
    return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

}  // namespace

denoise::Halves halvesOf(const ExrImage& exr, const std::string& path, const std::string& layer) {
    const int w = exr.width(), h = exr.height();
    std::vector<int> channels[2] = {halfChannelsIn(exr, 0, layer, path),
                                    halfChannelsIn(exr, 1, layer, path)};
    const int count = exr.channel("samples.X");
    denoise::Halves halves;
    for (int k = 0; k < 2; ++k) halves.half[k] = denoise::Image(w, h, kHalfChannels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float samples[2];
            for (int k = 0; k < 2; ++k) {
                for (int c = 0; c < kHalfChannels + 1; ++c) {
                    float v = exr.value(x, y, channels[k][size_t(c)]);
                    if (!std::isfinite(v))
                        throw DenoiseInputError(path + ": non-finite value in " +
                                                halfChannelNames(k, layer)[size_t(c)] + " at " +
                                                pixelText(x, y));
                    if (c < kHalfChannels) halves.half[k].at(x, y)[c] = v;
                }
                samples[k] = exr.value(x, y, channels[k][kHalfChannels]);
            }
            borrowEmptyHalf(halves, x, y, samples);
            if (count >= 0 && samples[0] + samples[1] != exr.value(x, y, count))
                throw DenoiseInputError(path +
                                        ": the half-buffers' sample counts do not add up "
                                        "to samples.X at " +
                                        pixelText(x, y));
        }
    return halves;
}

namespace {

// The layers of the kinds in bits that exr holds ("bounces": each bounceN); throws naming a kind
// it lacks.
std::vector<std::string> layersIn(const ExrImage& exr, uint32_t bits, const std::string& path) {
    std::vector<std::string> layers;
    std::string names = AovRequest::namesOf(bits);
    std::stringstream list(names);
    std::string name;
    while (std::getline(list, name, ',')) {
        const size_t before = layers.size();
        if (name != "bounces") {
            if (exr.channel(name + ".R") >= 0) layers.push_back(name);
        } else {
            for (int b = 1; b <= kMaxBounceLayers; ++b)
                if (exr.channel("bounce" + std::to_string(b) + ".R") >= 0)
                    layers.push_back("bounce" + std::to_string(b));
        }
        if (layers.size() == before)
            throw DenoiseInputError(path + ": has no AOV layer '" + name +
                                    "' (render it with --aov " + name + ")");
    }
    return layers;
}

// The EXR's PREFIX{R,G,B} ("" the beauty, "direct." a layer) replaced by denoised, the old values
// kept as noisy.PREFIX{R,G,B} unless the file holds those already (it was denoised before).
void replaceWithDenoised(ExrImage& exr, const std::string& prefix,
                         const std::vector<Color>& denoised) {
    const bool keptNoisy = exr.channel("noisy." + prefix + "R") >= 0;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        std::vector<float> plane(denoised.size()), noisy(denoised.size());
        const int at = exr.channel(prefix + names[c]);
        for (size_t p = 0; p < denoised.size(); ++p) {
            plane[p] = denoised[p][c];
            noisy[p] = exr.value(int(p % size_t(exr.width())), int(p / size_t(exr.width())), at);
        }
        if (!keptNoisy) exr.setChannel("noisy." + prefix + names[c], noisy, false);
        exr.setChannel(prefix + names[c], plane, false);
    }
}

}  // namespace

double denoiseExr(const std::string& in, const std::string& out, const denoise::Options& options,
                  uint32_t denoisedLight) {
    ExrImage exr = ExrImage::read(in);
    denoise::Halves halves = halvesOf(exr, in);
    for (const char* c : {"R", "G", "B"})
        if (exr.channel(c) < 0) throw DenoiseInputError(in + ": has no beauty channel " + c);
    const std::vector<std::string> layers =
        denoisedLight ? layersIn(exr, denoisedLight, in) : std::vector<std::string>{};
    for (const std::string& layer : layers) halvesOf(exr, in, layer);  // checked before any work
    auto start = std::chrono::steady_clock::now();
    // The beauty, then each layer, sharing the prefiltered features; each is asked for once, so
    // the beauty's halves are moved in, not copied.
    std::vector<std::vector<Color>> denoised = denoise::denoiseAll(
        layers.size() + 1,
        [&](size_t i) { return i == 0 ? std::move(halves) : halvesOf(exr, in, layers[i - 1]); },
        options);
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    replaceWithDenoised(exr, "", denoised[0]);
    std::string names;
    for (size_t l = 0; l < layers.size(); ++l) {
        replaceWithDenoised(exr, layers[l] + ".", denoised[l + 1]);
        if (!names.empty()) names += ',';
        names += layers[l];
    }
    exr.setAttribute("kiln:denoised", denoise::describe(options));
    if (!names.empty()) exr.setAttribute("kiln:denoised_aovs", names);
    exr.write(out);
    return seconds;
}

}  // namespace kiln
