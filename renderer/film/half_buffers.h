// The denoiser's half-buffers: the film's sums of colour and features split by sample index, even
// samples in half A, odd ones in half B (Bitterli et al. 2016, "Nonlinearly Weighted First-order
// Regression for Denoising Monte Carlo Renderings", section 4). Two independent estimates of
// every pixel give its variance and let the denoiser cross-filter; kept only with --denoise
// (AovKind::DenoiseHalves). The split follows the sample index, never the order samples arrive
// in, so checkpoints, resumes, sample-range shards and merges hold the same bits.
#pragma once

#include <string>
#include <vector>

#include "renderer/film/aov.h"

namespace kiln {

// Features per half: albedo RGB, shading normal XYZ, depth along the camera ray.
constexpr int kHalfFeatures = 7;
// The film's sums per half: colour RGB, its squares (the per-pixel sample variance), features.
constexpr int kHalfSums = 3 + 3 + kHalfFeatures;
// What a half holds for the denoiser (Film::halfMean, the EXR's halfA.* / halfB.*, in this
// order): colour RGB, the variance of each colour mean (-1 where under two samples leave it
// unknown), then the feature means.
constexpr int kHalfChannels = 3 + 3 + kHalfFeatures;

// Per half and denoised light-path layer (AovLayout::denoisedLayers, --denoise-aovs): the film's
// sums of its colour and of its squares, and what the denoiser takes in place of the beauty's
// first six channels (colour RGB, the variance of each mean).
constexpr int kLayerHalfSums = 6;
constexpr int kLayerHalfChannels = 6;

inline int halfOfSample(uint32_t sampleIndex) { return int(sampleIndex & 1u); }

// A sample's features for the half-buffers: zero where the camera ray missed; a non-finite
// value (a degenerate normal) becomes zero and depth is capped, so a feature never drops a sample.
void halfFeatures(const SampleRecord& r, double out[kHalfFeatures]);

// The EXR channel names of half 0 (A) or 1 (B): the kHalfChannels values ("halfA.R", "halfA.G",
// "halfA.B", "halfA.var_R", ..., "halfA.albedo_R", ..., "halfA.N_X", ..., "halfA.Z"), then the
// half's sample count ("halfA.n").
const std::vector<std::string>& halfBufferChannels(int half);

// The EXR channel names of a denoised layer's half: "halfA.direct.R", ..., "halfA.direct.var_B"
// (kLayerHalfChannels, in Film::layerHalfMean's order).
std::vector<std::string> layerHalfChannels(int half, const std::string& layer);

// A half's colour mean and the variance of that mean from its sums of values and squares over n
// samples, both times scale (the film's radiance scale); the variance is -1 where under two
// samples leave it unknown.
void halfMeanAndVariance(double sum, double squares, double n, double scale, float& mean,
                         float& variance);

}  // namespace kiln
