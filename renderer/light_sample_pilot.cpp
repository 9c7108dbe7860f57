#include "renderer/light_sample_pilot.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "integrators/make_integrator.h"
#include "renderer/render_loop.h"

namespace kiln {
namespace {

// The pilot's random numbers: another stream than every render seed's.
constexpr uint64_t kPilotSeedSalt = 0x6c69676874706c74ull;

// What a camera sample costs, from what it did: nanoseconds per operation on one core of the
// 2-core development machine, fitted to single-thread renders of four scenes (an environment-lit
// Lucy and glossy bunny, two area-lit rooms) at -l 1, 2, 4 and 8 (docs/performance.md): a camera
// sample with its ray, each closest-hit ray after it with its vertex's shading, each shadow ray,
// each environment light sample drawn (located, looked up, its BSDF evaluated). Only the ratio of
// the base cost to a light sample's matters, and the choice is a power of two: a constant off by
// 2x moves n* by sqrt(2).
struct CostModel {
    double cameraSample, bounceRay, shadowRay, lightDraw;
};
constexpr CostModel kCost{150.0, 290.0, 80.0, 110.0};

double costOf(const RayCounter& c, uint64_t cameraSamples) {
    const uint64_t closest = c.rays - c.shadowRays;
    return kCost.cameraSample * double(cameraSamples) +
           kCost.bounceRay * double(closest - std::min(closest, cameraSamples)) +
           kCost.shadowRay * double(c.shadowRays) + kCost.lightDraw * double(c.lightDraws);
}

// One count's pilot: each grid pixel's mean luminance, the variance of its spp-sample mean (from
// `seeds` renders of it with independent seeds), and the work per camera sample.
struct PilotRun {
    std::vector<double> mean, variance;
    double costPerSample = 0;
};

// The pilot's integrator, settings and grid.
struct PilotSetup {
    IntegratorKind integrator;
    PathOptions path;
    RenderSettings settings;
    int nx, ny, spp, seeds;
};

PilotRun runPilot(const Scene& scene, const Accelerator& accel, const RenderPlan& plan,
                  PilotSetup setup, int lightSamples) {
    setup.path.lightSamples = lightSamples;
    const int nx = setup.nx, ny = setup.ny, spp = setup.spp, seeds = setup.seeds;
    RenderSettings s = setup.settings;
    s.regionX0 = s.regionY0 = s.regionX1 = s.regionY1 = 0;
    std::unique_ptr<Integrator> integrator =
        makeIntegrator(setup.integrator, scene, accel, setup.path, plan);
    const size_t pixels = size_t(nx) * size_t(ny);
    PilotRun run;
    run.mean.assign(pixels, 0.0);
    run.variance.assign(pixels, 0.0);
    std::vector<RayCounter> counters(pixels);
    auto trace = [&](size_t i) {
        const int px = int((double(i % nx) + 0.5) * s.width / nx);
        const int py = int((double(i / nx) + 0.5) * s.height / ny);
        RenderSettings seeded = s;
        double sum = 0, sumSq = 0;  // over the seeds' means
        for (int r = 0; r < seeds; ++r) {
            seeded.seed = mix64(s.seed ^ kPilotSeedSalt) + uint64_t(r);
            double m = 0;
            for (int k = 0; k < spp; ++k) {
                const double y =
                    luminance(traceSample(scene, *integrator, seeded, px, py, k, counters[i]).L);
                m += std::isfinite(y) ? y / spp : 0.0;
            }
            sum += m, sumSq += m * m;
        }
        run.mean[i] = sum / seeds;
        run.variance[i] = std::max(0.0, (sumSq - sum * run.mean[i]) / (seeds - 1));
    };
    tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
    arena.execute([&] { tbb::parallel_for(size_t(0), pixels, trace); });
    double cost = 0;  // summed in pixel order: the same for any thread count
    for (const RayCounter& c : counters) cost += costOf(c, uint64_t(spp * seeds));
    run.costPerSample = cost / double(pixels * size_t(spp * seeds));
    return run;
}

// The power of two nearest n* in log scale, within [1, kMaxChosen].
int nearestPowerOfTwo(double n) {
    if (!(n > 1)) return 1;
    const double log2n = std::round(std::log2(n));
    return int(std::min(double(LightSamplePilot::kMaxChosen), std::exp2(log2n)));
}

}  // namespace

std::string LightSamplePilot::describe() const {
    return fmt::format(
        "{} ({} pixels x {} seeds x {} samples at -l {} and {}: relative variance {:.4g} direct + "
        "{:.4g} other, cost {:.4g} + {:.4g} per light sample)",
        chosen, pixels, seeds, samplesPerPixel, kLow, kHigh, directVariance, otherVariance,
        baseCost, lightCost);
}

bool pilotChoosesLightSamples(IntegratorKind integrator, const PathOptions& path,
                              const RenderPlan& plan) {
    return integrator == IntegratorKind::Path && path.lightSamples <= 0 &&
           path.sampling == DirectSampling::Mis && plan.lightSamplesOpen;
}

LightSamplePilot pilotLightSamples(const Scene& scene, const Accelerator& accel,
                                   IntegratorKind integrator, const PathOptions& path,
                                   const RenderSettings& settings, const RenderPlan& plan,
                                   int maxPixels, int spp, int seeds) {
    LightSamplePilot pilot;
    const auto start = std::chrono::steady_clock::now();
    const RenderSettings& s = settings;
    if (s.width <= 0 || s.height <= 0 || maxPixels <= 0 || spp < 1 || seeds < 2) return pilot;
    // An nx x ny grid of the image's aspect, at most maxPixels and a sixteenth of the image (at
    // least 64 pixels): a small image's pilot stays small beside its render.
    const double imagePixels = double(s.width) * double(s.height);
    const double gridPixels = std::min(double(maxPixels), std::max(64.0, imagePixels / 16));
    const double scale = std::sqrt(gridPixels / imagePixels);
    const int nx = std::clamp(int(s.width * scale), 1, s.width);
    const int ny = std::clamp(int(s.height * scale), 1, s.height);
    pilot.pixels = nx * ny, pilot.samplesPerPixel = spp, pilot.seeds = seeds;
    const PilotSetup setup{integrator, path, settings, nx, ny, spp, seeds};
    const PilotRun low = runPilot(scene, accel, plan, setup, LightSamplePilot::kLow);
    const PilotRun high = runPilot(scene, accel, plan, setup, LightSamplePilot::kHigh);
    // Relative to each pixel's brightness (both runs' mean), as the benchmark's relative MSE.
    double vLow = 0, vHigh = 0;
    for (size_t i = 0; i < low.mean.size(); ++i) {
        const double m = 0.5 * (low.mean[i] + high.mean[i]), norm = m * m + 0.01;
        vLow += low.variance[i] / norm, vHigh += high.variance[i] / norm;
    }
    vLow /= double(low.mean.size()), vHigh /= double(low.mean.size());
    // V(n) = other + direct / n and C(n) = base + n light, through the two runs.
    constexpr double a = LightSamplePilot::kLow, b = LightSamplePilot::kHigh;
    pilot.directVariance = std::max(0.0, (vLow - vHigh) / (1 / a - 1 / b));
    pilot.otherVariance = std::max(0.0, vLow - pilot.directVariance / a);
    pilot.lightCost = (high.costPerSample - low.costPerSample) / (b - a);
    pilot.baseCost = low.costPerSample - a * pilot.lightCost;
    if (pilot.directVariance <= 0)
        pilot.chosen = 1;
    else if (pilot.otherVariance <= 0 || pilot.lightCost <= 0)
        pilot.chosen = LightSamplePilot::kMaxChosen;
    else
        pilot.chosen =
            nearestPowerOfTwo(std::sqrt(pilot.directVariance * std::max(0.0, pilot.baseCost) /
                                        (pilot.otherVariance * pilot.lightCost)));
    pilot.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return pilot;
}

}  // namespace kiln
