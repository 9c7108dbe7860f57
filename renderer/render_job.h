// One render, set up in one place: the plan for the scene, the integrator built complete for it,
// the film for the render region, the tile loop, and the metadata naming every option. kiln render,
// --traversal-floor, the benchmarks and the tests all render through it, so a benchmark times
// exactly what kiln render runs.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include "color/image_output.h"
#include "integrators/path_options.h"
#include "integrators/render_plan.h"
#include "renderer/render_loop.h"

namespace kiln {

class GuideField;

struct RenderJobOptions {
    IntegratorKind integrator = IntegratorKind::Path;
    PathOptions path;
    AovRequest aovs = AovRequest::defaults();  // what kiln render writes without --aov
    PlanMode plan = PlanMode::Auto;
    RenderSettings settings;  // size, region, spp, seed, threads, adaptive sampling
};

class RenderJob {
  public:
    // Analyses the scene and builds the integrator; accel must outlive the job.
    RenderJob(const Scene& scene, const Accelerator& accel, const RenderJobOptions& options);
    // The same job (scene, options, plan: no new analysis) traced through another accelerator,
    // e.g. one that records every ray.
    RenderJob(const RenderJob& job, const Accelerator& accel);

    const RenderJobOptions& options() const { return options_; }
    const Scene& scene() const { return scene_; }
    const RenderPlan& plan() const { return plan_; }
    const Integrator& integrator() const { return *integrator_; }
    int filmScaleExponent() const { return filmScaleExponent_; }
    // Whether diffuse bounces follow a guide field (--guiding, else the plan). The field is
    // trained by the first render or traced sample, so a job refused for its inputs (a foreign
    // checkpoint, say) costs no training. The checkpoint fingerprint takes guided() alone: the
    // training follows from the rest of it.
    bool guided() const { return guided_; }
    // "off", or what the training found (the EXR header); its seconds count in the render's.
    std::string guidingText() const;
    double guideTrainingSeconds() const { return guideSeconds_; }

    // A film of the render region's size, placed in the full image.
    Film makeFilm() const;
    // Renders into film (made by makeFilm, or partly filled by an earlier render of this job, e.g.
    // read back from a checkpoint: each pixel continues at its next sample).
    RenderStats render(Film& film, const RenderControl& control = {}) const;
    // One camera sample exactly as the render traces it (for --pixel/--sample debugging).
    SampleRecord traceSample(int x, int y, int sample, RayCounter& counter) const;
    // Samples [first, first + count) of each pixel as one batch (render_loop.h's traceSamples).
    std::vector<SampleRecord> traceSamples(std::span<const PixelXY> pixels, int first, int count,
                                           RayCounter& counter) const;
    // The job's options and results by name (the EXR header's kiln: attributes).
    Metadata metadata(const RenderStats& stats, const Film& film) const;

  private:
    const Scene& scene_;
    const Accelerator& accel_;
    RenderJobOptions options_;
    RenderPlan plan_;
    std::unique_ptr<Integrator> integrator_;
    int filmScaleExponent_;  // from the scene's brightest emitter (fixed_sum.h)
    // Trains the guide field if this job is guided and has none yet: the seconds this call took.
    double trainGuideOnce() const;
    bool guided_ = false;
    mutable std::once_flag guideTrained_;
    mutable std::shared_ptr<const GuideField> guide_;
    mutable double guideSeconds_ = 0;
    mutable double uncountedTrainingSeconds_ = 0;  // training no render has counted yet
};

}  // namespace kiln
