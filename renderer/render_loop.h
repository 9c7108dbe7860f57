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
#include "renderer/render_settings.h"

namespace kiln {

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
    // Stops this render alone at the next pixel, as SIGINT stops every render (the Python module:
    // a callback returning False, KeyboardInterrupt, another thread); stats.interrupted says so.
    const std::atomic<bool>* cancel = nullptr;
    // Called after each tile, by the thread that rendered it, with the samples done and the
    // samples in all (the Python module's progress callback).
    std::function<void(uint64_t done, uint64_t total)> tileDone;
};

// Replays one camera sample exactly as the render loop traces it (same sampler state): for
// debugging.
SampleRecord traceSample(const Scene& scene, const Integrator& integrator,
                         const RenderSettings& settings, int x, int y, int sample,
                         RayCounter& counter);
// Samples [first, first + count) of each pixel, traced together as one batch, pixel after pixel
// (each the sample traceSample gives: a path's numbers and light do not depend on its batch).
struct PixelXY {
    int x, y;
};
std::vector<SampleRecord> traceSamples(const Scene& scene, const Integrator& integrator,
                                       const RenderSettings& settings,
                                       std::span<const PixelXY> pixels, int first, int count,
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
