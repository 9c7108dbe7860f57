// What a render is asked for: image and region, samples, threads, tiles, seed, sampler and the
// adaptive-sampling rule. Plain data, read by the tile loop, adaptive sampling and checkpoints.
#pragma once

#include <cstdint>
#include <string>

#include "renderer/core/sampler.h"

namespace kiln {

struct RenderSettings {
    int width = 800, height = 600;
    // Render region (pbrt's crop window): pixels [x0, x1) x [y0, y1) of the width x height image.
    // The film holds just those; a pixel renders exactly as it would in the whole image. x1 = 0:
    // the whole image.
    int regionX0 = 0, regionY0 = 0, regionX1 = 0, regionY1 = 0;
    bool hasRegion() const { return regionX1 > 0; }
    int filmWidth() const { return hasRegion() ? regionX1 - regionX0 : width; }
    int filmHeight() const { return hasRegion() ? regionY1 - regionY0 : height; }
    int filmOriginX() const {
        return hasRegion() ? regionX0 : 0;
    }  // film pixel (0, 0) in the image
    int filmOriginY() const { return hasRegion() ? regionY0 : 0; }
    int spp = 1;  // the render ends at sample index spp (exclusive)
    // --sample-range A B: this render takes samples [sampleStart, spp) of every pixel (a shard).
    int sampleStart = 0;
    int threads = 0;  // 0 = all cores
    int tileSize = 32;
    uint64_t seed = 0;
    SamplerKind sampler = SamplerKind::Sobol;  // measured: docs/performance.md, "Estimators"
    bool progress = true;
    // Adaptive sampling as CS184 defines it: every adaptiveBatch samples a pixel stops once
    // 1.96 sigma / sqrt(n) <= adaptiveTolerance * mu on sample illuminance. 0 = off.
    int adaptiveBatch = 0;
    float adaptiveTolerance = 0.05f;
    // Adaptive sampling by a noise threshold (Cycles' adaptive_threshold): after
    // adaptiveMinSpp samples and every adaptiveMinSpp after, a pixel stops once the relative
    // standard error of its luminance mean is <= noiseThreshold (renderer/adaptive.h). 0 = off.
    float noiseThreshold = 0;
    int adaptiveMinSpp = 16;
    // The sample counts where adaptive sampling tests a pixel are the multiples of this; 0: off.
    int adaptiveStep() const {
        return adaptiveBatch > 0 ? adaptiveBatch : noiseThreshold > 0 ? adaptiveMinSpp : 0;
    }
    // "off", "BATCH TOL" (CS184) or "noise T min N": the metadata's and the checkpoint
    // fingerprint's name of the rule.
    std::string adaptiveText() const;
};

}  // namespace kiln
