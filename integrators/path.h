// Path tracing with next-event estimation at every vertex, MIS against BSDF sampling, Russian
// roulette and CS184 depth semantics (-m 0: emission only, 1: direct lighting, >= 2: global
// illumination).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "integrators/bsdf.h"
#include "integrators/cs184_rules.h"
#include "integrators/guiding.h"
#include "integrators/integrator.h"
#include "integrators/lights.h"
#include "integrators/media.h"
#include "integrators/path_options.h"
#include "integrators/render_plan.h"
#include "renderer/core/warp.h"

namespace kiln {

// -l if given, else the render plan's default for the scene.
inline int resolvedLightSamples(const PathOptions& options, const RenderPlan& plan) {
    return options.lightSamples > 0 ? options.lightSamples : plan.defaultLightSamples;
}

struct SurfaceInteraction;

class PathIntegrator final : public Integrator {
    using TraceFn = void (PathIntegrator::*)(std::span<CameraSample>, RayCounter&) const;

  public:
    // The path specialised for the plan (plan.general: every feature on), recording plan.aovs.
    PathIntegrator(const Scene& scene, const Accelerator& accel, const PathOptions& options,
                   const RenderPlan& plan = generalPlan());
    using Integrator::Li;
    void Li(const Ray& ray, Sampler& sampler, RayCounter& counter,
            SampleRecord& record) const override;
    void Li(std::span<CameraSample> batch, RayCounter& counter) const override;
    const char* name() const override { return "path"; }
    const PathOptions& options() const { return opt_; }
    const LightSet& lights() const { return lights_; }

    // Traces photons [first, first + count) of the guide's training (seeded by seed) from the
    // area lights and emitting meshes, and appends a record where one lands on a Lambertian
    // surface after a glossy or specular bounce: the caustics cosine sampling rarely finds.
    void traceCausticPhotons(uint64_t first, size_t count, uint64_t seed,
                             std::vector<GuideRecord>& records) const;
    // Diffuse bounces from now on follow this field (nullptr: cosine sampling alone).
    void setGuide(std::shared_ptr<const GuideField> guide) { guide_ = std::move(guide); }
    const std::shared_ptr<const GuideField>& guide() const { return guide_; }

  private:
    // What the plan lets a specialisation leave out, as compile-time flags (pathFor).
    template <bool DiffuseOnly, bool Infinite, bool DeltaLightsOnly, bool SplitLight,
              bool Media = false>
    struct Features {
        static constexpr bool diffuseOnly = DiffuseOnly;          // every surface Lambert or black
        static constexpr bool infinite = Infinite;                // escaping rays look up lights
        static constexpr bool deltaLightsOnly = DeltaLightsOnly;  // no light a ray can hit
        static constexpr bool splitLight = SplitLight;            // light AOVs recorded
        static constexpr bool media = Media;  // media and subsurface walks (general otherwise)
    };
    struct PathState;  // path.cpp: what a path carries between vertices
    struct Scratch;    // path.cpp: a batch's queues
    struct Vertex;     // path.cpp: one path's surface vertex being shaded
    // A ray that left the scene: its unit direction and that direction's map coordinates.
    struct EscapedDirection {
        Vec3 dir;
        LatLong at;
    };

