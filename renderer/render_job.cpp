#include "renderer/render_job.h"

#include <tbb/info.h>

#include <chrono>
#include <string>
#include <utility>

#include "color/working_space.h"
#include "integrators/make_integrator.h"
#include "integrators/path.h"
#include "renderer/geometry/camera.h"
#include "renderer/guide_training.h"
#include "renderer/progress.h"

namespace kiln {
namespace {

// The path options with the camera's pixel spread for this image (texture footprints). Parallel
// rays spread by no angle: an orthographic view filters at the finest level.
PathOptions withPixelSpread(const Scene& scene, const RenderJobOptions& options) {
    PathOptions path = options.path;
    const RenderSettings& s = options.settings;
    CameraModel camera(scene.camera, s.width, s.height);
    path.pixelSpread = camera.orthographic()
                           ? 0.0f
                           : camera.vFovDeg() * kPi / 180.0f / float(std::max(1, s.height));
    return path;
}

// Every import warning (the list kiln info and stderr show), one per line: never only on a
// terminal nobody kept.
std::string joinedWarnings(const std::vector<std::string>& warnings) {
    std::string text;
    for (const std::string& w : warnings) text += (text.empty() ? "" : "\n") + w;
    return text;
}

// --guiding on or off, else the plan's choice; never with -H, whose probes stand for the bounce
// CS184 defines.
bool wantsGuide(const RenderJobOptions& o, const RenderPlan& plan) {
    if (o.integrator != IntegratorKind::Path || o.path.sampling == DirectSampling::Hemisphere)
        return false;
    return o.path.guiding == GuideMode::On || (o.path.guiding == GuideMode::Auto && plan.guiding);
}

}  // namespace

RenderJob::RenderJob(const Scene& scene, const Accelerator& accel, const RenderJobOptions& options)
    : scene_(scene),
      accel_(accel),
      options_(options),
      plan_(planFor(scene, accel, options.aovs, options.plan)),
      integrator_(
          makeIntegrator(options.integrator, scene, accel, withPixelSpread(scene, options), plan_)),
      filmScaleExponent_(kiln::filmScaleExponent(scene.brightestEmission())) {
    // The number the integrator uses, for the EXR header and checkpoint fingerprints.
    options_.path.lightSamples = resolvedLightSamples(options_.path, plan_);
    guided_ = wantsGuide(options_, plan_);
}

RenderJob::RenderJob(const RenderJob& job, const Accelerator& accel)
    : scene_(job.scene_),
      accel_(accel),
      options_(job.options_),
      plan_(job.plan_),
      integrator_(makeIntegrator(options_.integrator, scene_, accel,
                                 withPixelSpread(scene_, options_), plan_)),
      filmScaleExponent_(job.filmScaleExponent_),
      guided_(job.guided_) {
    // The same field, not a second training: the original's, this job's marked as trained.
    job.trainGuideOnce();
    guide_ = job.guide_;
    std::call_once(guideTrained_, [] {});
    if (guide_) static_cast<PathIntegrator&>(*integrator_).setGuide(guide_);
}

double RenderJob::trainGuideOnce() const {
    double seconds = 0;
    std::call_once(guideTrained_, [&] {
        if (!guided_) return;
        StageProgress stage("guide_training");
        auto start = std::chrono::steady_clock::now();
        auto& path = static_cast<PathIntegrator&>(*integrator_);
        guide_ = trainGuide(path, options_.settings);
        path.setGuide(guide_);
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        guideSeconds_ = uncountedTrainingSeconds_ = seconds;
    });
    return seconds;
}

std::string RenderJob::guidingText() const {
    if (!guided_) return "off";
    return guide_ ? GuideTraining::describe(*guide_) : "on";
}

Film RenderJob::makeFilm() const {
    const RenderSettings& s = options_.settings;
    Film film(s.filmWidth(), s.filmHeight(), options_.aovs);
    film.setRegion(s.filmOriginX(), s.filmOriginY(), s.width, s.height);
    film.setScaleExponent(filmScaleExponent_);
    return film;
}

RenderStats RenderJob::render(Film& film, const RenderControl& control) const {
    // The first render counts the training in its time, whatever traced first (the frame probe
    // of kiln render trains the guide before the render starts).
    trainGuideOnce();
    const double training = std::exchange(uncountedTrainingSeconds_, 0.0);
    RenderStats stats = renderImage(scene_, *integrator_, options_.settings, film, control);
    stats.seconds += training;
    return stats;
}

SampleRecord RenderJob::traceSample(int x, int y, int sample, RayCounter& counter) const {
    const PixelXY pixel{x, y};
    return traceSamples({&pixel, 1}, sample, 1, counter)[0];
}

std::vector<SampleRecord> RenderJob::traceSamples(std::span<const PixelXY> pixels, int first,
                                                  int count, RayCounter& counter) const {
    trainGuideOnce();
    return kiln::traceSamples(scene_, *integrator_, options_.settings, pixels, first, count,
                              counter);
}

Metadata RenderJob::metadata(const RenderStats& stats, const Film& film) const {
    const RenderSettings& s = options_.settings;
    const PathOptions& p = options_.path;
    CameraModel camera(scene_.camera, s.width, s.height);
    auto text = [](auto v) { return std::to_string(v); };
    Metadata meta{
        {"integrator", integrator_->name()},
        {"accelerator", accel_.stats().description},
        {"spp", text(s.spp)},
        {"sample_range", text(s.sampleStart) + " " + text(s.spp)},
        {"mean_spp", text(double(stats.samples) / (double(film.width()) * film.height()))},
        {"seed", text(s.seed)},
        {"sampler", toString(s.sampler)},
        {"resolution", text(s.width) + "x" + text(s.height)},
        {"render_seconds", text(stats.seconds)},
        {"hfov", text(camera.hFovDeg())},
        {"vfov", text(camera.vFovDeg())},
        {"interrupted", stats.interrupted ? "yes" : "no"},
        {"max_depth", text(p.maxDepth)},
        {"light_samples", text(p.lightSamples)},
        {"sampling", toString(p.sampling)},
        {"roulette", toString(p.roulette)},
        {"accumulate_bounces", p.accumulateBounces ? "yes" : "no"},
        {"adaptive", s.adaptiveText()},
        {"mis_heuristic", toString(p.heuristic)},
        {"microfacet", toString(p.microfacet)},
        {"guiding", guidingText()},
        {"camera", scene_.framedByCourseRule ? "cs184-framing"
                   : scene_.hasFileCamera    ? "file"
                                             : "default-framing"},
        {"threads", text(s.threads > 0 ? s.threads : tbb::info::default_concurrency())},
        {"rays", text(stats.rays)},
        {"working_space",
         workingSpace().rec709
             ? std::string("lin_rec709 (linear Rec.709 primaries, D65)")
             : workingSpace().name + " (scene_linear; file colours converted from linear Rec.709)"},
        {"plan", plan_.compact()},
        {"plan_decisions", plan_.text()},
        {"nonfinite_samples", text(stats.nonFiniteSamples)},
        {"warning_count", text(scene_.warnings.size())}};
    if (!scene_.warnings.empty()) meta["warnings"] = joinedWarnings(scene_.warnings);
    if (camera.orthographic())
        meta["orthographic_half_size"] =
            text(camera.orthoHalfWidth()) + " " + text(camera.orthoHalfHeight());
    return meta;
}

}  // namespace kiln
