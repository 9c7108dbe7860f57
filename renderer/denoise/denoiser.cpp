#include "renderer/denoise/denoiser.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <optional>
#include <string>

#include "renderer/denoise/nl_means.h"
#include "renderer/denoise/regression.h"

namespace kiln::denoise {
namespace {

// Per half: colour, its variance, then the features.
constexpr int kColour = 0, kVariance = 3, kFeatures = 6;
// The two bandwidths NFOR chooses between per pixel (section 5.3).
constexpr float kBandwidths[2] = {0.5f, 1.0f};
// The variance maps from the halves' difference: one degree of freedom per pixel, averaged over
// this box radius.
constexpr int kVarianceRadius = 2;

// The halves with non-finite values replaced by 0 (variances: by "unknown").
Halves sanitized(Halves out) {
    for (Image& half : out.half)
        parallelChunks(half.values.size(), [&half](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                const int c = int(i % size_t(half.channels));
                if (!std::isfinite(half.values[i]))
                    half.values[i] = c >= kVariance && c < kFeatures ? -1.0f : 0.0f;
            }
        });
    return out;
}

// Per channel: (a + b) / 2 and its variance (a - b)^2 / 4 (two independent halves).
void meanAndVariance(const Image& a, const Image& b, Image& mean, Image& variance) {
    mean = Image(a.width, a.height, a.channels), variance = mean;
    parallelChunks(a.values.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            float d = a.values[i] - b.values[i];
            mean.values[i] = 0.5f * (a.values[i] + b.values[i]);
            variance.values[i] = 0.25f * d * d;
        }
    });
}

// The variance of the halves' mean colour from the halves' sample variances, (vA + vB) / 4;
// where a half's is unknown, the estimate from their difference.
Image sampleVariance(const Halves& in, const Image& fromDifference) {
    Image v = fromDifference;
    parallelChunks(v.pixels(), [&](size_t begin, size_t end) {
        for (size_t p = begin; p < end; ++p)
            for (int c = 0; c < 3; ++c) {
                size_t at = p * size_t(in.half[0].channels) + size_t(kVariance + c);
                float a = in.half[0].values[at], b = in.half[1].values[at];
                if (a >= 0 && b >= 0) v.values[p * 3 + size_t(c)] = 0.25f * (a + b);
            }
    });
    return v;
}

struct FilterPair {
    Image a, b;  // half A and half B filtered
};

// Step 2 and 3's estimate at every bandwidth: each half regressed on its own filtered features,
// with the other half as the weights' guide. Its own, not the other's (Tungsten's choice): at a
// texture or outline edge a half's colour follows where its own samples fell in the pixel, and
// a fit on the other half's features reads that as noise in the regressors, which flattens the
// slope on the features and softens the edge (the textured cube's albedo edges: 0.980 -> 0.994
// of the reference's at 16 spp, mean of 8 seeds, relMSE 4 % lower). The other half's colour
// noise then reaches a half's estimate only through the weights, as the MSE estimate assumes.
std::vector<FilterPair> regressHalves(const Image colour[2], const Image features[2],
                                      const Image& variance, const Options& o) {
    // The weights' guide is a half: its variance is twice the mean's.
    RegressionParams p{{o.patchRadius, o.windowRadius, 1.0f, 2.0f},
                       {std::begin(kBandwidths), std::end(kBandwidths)},
                       o.fitStride};
    std::vector<Image> a = collaborativeRegression(colour[0], colour[1], features[0], variance, p);
    std::vector<Image> b = collaborativeRegression(colour[1], colour[0], features[1], variance, p);
    std::vector<FilterPair> pairs;
    for (size_t k = 0; k < a.size(); ++k) pairs.push_back({std::move(a[k]), std::move(b[k])});
    return pairs;
}

// The MSE of the pair's mean, estimated from the halves (each filtered half against the other
// noisy half, less that half's variance and the filtered halves' own difference).
Image estimatedMse(const Image colour[2], const FilterPair& f, const Image& variance) {
    Image mse(f.a.width, f.a.height, 3);
    parallelChunks(mse.values.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            float ea = colour[1].values[i] - f.a.values[i];
            float eb = colour[0].values[i] - f.b.values[i];
            float between = f.b.values[i] - f.a.values[i];
            mse.values[i] =
                0.5f * (ea * ea + eb * eb) - 2.0f * variance.values[i] - 0.25f * between * between;
        }
    });
    return mse;
}

Image smoothedMap(const Image& map, const Image& guide, const Image& variance, const Options& o) {
    return nlMeans(map, guide, variance, {1, o.mseWindow, 1.0f, 1.0f});
}

// Both MSE maps smoothed with one set of weights (the same guide): side by side as channels.
void smoothMaps(Image mse[2], const Image& guide, const Image& variance, const Options& o) {
    Image both(guide.width, guide.height, 6);
    parallelChunks(both.pixels(), [&](size_t begin, size_t end) {
        for (size_t p = begin; p < end; ++p)
            for (int c = 0; c < 3; ++c)
                for (int b = 0; b < 2; ++b)
                    both.values[p * 6 + size_t(3 * b + c)] = mse[b].values[p * 3 + size_t(c)];
    });
    both = smoothedMap(both, guide, variance, o);
    for (int b = 0; b < 2; ++b) mse[b] = channelsOf(both, 3 * b, 3);
}

// The features prefiltered once for every colour image of a frame (steps 1 and 4's feature
// filter).
struct Prefiltered {
    Image filtered[2];    // each half's features, guided by the other half
    Image finalFeatures;  // the filtered halves' mean, filtered once more
};