    static TraceFn pathFor(const RenderPlan& plan);
    // The wavefront over a batch, a bounce at a time, in named stages (path.cpp).
    template <class F>
    void trace(std::span<CameraSample> batch, RayCounter& counter) const;
    template <class F>
    void shadePath(std::span<CameraSample> batch, Scratch& w, size_t j, int bounce) const;
    // Media (path.cpp): the free flight of a ray in a medium and the index-matched boundaries it
    // passes; true when the path's vertex is done with (scattered, passed through, or ended).
    template <class F>
    bool crossMedium(std::span<CameraSample> batch, Scratch& w, size_t j, int bounce) const;
    // A principled vertex with subsurface > 0: its surface without the diffuse lobe, or a random
    // walk below it and the walk's exit vertex (path.cpp).
    template <class F>
    void shadeSubsurface(const Vertex& v, const SurfaceInputs& in, Scratch& w) const;
    // The medium a path is in after its vertex's BSDF sent the next ray through the surface.
    void followTransmission(Scratch& w, uint32_t path, const Hit& hit,
                            const SurfaceInteraction& si) const;
    // Light from the lights at infinity along a ray that left the scene; its unit direction and
    // that direction's coordinates found already (locateEscapes) or, null, found here.
    template <class F>
    void addEscaped(const PathState& st, SampleRecord& rec, const Ray& ray, int bounce,
                    const EscapedDirection* located) const;
    // The unit direction and map coordinates of every ray of the batch that left the scene, four
    // at a time (latLong4), and what their lookups will read asked for from memory.
    void locateEscapes(Scratch& w) const;
    template <class F>
    void addSurfaceEmission(const PathState& st, SampleRecord& rec, const Ray& ray, const Hit& hit,
                            const SurfaceInteraction& si, int bounce) const;
    template <class F>
    float emissionWeight(const PathState& st, int li, const Vec3& dir, const Vec3& x,
                         const Vec3& n) const;
    template <class F>
    std::optional<float> fixedEmissionWeight(const PathState& st, int li) const;
    float neeWeight(const PathState& st, int li, float lightPdf) const;
    SurfaceInputs surfaceInputs(PathState& st, const Material& mat, const Ray& ray, const Hit& hit,
                                SurfaceInteraction& si) const;
    template <class F, class B>
    void shadeVertex(const Vertex& v, const B& bsdf, Scratch& w) const;
    template <class F, class B>
    void sampleDirectLight(const Vertex& v, const B& bsdf, const Vec3& wo, bool lightOnly,
                           Scratch& w) const;
    // A light sample's numbers: the light, its selection probability, the point on it.
    struct LightDraw {
        size_t light;
        float pmf, u1, u2;
    };
    // Light samples a vertex draws at once (their cache misses overlap).
    static constexpr int kLightChunk = 8;
    struct DrawnAhead;  // path.cpp: a vertex's light samples drawn before it is shaded
    // A vertex's light samples, more than one, are split draws of the same pairs (Sampler::split:
    // stratified among themselves); one is drawn from the next dimensions, as any other number.
    std::optional<Sampler::Split> splitLights(Sampler& sampler) const;
    // Draws light samples k0 .. k0 + m - 1 of a vertex (split: from the vertex's split pairs;
    // else in the order a loop of single samples draws them), each table entry the light will
    // read asked for from memory.
    void drawLights(Sampler& sampler, std::optional<Sampler::Split> split, int k0, int m,
                    LightDraw* out) const {
        drawLights(sampler, split, k0, m, out, nullptr, nullptr);
    }
    // The same, each environment-map draw's row kept in rows[j] (rowPicked[j]) for locateAhead.
    void drawLights(Sampler& sampler, std::optional<Sampler::Split> split, int k0, int m,
                    LightDraw* out, EnvironmentSample* rows, bool* rowPicked) const;
    // The light samples of the vertex the path of ray k will shade, drawn now on a copy of its
    // sampler, so that their tables are in cache when it is shaded (sampleDirectLight takes them
    // if the sampler is still where they start).
    void drawAhead(std::span<CameraSample> batch, Scratch& w, size_t k, int bounce) const;
    void locateAhead(std::span<CameraSample> batch, Scratch& w, size_t k) const;
    template <class F, class B>
    void queueLightSample(const Vertex& v, const B& bsdf, const Vec3& wo, bool lightOnly,
                          const LightDraw& d, const LightSample& ls, Scratch& w) const;
    template <class B>
    void queueHemisphereProbes(const Vertex& v, const B& bsdf, const Vec3& wo, Scratch& w) const;
    template <class B>
    void continuePath(const Vertex& v, const B& bsdf, const Vec3& wo, Scratch& w) const;
    bool playRoulette(PathState& st, Sampler& sampler, int bounce) const;
    template <class F>
    void resolveShadowRays(std::span<CameraSample> batch, Scratch& w, RayCounter& counter) const;
    template <class F>
    void resolveProbes(std::span<CameraSample> batch, Scratch& w, RayCounter& counter) const;

    template <bool SplitLight>
    void addLight(SampleRecord& rec, int bounce, const Color& c, Lobe lobe) const;
    // Radiance an emitting surface sends back along ray; li: the light that samples it, or -1.
    Color emissionAt(const Ray& ray, const Hit& hit, const SurfaceInteraction& si, int& li) const;
    // What a -H hemisphere probe finds: emission where it hits, lights at infinity where not.
    template <bool Infinite>
    Color probeEmission(const Ray& ray, const Hit& hit) const;
    float misWeight(float nf, float fPdf, float ng, float gPdf) const {
        return opt_.heuristic == MisHeuristic::Power ? powerHeuristic(nf, fPdf, ng, gPdf)
                                                     : balanceHeuristic(nf, fPdf, ng, gPdf);
    }

    TraceFn trace_;  // chosen once, for the plan
    PathOptions opt_;
    LightSet lights_;
    Cs184Rules rules_;
    SceneMedia media_;
    // Next-event estimation: light sampling (mis, light) with lights to sample.
    bool useNee_ = false;
    bool lightOnlyAtLastVertex_ = false;  // a diffuse last vertex: NEE alone, no continuation
    int lightSamplesPerVertex_ = 1;       // the rules' count for -l and these lights
    bool drawAheadPays_ = false;          // drawAhead: only with an environment map
    // An environment map lights the scene: rays leaving it look it up (their coordinates found
    // four at a time, locateEscapes).
    bool mapEscapes_ = false;
    std::shared_ptr<const GuideField> guide_;
    std::vector<uint8_t> lambertian_;  // per material: shaded by the Lambert-only code
};

}  // namespace kiln
