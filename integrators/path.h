// Path tracing with next-event estimation at every vertex, MIS against BSDF sampling, Russian
// roulette and CS184 depth semantics (-m 0: emission only, 1: direct lighting, >= 2: global
// illumination).
#pragma once

#include "integrators/bsdf.h"
#include "integrators/integrator.h"
#include "integrators/lights.h"
#include "integrators/render_plan.h"
#include "renderer/warp.h"

namespace kiln {

enum class DirectSampling { Hemisphere, Light, Mis };
enum class Roulette { Off, Throughput, Fixed };

struct PathOptions {
    int maxDepth = 5;
    int lightSamples = 1;  // -l: light samples per shading point
    DirectSampling sampling = DirectSampling::Mis;
    bool powerHeuristic = true;  // else balance
    Roulette roulette = Roulette::Throughput;
    float fixedContinuation = 0.65f;  // CS184's constant continuation probability (Roulette::Fixed)
    int rouletteMinBounces = 3;       // throughput roulette starts after this many bounces
    bool accumulateBounces = true;    // false: only light that bounced exactly maxDepth times
    MicrofacetModel microfacet = MicrofacetModel::Beckmann;
};

class PathIntegrator final : public Integrator {
  public:
    PathIntegrator(const Scene& scene, const Accelerator& accel, const PathOptions& options);
    using Integrator::Li;
    void Li(const Ray& ray, Sampler& sampler, RayCounter& counter,
            SampleRecord& record) const override;
    void Li(std::span<CameraSample> batch, RayCounter& counter) const override;
    const char* name() const override { return "path"; }
    const PathOptions& options() const { return opt_; }
    const LightSet& lights() const { return lights_; }
    // Chooses the path specialised for the plan (the general one until called, or with
    // plan.general).
    void usePlan(const RenderPlan& plan);

  private:
    template <bool DiffuseOnly, bool Infinite, bool DeltaLightsOnly, bool SplitLight>
    void trace(std::span<CameraSample> batch, RayCounter& counter) const;
    using TraceFn = void (PathIntegrator::*)(std::span<CameraSample>, RayCounter&) const;
    template <bool SplitLight>
    void addLight(SampleRecord& rec, int bounce, const Color& c, Lobe lobe) const;
    TraceFn trace_;
    float misWeight(float nf, float fPdf, float ng, float gPdf) const {
        return opt_.powerHeuristic ? powerHeuristic(nf, fPdf, ng, gPdf)
                                   : balanceHeuristic(nf, fPdf, ng, gPdf);
    }
    PathOptions opt_;
    LightSet lights_;
    bool eachDeltaLightOnce_ = false;  // only (a few) delta lights: NEE takes each once
};

}  // namespace kiln
