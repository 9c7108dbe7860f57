// What the camera will see, before the render: a quick probe of the frame (a grid of pixels across
// the render region, a few samples each, traced exactly as the render traces them) and its mean
// and brightest luminance. kiln render warns from it that the image will look black, whatever the
// cause (lights too dim or too far for the scene's size, a light convention, a camera that sees
// nothing lit): no fixed threshold on light power can tell.
#pragma once

#include <optional>
#include <string>

#include "renderer/render_job.h"

namespace kiln {

struct FrameProbe {
    int pixels = 0, samplesPerPixel = 0;
    double meanLuminance = 0;  // over every probe sample (non-finite ones skipped)
    double maxPixelLuminance = 0;
};

// Up to maxPixels pixels on an even grid over the render region, spp samples each (the render's
// first sample indices), and never more samples than a quarter of the render's (pixels x spp).
// Costs at most maxPixels * spp camera samples; trains the guide field if the job is guided (the
// render would train it anyway).
FrameProbe probeFrame(const RenderJob& job, int maxPixels = 4096, int spp = 2);

// Below this mean luminance (scene-linear, after exposure) an image shows as black: 1e-3 is
// code 3 of 255 after the sRGB encoding.
constexpr double kBlackMeanLuminance = 1e-3;

// The warning, or nothing when the probe finds a visible image. exposureStops scales as the
// preview does (2^stops).
std::optional<std::string> blackImageWarning(const FrameProbe& probe, float exposureStops = 0);

}  // namespace kiln
