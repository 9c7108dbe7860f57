#include "renderer/render_loop.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "renderer/adaptive.h"
#include "renderer/geometry/camera.h"
#include "renderer/progress.h"
#include "renderer/tile_schedule.h"

namespace kiln {

std::atomic<bool>& renderCancelFlag() {
    static std::atomic<bool> flag{false};
    return flag;
}

std::atomic<bool>& checkpointRequestFlag() {
    static std::atomic<bool> flag{false};
    return flag;
}

namespace {

// Camera samples a render traces per integrator call: enough for full 16-wide packets after
// paths die off, few enough that the batch stays in cache.
constexpr size_t kBatchSamples = 256;

Sampler::PixelKey pixelKey(const RenderSettings& settings, int x, int y) {
    return Sampler::pixelKey(settings.seed, uint64_t(y) * uint64_t(settings.width) + uint64_t(x));
}

// Appends the camera sample of pixel (x, y) (its sampler's key given), sample s, built in place.
void addCameraSample(std::vector<CameraSample>& batch, const CameraModel& camera,
                     const AovRequest& aovs, const RenderSettings& settings, Sampler::PixelKey key,
                     int x, int y, int s) {
    Sampler sampler(key, uint64_t(s), settings.sampler);
    float jx = sampler.next1D(), jy = sampler.next1D();
    float lu = 0.5f, lv = 0.5f;
    if (camera.hasLens()) {
        lu = sampler.next1D(), lv = sampler.next1D();
    } else {
        sampler.skip2D();
    }
    CameraSample& cs = batch.emplace_back(camera.generateRay(float(x) + jx, float(y) + jy, lu, lv),
                                          sampler, SampleRecord{});
    cs.record.reset(aovs);
}

}  // namespace

SampleRecord traceSample(const Scene& scene, const Integrator& integrator,
                         const RenderSettings& settings, int x, int y, int sample,
                         RayCounter& counter) {
    const PixelXY pixel{x, y};
    return traceSamples(scene, integrator, settings, {&pixel, 1}, sample, 1, counter)[0];
}

std::vector<SampleRecord> traceSamples(const Scene& scene, const Integrator& integrator,
                                       const RenderSettings& settings,
                                       std::span<const PixelXY> pixels, int first, int count,
                                       RayCounter& counter) {
    CameraModel camera(scene.camera, settings.width, settings.height);
    static const AovRequest all = AovRequest::parse("all", kMaxBounceLayers);
    std::vector<CameraSample> batch;
    batch.reserve(pixels.size() * size_t(std::max(count, 0)));
    for (const auto [x, y] : pixels) {
        const Sampler::PixelKey key = pixelKey(settings, x, y);
        for (int s = first; s < first + count; ++s)
            addCameraSample(batch, camera, all, settings, key, x, y, s);
    }
    integrator.Li(std::span<CameraSample>(batch), counter);
    std::vector<SampleRecord> records;
    records.reserve(batch.size());
    for (CameraSample& c : batch) records.push_back(std::move(c.record));
    return records;
}

namespace {

// The sample indices where waves end. Waves of 1, 1, 2, 4, ... samples (at most kMaxWave): an
// interrupted render has nearly even counts everywhere. Adaptive renders go in waves of one step
// (-a's batch, or the noise threshold's minimum samples), the granularity of the convergence test.
// The sums do not depend on the waves (they are exact); only the adaptive test points do, and those
// are fixed multiples of the step.
constexpr int kMaxWave = 64;

std::vector<int> waveEnds(const RenderSettings& s) {
    std::vector<int> ends;
    const int step = s.adaptiveStep();
    int done = s.sampleStart, wave = step > 0 ? step : 1;
    while (done < s.spp) {
        done = std::min(s.spp, step > 0 ? (done / wave + 1) * wave : done + wave);
        ends.push_back(done);
        if (step <= 0 && done > s.sampleStart + 1) wave = std::min(2 * wave, kMaxWave);
    }
    return ends;
}

// The samples pixel (x, y) of the film still lacks.
uint64_t remainingSamples(const Film& film, const RenderSettings& s) {
    uint64_t n = 0;
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            if (!film.converged(x, y))
                n += uint64_t(std::max(0, s.spp - s.sampleStart - int(film.samples(x, y))));
    return n;
}

using Clock = std::chrono::steady_clock;

Clock::time_point after(Clock::time_point t, double seconds) {
    return t + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

}  // namespace

RenderStats renderImage(const Scene& scene, const Integrator& integrator,
                        const RenderSettings& settings, Film& film, const RenderControl& control) {
    RenderStats stats;
    CameraModel camera(scene.camera, settings.width, settings.height);
    // Tiles cover the film (the render region); cameras and samplers see whole-image pixels.
    const int fw = settings.filmWidth(), fh = settings.filmHeight();
    const int ox = settings.filmOriginX(), oy = settings.filmOriginY();
    if (film.width() != fw || film.height() != fh)
        throw std::logic_error("renderImage: film size differs from the render region");
    int tile = std::max(1, settings.tileSize);
    int tilesX = (fw + tile - 1) / tile, tilesY = (fh + tile - 1) / tile;
    const uint64_t totalWork = remainingSamples(film, settings);
    Progress progress("render", totalWork, settings.progress);
    std::atomic<uint64_t> doneWork{0};
    std::atomic<uint64_t> nonFinite{0};
    std::mutex badMutex;
    std::vector<BadSample> bad;
    std::atomic<bool>& signalled = renderCancelFlag();
    auto cancelled = [&] {
        return signalled.load(std::memory_order_relaxed) ||
               (control.cancel && control.cancel->load(std::memory_order_relaxed));
    };
    std::atomic<bool>& request = checkpointRequestFlag();
    const bool timed = control.timeLimitSeconds > 0, periodic = control.checkpointEverySeconds > 0;
    const Clock::time_point limit = after(control.start, control.timeLimitSeconds);
    Clock::time_point nextCheckpoint = after(control.start, control.checkpointEverySeconds);
    // Checked before every pixel: any reason to stop the tiles (they finish the pixel in hand).
    std::atomic<bool> paused{false};
    auto pausing = [&] {
        if (paused.load(std::memory_order_relaxed)) return true;
        bool stop = cancelled() || (request.load(std::memory_order_relaxed) && control.checkpoint);
        if (!stop && (timed || periodic)) {
            Clock::time_point now = Clock::now();
            stop = (timed && now >= limit) || (periodic && now >= nextCheckpoint);
        }
        if (stop) paused.store(true);
        return stop;
    };

    const int adaptiveStep = settings.adaptiveStep();
    // Each tile's time in the last whole wave (the next wave's order) and in this one, summed over
    // its runs when checkpoints pause the wave.
    std::vector<double> lastWaveSeconds(size_t(tilesX) * size_t(tilesY), 0.0);
    std::vector<double> waveSeconds(lastWaveSeconds.size(), 0.0);
    auto renderTile = [&](int tileIndex, int waveStart, int waveEnd) {
        const Clock::time_point tileStart = Clock::now();
        int x0 = (tileIndex % tilesX) * tile, y0 = (tileIndex / tilesX) * tile;
        int x1 = std::min(x0 + tile, fw), y1 = std::min(y0 + tile, fh);
        RayCounter counter;
        uint64_t work = 0, badCount = 0;
        std::vector<CameraSample> batch;
        struct Queued {
            int x, y, first;
        };
        std::vector<Queued> queued;  // the pixels of the batch, in order
        batch.reserve(kBatchSamples + size_t(waveEnd - waveStart));
        // Whole pixels per batch, samples in order.
        auto flush = [&] {
            integrator.Li(std::span<CameraSample>(batch), counter);
            size_t k = 0;
            for (auto [x, y, first] : queued) {
                for (int s = first; s < waveEnd; ++s, ++k) {
                    if (film.add(x, y, batch[k].record, s)) continue;
                    // Dropped from the image, counted, and kept for replay (in whole-image
                    // pixels, as --pixel takes them).
                    ++badCount;
                    std::lock_guard lock(badMutex);
                    bad.push_back({x + ox, y + oy, s});
                }
                // The convergence test at fixed sample counts, so resumed renders test alike.
                if (adaptiveStep > 0 && film.samples(x, y) % adaptiveStep == 0 &&
                    adaptiveConverges(film, settings, x, y))
                    film.setConverged(x, y);
            }
            batch.clear();
            queued.clear();
        };
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                int first = std::max(waveStart, settings.sampleStart + int(film.samples(x, y)));
                if (first >= waveEnd) continue;
                if (pausing()) {
                    y = y1;
                    break;
                }
                work += uint64_t(waveEnd - first);
                if (film.converged(x, y)) continue;
                const Sampler::PixelKey key = pixelKey(settings, x + ox, y + oy);
                for (int s = first; s < waveEnd; ++s)
                    addCameraSample(batch, camera, film.layout().request(), settings, key, x + ox,
                                    y + oy, s);
                queued.push_back({x, y, first});
                if (batch.size() >= kBatchSamples) flush();
            }
        if (!batch.empty()) flush();
        // Before the callbacks: the Python module's waits for its caller.
        waveSeconds[size_t(tileIndex)] +=
            std::chrono::duration<double>(Clock::now() - tileStart).count();
        progress.add(work, counter.rays);
        if (badCount) nonFinite += badCount;
        if (control.tileDone) control.tileDone(doneWork += work, totalWork);
    };

