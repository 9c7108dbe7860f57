// kiln's denoiser for final frames: NFOR, the nonlinearly weighted first-order regression of
// Bitterli, Rousselle, Moon, Iglesias-Guitian, Adler, Mitchell, Jarosz and Novak, "Nonlinearly
// Weighted First-order Regression for Denoising Monte Carlo Renderings", Computer Graphics Forum
// 35(4), 2016 (EGSR). Written for kiln after reading Tungsten's src/denoiser (docs/denoise.md):
// 1. the features (albedo, normal, depth) of each half are prefiltered by NL-means guided by the
//    other half (they are noisy under depth of field, motion and glossy reflection; 5.1);
// 2. each half's colour is regressed on its own filtered features with weights from the other
//    half's colour (cross-filtering), at two bandwidths (5.2);
// 3. each pixel picks its bandwidth by the MSE the half-buffers estimate, the estimates and the
//    choice smoothed by NL-means (5.3);
// 4. the two filtered halves are averaged and filtered once more with their difference as the
//    variance (5.4).
// Inputs are the two half-buffers' means and variances; NaN and Inf inputs count as 0 and never
// spread.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "renderer/core/math.h"
#include "renderer/denoise/image.h"

namespace kiln::denoise {

// The two half-buffers of a frame (even and odd samples), per pixel: colour RGB, the variance of
// each colour value (negative: unknown, estimated from the two halves instead), then the
// features; both the same size and channels.
struct Halves {
    Image half[2];
};

struct Options {
    int threads = 0;        // 0: all cores
    int windowRadius = 4;   // the regression's window: (2R+1)^2 pixels
    int patchRadius = 3;    // NL-means patches: (2F+1)^2
    int featureWindow = 4;  // the feature prefilter's window radius
    int mseWindow = 3;      // the MSE and selection maps' smoothing window radius
    int fitStride = 2;      // regression fits at every fitStride-th pixel in x and y
};

// "" when the halves can be denoised, else what is wrong with them.
std::string problemWith(const Halves& halves);

// The denoised colour, row-major. Bit-identical for any thread count.
std::vector<Color> denoise(const Halves& halves, const Options& options = {});

// Several colour images of one frame that share its features (the beauty, then light-path
// layers): halvesOf(i) gives the i-th one's halves, asked for one at a time. The features are
// prefiltered once, from the first; each result is the one denoise() gives.
std::vector<std::vector<Color>> denoiseAll(size_t count,
                                           const std::function<Halves(size_t)>& halvesOf,
                                           const Options& options = {});

// One line for the EXR header: the method and its parameters.
std::string describe(const Options& options);

}  // namespace kiln::denoise