Prefiltered prefilter(const Halves& in, const Options& o) {
    const int nf = in.half[0].channels - kFeatures;
    Image features[2];
    for (int k = 0; k < 2; ++k) features[k] = channelsOf(in.half[k], kFeatures, nf);
    Image featureMean, featureVariance;
    meanAndVariance(features[0], features[1], featureMean, featureVariance);
    featureVariance = boxMean(featureVariance, kVarianceRadius);
    // 1. Feature prefiltering, each half guided by the other.
    // Where both halves' features agree over a tile's whole reach there is nothing to filter.
    NlMeansParams featureParams{o.patchRadius, o.featureWindow, 0.5f, 2.0f, true};
    Prefiltered p{{nlMeans(features[0], features[1], featureVariance, featureParams),
                   nlMeans(features[1], features[0], featureVariance, featureParams)},
                  {}};
    Image filteredMean, filteredVariance;
    meanAndVariance(p.filtered[0], p.filtered[1], filteredMean, filteredVariance);
    p.finalFeatures =
        nlMeans(filteredMean, filteredMean, filteredVariance, {o.patchRadius, 2, 0.5f, 1.0f});
    return p;
}

std::vector<Color> runNfor(const Halves& in, const Prefiltered& features, const Options& o) {
    const int w = in.half[0].width, h = in.half[0].height;
    Image colour[2];
    for (int k = 0; k < 2; ++k) colour[k] = channelsOf(in.half[k], kColour, 3);
    Image colourMean, colourVariance;
    meanAndVariance(colour[0], colour[1], colourMean, colourVariance);
    colourVariance = sampleVariance(in, boxMean(colourVariance, kVarianceRadius));
    const Image* filtered = features.filtered;

    // 2, 3. Two bandwidths, their MSE, the per-pixel choice.
    std::vector<FilterPair> pass = regressHalves(colour, filtered, colourVariance, o);
    Image mse[2];
    for (int b = 0; b < 2; ++b) mse[b] = estimatedMse(colour, pass[size_t(b)], colourVariance);
    smoothMaps(mse, colourMean, colourVariance, o);
    Image choice(w, h, 3);
    parallelChunks(choice.values.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i)
            choice.values[i] = mse[0].values[i] < mse[1].values[i] ? 0.0f : 1.0f;
    });
    choice = smoothedMap(choice, colourMean, colourVariance, o);
    Image chosen[2] = {Image(w, h, 3), Image(w, h, 3)};
    parallelChunks(choice.values.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            float t = choice.values[i];
            chosen[0].values[i] = (1 - t) * pass[0].a.values[i] + t * pass[1].a.values[i];
            chosen[1].values[i] = (1 - t) * pass[0].b.values[i] + t * pass[1].b.values[i];
        }
    });

    // 4. The second pass over the averaged halves.
    Image combined, combinedVariance;
    meanAndVariance(chosen[0], chosen[1], combined, combinedVariance);
    Image result =
        collaborativeRegression(combined, combined, features.finalFeatures, combinedVariance,
                                {{o.patchRadius, o.windowRadius, 1.0f, 1.0f}, {1.0f}, o.fitStride})
            .front();

    // A plane fitted across a light's edge can overshoot below zero next to it; light is never
    // negative, so neither is the result where no input value is.
    const float floor =
        std::min(0.0f, *std::min_element(colourMean.values.begin(), colourMean.values.end()));
    std::vector<Color> out(result.pixels());
    parallelChunks(out.size(), [&](size_t begin, size_t end) {
        for (size_t p = begin; p < end; ++p) {
            Color c(result.values[3 * p], result.values[3 * p + 1], result.values[3 * p + 2]);
            // A failed fit falls back to the noisy pixel rather than spread anything.
            bool finite = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
            out[p] = finite ? max(c, Color(floor))
                            : Color(colourMean.values[3 * p], colourMean.values[3 * p + 1],
                                    colourMean.values[3 * p + 2]);
        }
    });
    return out;
}

}  // namespace

std::string problemWith(const Halves& halves) {
    const Image &a = halves.half[0], &b = halves.half[1];
    if (a.width <= 0 || a.height <= 0) return "the half-buffers are empty";
    if (a.width != b.width || a.height != b.height)
        return "the half-buffers differ in size (" + std::to_string(a.width) + "x" +
               std::to_string(a.height) + " and " + std::to_string(b.width) + "x" +
               std::to_string(b.height) + ")";
    if (a.channels != b.channels || a.channels < kFeatures || a.channels > kFeatures + 13)
        return "the half-buffers hold unusable channel counts";
    return "";
}

std::vector<std::vector<Color>> denoiseAll(size_t count,
                                           const std::function<Halves(size_t)>& halvesOf,
                                           const Options& options) {
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    std::vector<std::vector<Color>> out(count);
    std::optional<Prefiltered> features;
    for (size_t i = 0; i < count; ++i) {
        arena.execute([&] {
            const Halves clean = sanitized(halvesOf(i));
            if (!features) features = prefilter(clean, options);
            out[i] = runNfor(clean, *features, options);
        });
    }
    return out;
}

std::vector<Color> denoise(const Halves& halves, const Options& options) {
    return denoiseAll(
               1, [&halves](size_t) { return halves; }, options)
        .front();
}

std::string describe(const Options& o) {
    int window = 2 * o.windowRadius + 1, patch = 2 * o.patchRadius + 1;
    return "NFOR (Bitterli et al. 2016): first-order regression on albedo, normal, depth from "
           "the even/odd half-buffers; window " +
           std::to_string(window) + "x" + std::to_string(window) + ", patch " +
           std::to_string(patch) + "x" + std::to_string(patch) +
           ", bandwidths 0.5 and 1, fits every " + std::to_string(o.fitStride) + " pixels";
}

}  // namespace kiln::denoise
