// Adaptive sampling's stopping rules. Each is a pure function of one pixel's exact film sums at a
// test point (a multiple of RenderSettings::adaptiveStep), so the pixels that stop, and the image,
// are the same for any thread count, tile size or checkpoint/resume point.
#pragma once

#include "renderer/film/film.h"
#include "renderer/render_settings.h"

namespace kiln {

// The relative standard error of the pixel's luminance mean: sqrt(Var[mean] / (mu^2 + 0.01)),
// the root of the pixel's expected relative squared error (relativeSquaredError). Var[mean] is the
// unbiased sample variance over n; infinite below 2 samples.
double pixelRelativeError(const Film& film, int x, int y);

// Whether the pixel, holding a test point's samples, stops: the CS184 rule with -a BATCH TOL
// (1.96 sigma / sqrt(n) <= TOL mu), else the noise threshold.
bool adaptiveConverges(const Film& film, const RenderSettings& settings, int x, int y);

}  // namespace kiln
