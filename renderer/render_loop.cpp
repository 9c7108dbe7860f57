#include "renderer/render_loop.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "renderer/geometry/camera.h"
#include "renderer/progress.h"

namespace kiln {

std::atomic<bool>& renderCancelFlag() {
    static std::atomic<bool> flag{false};
    return flag;
}

namespace {

// Camera samples a render traces per integrator call: enough for full 16-wide packets after
// paths die off, few enough that the batch stays in cache.
constexpr size_t kBatchSamples = 256;

// Appends the camera sample of pixel (x, y), sample s, built in place.
void addCameraSample(std::vector<CameraSample>& batch, const CameraModel& camera,
                     const AovRequest& aovs, const RenderSettings& settings, int x, int y, int s) {
    Sampler sampler(settings.seed, uint64_t(y) * uint64_t(settings.width) + uint64_t(x),
                    uint64_t(s), settings.sampler);
    float jx = sampler.next1D(), jy = sampler.next1D();
    float lu = sampler.next1D(), lv = sampler.next1D();
    CameraSample& cs = batch.emplace_back(camera.generateRay(float(x) + jx, float(y) + jy, lu, lv),
                                          sampler, SampleRecord{});
    cs.record.reset(aovs);
}

}  // namespace

SampleRecord traceSample(const Scene& scene, const Integrator& integrator,
                         const RenderSettings& settings, int x, int y, int sample,
                         RayCounter& counter) {
    CameraModel camera(scene.camera, settings.width, settings.height);
    AovRequest all = AovRequest::parse("all", kMaxBounceLayers);
    std::vector<CameraSample> one;
    addCameraSample(one, camera, all, settings, x, y, sample);
    integrator.Li(std::span<CameraSample>(one), counter);
    return one[0].record;
}

RenderStats renderImage(const Scene& scene, const Integrator& integrator,
                        const RenderSettings& settings, Film& film) {
    RenderStats stats;
    CameraModel camera(scene.camera, settings.width, settings.height);
    // Tiles cover the film (the render region); cameras and samplers see whole-image pixels.
    const int fw = settings.filmWidth(), fh = settings.filmHeight();
    const int ox = settings.filmOriginX(), oy = settings.filmOriginY();
    if (film.width() != fw || film.height() != fh)
        throw std::logic_error("renderImage: film size differs from the render region");
    int tile = std::max(1, settings.tileSize);
    int tilesX = (fw + tile - 1) / tile, tilesY = (fh + tile - 1) / tile;
    uint64_t pixels = uint64_t(fw) * uint64_t(fh);
    Progress progress("render", pixels * uint64_t(settings.spp), settings.progress);
    std::atomic<uint64_t> nonFinite{0};
    std::mutex badMutex;
    std::vector<BadSample> bad;
    std::atomic<bool>& cancel = renderCancelFlag();

    // Adaptive sampling: a pixel that met the confidence test takes no more samples.
    std::vector<uint8_t> converged(settings.adaptiveBatch > 0 ? size_t(pixels) : 0, 0);
    auto converges = [&](int x, int y) {
        double n = film.samples(x, y);
        if (n < 2) return false;
        double s1 = film.luminanceSum(x, y), s2 = film.luminanceSquareSum(x, y);
        double mu = s1 / n, var = std::max(0.0, (s2 - s1 * s1 / n) / (n - 1));
        return 1.96 * std::sqrt(var / n) <= settings.adaptiveTolerance * mu;
    };

    auto renderTile = [&](int tileIndex, int firstSample, int sampleCount) {
        int x0 = (tileIndex % tilesX) * tile, y0 = (tileIndex / tilesX) * tile;
        int x1 = std::min(x0 + tile, fw), y1 = std::min(y0 + tile, fh);
        RayCounter counter;
        uint64_t work = 0, badCount = 0;
        std::vector<CameraSample> batch;
        std::vector<std::pair<int, int>> pixels;  // of the batch, in order
        batch.reserve(kBatchSamples + size_t(sampleCount));
        // Whole pixels per batch, samples in order, so the film sums each pixel as before.
        auto flush = [&] {
            integrator.Li(std::span<CameraSample>(batch), counter);
            size_t k = 0;
            for (auto [x, y] : pixels) {
                for (int s = firstSample; s < firstSample + sampleCount; ++s, ++k) {
                    if (film.add(x, y, batch[k].record)) continue;
                    // Non-finite: dropped from the image, counted, and kept for replay (in
                    // whole-image pixels, as --pixel takes them).
                    ++badCount;
                    std::lock_guard lock(badMutex);
                    bad.push_back({x + ox, y + oy, s});
                }
                if (!converged.empty() && converges(x, y)) converged[uint64_t(y) * fw + x] = 1;
            }
            batch.clear();
            pixels.clear();
        };
        for (int y = y0; y < y1 && !cancel.load(std::memory_order_relaxed); ++y)
            for (int x = x0; x < x1; ++x) {
                work += uint64_t(sampleCount);
                if (!converged.empty() && converged[uint64_t(y) * fw + x]) continue;
                for (int s = firstSample; s < firstSample + sampleCount; ++s)
                    addCameraSample(batch, camera, film.layout().request(), settings, x + ox,
                                    y + oy, s);
                pixels.emplace_back(x, y);
                if (batch.size() >= kBatchSamples) flush();
            }
        if (!batch.empty()) flush();
        progress.add(work, counter.rays);
        if (badCount) nonFinite += badCount;
    };

    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        // Waves of 1, 1, 2, 4, ... samples: an interrupted render has nearly even counts
        // everywhere. Adaptive renders go in waves of one batch, the granularity of the convergence
        // test.
        int done = 0, wave = settings.adaptiveBatch > 0 ? settings.adaptiveBatch : 1;
        while (done < settings.spp && !cancel.load()) {
            int n = std::min(wave, settings.spp - done);
            tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 1),
                              [&](const tbb::blocked_range<int>& r) {
                                  for (int t = r.begin(); t != r.end(); ++t) renderTile(t, done, n);
                              });
            done += n;
            if (done > 1 && settings.adaptiveBatch <= 0) wave *= 2;
        }
    });
    progress.finish();
    stats.seconds = progress.elapsedSeconds();
    stats.rays = progress.rays();
    stats.samples = film.totalSamples();
    stats.nonFiniteSamples = nonFinite.load();
    std::sort(bad.begin(), bad.end(), [](const BadSample& a, const BadSample& b) {
        return std::tie(a.y, a.x, a.sample) < std::tie(b.y, b.x, b.sample);
    });
    if (bad.size() > 10) bad.resize(10);
    stats.firstBadSamples = bad;
    stats.interrupted = cancel.load();
    return stats;
}

}  // namespace kiln
