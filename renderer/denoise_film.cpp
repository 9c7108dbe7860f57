#include "renderer/denoise_film.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

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

denoise::Halves halvesOf(const Film& film) {
    denoise::Halves halves;
    for (denoise::Image& half : halves.half)
        half = denoise::Image(film.width(), film.height(), kHalfChannels);
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            float samples[2];
            for (int h = 0; h < 2; ++h) {
                film.halfMean(x, y, h, halves.half[h].at(x, y));
                samples[h] = float(film.halfSamples(x, y, h));
            }
            borrowEmptyHalf(halves, x, y, samples);
        }
    return halves;
}

std::shared_ptr<const std::vector<Color>> denoiseFilm(const Film& film,
                                                      const denoise::Options& options) {
    return std::make_shared<const std::vector<Color>>(denoise::denoise(halvesOf(film), options));
}

void denoiseForOutputs(const Film& film, int threads, ExrOptions& exr, Metadata& meta) {
    denoise::Options options;
    options.threads = threads;
    auto start = std::chrono::steady_clock::now();
    exr.denoised = denoiseFilm(film, options);
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    meta["denoised"] = denoise::describe(options);
    meta["denoise_seconds"] = fmt::format("{:.3f}", seconds);
    logInfo("denoised {}x{} in {:.2f}s", film.width(), film.height(), seconds);
}

namespace {

// The channels of half h in the file, in the film's order; throws naming the first one missing.
std::vector<int> halfChannelsIn(const ExrImage& exr, int h, const std::string& path) {
    std::vector<int> at;
    for (const std::string& name : halfBufferChannels(h)) {
        int c = exr.channel(name);
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

}  // namespace

denoise::Halves halvesOf(const ExrImage& exr, const std::string& path) {
    const int w = exr.width(), h = exr.height();
    std::vector<int> channels[2] = {halfChannelsIn(exr, 0, path), halfChannelsIn(exr, 1, path)};
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
                                                halfBufferChannels(k)[size_t(c)] + " at pixel (" +
                                                std::to_string(x) + ", " + std::to_string(y) + ")");
                    if (c < kHalfChannels) halves.half[k].at(x, y)[c] = v;
                }
                samples[k] = exr.value(x, y, channels[k][kHalfChannels]);
            }
            borrowEmptyHalf(halves, x, y, samples);
            if (count >= 0 && samples[0] + samples[1] != exr.value(x, y, count))
                throw DenoiseInputError(path +
                                        ": the half-buffers' sample counts do not add up "
                                        "to samples.X at pixel (" +
                                        std::to_string(x) + ", " + std::to_string(y) + ")");
        }
    return halves;
}

double denoiseExr(const std::string& in, const std::string& out, const denoise::Options& options) {
    ExrImage exr = ExrImage::read(in);
    denoise::Halves halves = halvesOf(exr, in);
    for (const char* c : {"R", "G", "B"})
        if (exr.channel(c) < 0) throw DenoiseInputError(in + ": has no beauty channel " + c);
    auto start = std::chrono::steady_clock::now();
    std::vector<Color> denoised = denoise::denoise(halves, options);
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const size_t pixels = denoised.size();
    const char* names[3] = {"R", "G", "B"};
    const bool keptNoisy = exr.channel("noisy.R") >= 0;
    for (int c = 0; c < 3; ++c) {
        std::vector<float> plane(pixels), noisy(pixels);
        const int at = exr.channel(names[c]);
        for (size_t p = 0; p < pixels; ++p) {
            plane[p] = denoised[p][c];
            noisy[p] = exr.value(int(p % size_t(exr.width())), int(p / size_t(exr.width())), at);
        }
        if (!keptNoisy) exr.setChannel(std::string("noisy.") + names[c], noisy, false);
        exr.setChannel(names[c], plane, false);
    }
    exr.setAttribute("kiln:denoised", denoise::describe(options));
    exr.write(out);
    return seconds;
}

}  // namespace kiln
