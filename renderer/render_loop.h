// The TBB tile loop: sample waves over tiles, deterministic sampling, cancellation with true
// counts.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "renderer/film/film.h"

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

// A sample that produced NaN or Inf: enough to replay it with --pixel X Y --sample N.
struct BadSample {
    int x = 0, y = 0;
    int sample = 0;
};

struct RenderStats {
    double seconds = 0;
    uint64_t rays = 0;
    uint64_t samples = 0;
    uint64_t nonFiniteSamples = 0;
    std::vector<BadSample> firstBadSamples;  // the first few, in (pixel, sample) order
    bool interrupted = false;                // SIGINT/SIGTERM: stopped at a pixel boundary
    bool timeLimitReached = false;           // RenderControl::timeLimitSeconds: likewise
    bool complete = false;                   // every pixel has all its samples (or converged)
};

// What a long render does besides rendering: periodic checkpoints (at a pixel boundary, the film
// quiescent) and a time limit. The loop stops there, the caller writes what it has.
struct RenderControl {
    double checkpointEverySeconds = 0;  // 0: none
    double timeLimitSeconds = 0;        // 0: none; counted from start
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    // Called between pixels with no tile running; stats hold the counts so far.
    std::function<void(const Film&, const RenderStats&)> checkpoint;
};

// Replays one camera sample exactly as the render loop traces it (same sampler state): for
// debugging.
SampleRecord traceSample(const Scene& scene, const Integrator& integrator,
                         const RenderSettings& settings, int x, int y, int sample,
                         RayCounter& counter);

// Set by the SIGINT/SIGTERM handler; the loop stops at the next pixel and keeps what it has.
std::atomic<bool>& renderCancelFlag();
// Set by the SIGUSR1 handler: write a checkpoint at the next pixel boundary and go on.
std::atomic<bool>& checkpointRequestFlag();

// Renders the samples each pixel still lacks: a pixel holding n samples continues at sample
// sampleStart + n, so a film read back from a checkpoint resumes exactly where it stopped.
RenderStats renderImage(const Scene& scene, const Integrator& integrator,
                        const RenderSettings& settings, Film& film,
                        const RenderControl& control = {});

}  // namespace kiln