    auto snapshot = [&] {
        stats.seconds = progress.elapsedSeconds();
        stats.rays = progress.rays();
        stats.samples = film.totalSamples();
        stats.nonFiniteSamples = nonFinite.load();
    };
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        int waveStart = settings.sampleStart;
        for (int waveEnd : waveEnds(settings)) {
            std::fill(waveSeconds.begin(), waveSeconds.end(), 0.0);
            for (;;) {
                paused.store(false);
                forEachTileInOrder(costliestFirst(lastWaveSeconds),
                                   tbb::this_task_arena::max_concurrency(),
                                   [&](int t) { renderTile(t, waveStart, waveEnd); });
                if (!paused.load()) break;
                if (cancelled()) return;
                if (timed && Clock::now() >= limit) {
                    stats.timeLimitReached = true;
                    return;
                }
                // A checkpoint (periodic or SIGUSR1), then the rest of the wave.
                request.store(false);
                snapshot();
                const Clock::time_point written = Clock::now();
                if (control.checkpoint) control.checkpoint(film, stats);
                // Never sooner than a write takes, nor than 10 ms: a shorter period
                // (--checkpoint-every 1e-6) had every tile pause before its first pixel, and the
                // render wrote checkpoints without end.
                const Clock::time_point now = Clock::now();
                nextCheckpoint = std::max({after(now, control.checkpointEverySeconds),
                                           now + (now - written), after(now, 0.01)});
            }
            lastWaveSeconds.swap(waveSeconds);
            waveStart = waveEnd;
        }
    });
    progress.finish();
    snapshot();
    std::sort(bad.begin(), bad.end(), [](const BadSample& a, const BadSample& b) {
        return std::tie(a.y, a.x, a.sample) < std::tie(b.y, b.x, b.sample);
    });
    if (bad.size() > 10) bad.resize(10);
    stats.firstBadSamples = bad;
    stats.interrupted = cancelled();
    stats.complete = remainingSamples(film, settings) == 0;
    return stats;
}

}  // namespace kiln
