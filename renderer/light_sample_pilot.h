// How many light samples a vertex takes where the user gives no -l and the render plan leaves the
// count open (an environment map lights the scene): the count that reaches a given error soonest.
// A vertex's next-event estimate is split n ways (Veach's "splitting"; Rath et al., "EARS:
// Efficiency-Aware Russian Roulette and Splitting", SIGGRAPH 2022, choose it per vertex): with
// per-sample relative variance V(n) = V_other + V_direct / n and cost C(n) = C_base + n C_light,
// the work to a given error, V(n) C(n), is least at n* = sqrt(V_direct C_base / (V_other C_light)).
// A pilot measures both at two counts on a grid of pixels and picks the power of two nearest n*. On
// an environment-lit diffuse mesh nearly all the noise is direct light, which more samples remove
// cheaply; under a glossy object most of it comes from later bounces, which they do not. The pilot
// depends on the scene, camera, image size, seed and path options alone (never on the region,
// sample range, samples, threads or tiles), so every shard, resumed and refined render picks the
// same count and images stay bit-identical.
#pragma once

#include <string>

#include "integrators/path_options.h"
#include "integrators/render_plan.h"
#include "renderer/render_settings.h"

namespace kiln {

class Accelerator;
struct Scene;

struct LightSamplePilot {
    static constexpr int kLow = 1, kHigh = 8;  // the two counts the pilot renders
    static constexpr int kMaxChosen = 16;
    int chosen = 0;  // 0: no pilot ran (the plan's or the user's count stands)
    int pixels = 0, seeds = 0, samplesPerPixel = 0;
    // Relative variance of a pixel's samplesPerPixel-sample mean (the benchmark's relative MSE,
    // averaged over the pixels): the part more light samples divide, and the rest.
    double directVariance = 0, otherVariance = 0;
    // Cost of one camera sample in the units of lightSampleCostModel: fixed, and per light sample
    // per vertex.
    double baseCost = 0, lightCost = 0;
    double seconds = 0;            // the pilot's wall time (not part of the choice)
    std::string describe() const;  // the EXR header's kiln:light_samples_pilot
};

// Whether the job's light samples are the pilot's to choose: the path tracer with light sampling
// and MIS, no -l, and a plan that leaves the count open.
bool pilotChoosesLightSamples(IntegratorKind integrator, const PathOptions& path,
                              const RenderPlan& plan);

// Runs the pilot for the render's path options (their lightSamples is ignored) and settings: up
// to maxPixels pixels (a sixteenth of the image, at least 64) on an even grid over the whole
// image, each rendered at each of the two counts with spp samples of the render's sampler, `seeds`
// times with independent seeds (the spread of those means is the error a render has,
// stratification included).
LightSamplePilot pilotLightSamples(const Scene& scene, const Accelerator& accel,
                                   IntegratorKind integrator, const PathOptions& path,
                                   const RenderSettings& settings, const RenderPlan& plan,
                                   int maxPixels = 1024, int spp = 8, int seeds = 4);

}  // namespace kiln
