#include "integrators/path.h"

#include <algorithm>
#include <array>
#include <optional>
#include <type_traits>
#include <utility>

#include "integrators/subsurface.h"
#include "renderer/geometry/interaction.h"
#include "renderer/geometry/material_lookup.h"
#include "renderer/geometry/normal_map.h"
#include "scene/material_kinds.h"

namespace kiln {

PathIntegrator::PathIntegrator(const Scene& scene, const Accelerator& accel,
                               const PathOptions& options, const RenderPlan& plan)
    : Integrator(scene, accel, plan.aovs, options.pixelSpread),
      trace_(pathFor(plan)),
      opt_(options),
      lights_(scene, {.misWithBsdf = options.sampling == DirectSampling::Mis}),
      media_(scene) {
    // An integrator built without analysis (the general plan) still sees a scene's media.
    if (plan.general && (sceneHasMedia(scene) || sceneHasSubsurface(scene)))
        trace_ = &PathIntegrator::trace<Features<false, true, false, true, true>>;
    for (const Material& m : scene.materials) lambertian_.push_back(specOf(m.kind).lambertian);
    opt_.lightSamples = resolvedLightSamples(options, plan);
    mapEscapes_ = plan.environmentMap;
    rules_ = Cs184Rules(options, lights_.size(), lights_.allDelta());
    lightSamplesPerVertex_ = rules_.lightSamplesPerVertex(opt_.lightSamples, lights_.size());
    // Drawing a vertex's light samples a few paths ahead pays only where the draw reads tables too
    // large for the cache (an environment map's); elsewhere it is copies of the sampler.
    drawAheadPays_ = plan.environmentMap;
    // Without next-event estimation (hemisphere, bsdf) emission found by the path counts in full.
    useNee_ = !rules_.hemisphere && options.sampling != DirectSampling::Bsdf && lights_.size() > 0;
    // Only where light sampling sees every emitter and MIS would otherwise weigh what the last
    // continuation finds (not with -H probes or BSDF-only direct light), and sees all of its light
    // (not a compensated map's, whose light below the cut only BSDF sampling finds).
    lightOnlyAtLastVertex_ =
        lights_.size() > 0 && lights_.everyEmitterSampled() && !lights_.anyCompensated() &&
        (options.sampling == DirectSampling::Mis || options.sampling == DirectSampling::Light);
}

PathIntegrator::TraceFn PathIntegrator::pathFor(const RenderPlan& plan) {
    // Media and subsurface walks: one specialisation, every other feature on.
    if (plan.media || plan.subsurface)
        return &PathIntegrator::trace<Features<false, true, false, true, true>>;
    if (plan.general) return &PathIntegrator::trace<Features<false, true, false, true>>;
    bool diffuse = plan.diffuseOnly, infinite = plan.infiniteLights;
    bool deltaOnly = plan.deltaLightsOnly && !plan.emitters && !plan.infiniteLights;
    bool split = plan.aovs.splitsLight();
    // Chosen once per render: each combination is its own instantiation.
    static constexpr TraceFn kTable[2][2][2][2] = {
        {{{&PathIntegrator::trace<Features<false, false, false, false>>,
           &PathIntegrator::trace<Features<false, false, false, true>>},
          {&PathIntegrator::trace<Features<false, false, true, false>>,
           &PathIntegrator::trace<Features<false, false, true, true>>}},
         {{&PathIntegrator::trace<Features<false, true, false, false>>,
           &PathIntegrator::trace<Features<false, true, false, true>>},
          {&PathIntegrator::trace<Features<false, true, true, false>>,
           &PathIntegrator::trace<Features<false, true, true, true>>}}},
        {{{&PathIntegrator::trace<Features<true, false, false, false>>,
           &PathIntegrator::trace<Features<true, false, false, true>>},
          {&PathIntegrator::trace<Features<true, false, true, false>>,
           &PathIntegrator::trace<Features<true, false, true, true>>}},
         {{&PathIntegrator::trace<Features<true, true, false, false>>,
           &PathIntegrator::trace<Features<true, true, false, true>>},
          {&PathIntegrator::trace<Features<true, true, true, false>>,
           &PathIntegrator::trace<Features<true, true, true, true>>}}}};
    return kTable[diffuse][infinite][deltaOnly][split];
}

void PathIntegrator::Li(const Ray& ray, Sampler& sampler, RayCounter& counter,
                        SampleRecord& record) const {
    // A batch of one: the same code, so a replayed sample is the sample the render traced.
    CameraSample one{ray, sampler, record};
    (this->*trace_)(std::span<CameraSample>(&one, 1), counter);
    sampler = one.sampler;
    record = one.record;
}

void PathIntegrator::Li(std::span<CameraSample> batch, RayCounter& counter) const {
    (this->*trace_)(batch, counter);
}

namespace {

// The lobe AOVs split by material: a principled surface counts as diffuse unless fully metallic.
Lobe lobeOf(const Material& m, bool transmission) {
    if (transmission) return Lobe::Transmission;
    const MaterialKindSpec& k = specOf(m.kind);
    return k.countsAsDiffuse && k.countsAsDiffuse(m) ? Lobe::Diffuse : Lobe::Specular;
}

// A Lambertian vertex at x whose bounce draws kGuideFraction of its directions from the guide
// field's leaf (guiding.h) and the rest by cosine: the same reflectance, the mixture's density for
// the throughput. MIS against light sampling weighs by the cosine density alone, on both sides
// (pdf() and BsdfSample::misPdf): any one function used on both sides keeps the weights summing to
// one, and the guide aims at glossy surfaces, not at lights, so its density towards a light is
// nearly always zero and not worth a sum over the leaf's cones per light sample.
class GuidedLambert {
  public:
    GuidedLambert(const LambertBsdf& lambert, const GuideLeaf& leaf, const Vec3& x,
                  const Frame& frame)
        : lambert_(lambert), leaf_(leaf), x_(x), frame_(frame) {}
    bool isDelta() const { return false; }
    bool isBlack() const { return lambert_.isBlack(); }
    bool isDiffuse() const { return true; }
    bool hasTransmission() const { return false; }
    Color eval(const Vec3& wo, const Vec3& wi) const { return lambert_.eval(wo, wi); }
    float pdf(const Vec3& wo, const Vec3& wi) const { return lambert_.pdf(wo, wi); }
    bool usesLobeChoice() const { return true; }
    bool sample(const Vec3& wo, float uc, float u1, float u2, BsdfSample& out) const {
        if (uc >= kGuideFraction) {
            if (!lambert_.sample(wo, uc, u1, u2, out)) return false;
            out.misPdf = out.pdf;
            out.pdf = mixture(out.pdf, leaf_.pdf(x_, frame_.toWorld(out.wi)));
            return true;
        }
        if (wo.z == 0) return false;
        float guidePdf;
        // uc, rescaled to [0, 1), picks the cone.
        Vec3 wi = frame_.toLocal(leaf_.sample(x_, uc / kGuideFraction, u1, u2, guidePdf));
        if (wi.z * wo.z <= 0) return false;  // below the surface: the sample reflects nothing
        out = BsdfSample{};
        out.wi = wi;
        out.f = lambert_.eval(wo, wi);
        out.misPdf = lambert_.pdf(wo, wi);
        out.pdf = mixture(out.misPdf, guidePdf);
        return out.pdf > 0;
    }

  private:
    static float mixture(float cosinePdf, float guidePdf) {
        return (1 - kGuideFraction) * cosinePdf + kGuideFraction * guidePdf;
    }
    const LambertBsdf& lambert_;
    const GuideLeaf& leaf_;
    const Vec3& x_;
    const Frame& frame_;
};

}  // namespace

// Light that bounced `bounce` times; with accumulation off only the maxDepth-th bounce is kept.
// Every contribution lands in exactly one of emission / direct / indirect, so they sum to the
// beauty.
template <bool SplitLight>
void PathIntegrator::addLight(SampleRecord& rec, int bounce, const Color& c, Lobe lobe) const {
    if (!rules_.keeps(bounce)) return;
    rec.L += c;
    if constexpr (!SplitLight) return;
    if (!aovs_.splitsLight()) return;
    if (bounce == 0)
        rec.emission += c;
    else if (bounce == 1)
        rec.direct += c;
    else
        rec.indirect += c;
    if (bounce >= 1) rec.lobes[bounce == 1 ? 0 : 1][int(lobe)] += c;
    if (bounce >= 1 && bounce <= aovs_.bounceLayers) rec.bounces[bounce - 1] += c;
}

Color PathIntegrator::emissionAt(const Ray& ray, const Hit& hit, const SurfaceInteraction& si,
                                 int& li) const {
    li = (hit.shape != kSphereShape && hit.instance == kInvalidId) ? lights_.lightOfMesh(hit.shape)
                                                                   : -1;
    const Material& m = scene_.materials[si.material];
    Color Le = li >= 0 ? lights_.emitted(size_t(li), si.p, si.ng, ray.origin) : m.emission;
    if (m.maps.emissionTexture >= 0 && hit.shape != kSphereShape)
        Le = Le * emissionTexelAt(scene_, m, MeshPoint::of(hit));
    return Le;
}

template <bool Infinite>
Color PathIntegrator::probeEmission(const Ray& ray, const Hit& hit) const {
    Color Le(0.0f);
    if (!hit.valid()) {
        if constexpr (Infinite)
            for (size_t i : lights_.infiniteLights())
                Le += lights_.escaped(i, normalize(ray.dir), false);
        return Le;
    }
    SurfaceInteraction si = makeInteraction(scene_, ray, hit);
    if (maxComponent(scene_.materials[si.material].emission) <= 0) return Le;
    int li = -1;
    return emissionAt(ray, hit, si, li);
}

// What a path carries from one vertex to the next (its next ray waits in Scratch::nextRays).
struct PathIntegrator::PathState {
    Color beta{1.0f};
    bool specular = true;  // the previous vertex was the camera or a delta lobe: nothing else could
                           // see the light
    float prevPdf = 0;
    Vec3 prevP;
    Lobe firstLobe = Lobe::Diffuse;  // how the path left its first vertex (for the lobe AOVs)
    float travelled = 0;             // path length so far: the texture footprint grows with it
    int medium = -1;                 // the medium the path is in (SceneMedia), -1 none
    int crossings = 0;               // index-matched boundaries passed: they are no bounce
};

namespace {

// A next-event estimate waiting for its shadow ray: added to its path's record if unoccluded.
struct PendingLight {
    uint32_t path;
    int bounce;
    Lobe lobe;
    Color contribution;
};

}  // namespace

// A vertex's light samples drawn ahead (drawAhead): valid while its path's sampler is at
// `dimension` (dimensions only grow, so no later vertex of the path matches).
struct PathIntegrator::DrawnAhead {
    static constexpr uint32_t kNone = ~0u;
    uint32_t dimension = kNone;
    Sampler after{0, 0, 0};  // the sampler past the draws
    std::optional<Sampler::Split> split;
    std::array<LightDraw, kLightChunk> draws;
    // Environment-light draws located (locateAhead): the point, its density and texel addresses
    // (asked for from memory); the radiance is read at shading.
    bool locatedAll = false;
    std::array<bool, kLightChunk> located;
    // Drawn: an environment map's row picked (points[j] holds it until locateAhead finishes it).
    std::array<bool, kLightChunk> rowPicked;
    std::array<EnvironmentSample, kLightChunk> points;
};

// Scratch reused by every batch a thread traces.
struct PathIntegrator::Scratch {
    std::vector<PathState> paths;
    std::vector<uint32_t> active, next;  // live paths, and their rays in the same order
    std::vector<Ray> rays, nextRays, shadowRays;
    std::vector<Hit> hits;
    std::vector<PendingLight> pending;
    std::vector<int> shadowMedia;  // with media: the medium each shadow ray starts in
    uint64_t walkRays = 0;         // rays traced by subsurface walks
    std::vector<uint8_t> occluded;
    // -H: hemisphere probes (closest-hit rays whose emission is the direct light), their
    // throughput waiting in PendingLight::contribution.
    std::vector<Ray> probeRays;
    std::vector<Hit> probeHits;
    std::vector<PendingLight> probes;
    std::vector<DrawnAhead> ahead;  // per path
    std::vector<uint32_t> escapes;  // rays that left the scene (locateEscapes)
    // Per ray that left: its unit direction and that direction's coordinates, found once for
    // the lookup and the weight (addEscaped).
    std::vector<EscapedDirection> escaped;
};

// A surface vertex of one path, as its stages see it.
struct PathIntegrator::Vertex {
    uint32_t path;
    int bounce;
    PathState& st;
    Sampler& sampler;
    const SurfaceInteraction& si;
    const Material& mat;
    Vec3 woWorld;
    Frame frame;
    // Set where the vertex is not the material's surface: a subsurface walk's exit, a scattering
    // point in a medium (their light goes to the subsurface and volume AOVs).
    std::optional<Lobe> kind = std::nullopt;
    // The lobe the light gathered here is recorded under.
    Lobe lobe(bool transmission = false) const {
        if (bounce != 0) return st.firstLobe;
        return kind ? *kind : lobeOf(mat, transmission);
    }
};

// Wavefront over a batch: every live path's next ray is traced together (Embree packets), then
// every path is shaded, its next-event shadow rays queued; the queue is traced together and the
// unoccluded estimates added. Each path still draws its random numbers and adds its light in the
// same order as a path traced alone, so the image does not depend on how samples are batched.
template <class F>
void PathIntegrator::trace(std::span<CameraSample> batch, RayCounter& counter) const {
    thread_local Scratch scratch;
    Scratch& w = scratch;
    w.paths.assign(batch.size(), PathState{});
    w.ahead.resize(batch.size());
    for (DrawnAhead& a : w.ahead) a.dimension = DrawnAhead::kNone;
    size_t perVertex = size_t(lightSamplesPerVertex_);
    w.pending.reserve(batch.size() * perVertex);
    w.shadowRays.reserve(batch.size() * perVertex);
    w.active.clear();
    w.rays.clear();
    for (uint32_t i = 0; i < batch.size(); ++i) {
        w.paths[i].prevP = batch[i].ray.origin;
        w.active.push_back(i);
        w.rays.push_back(batch[i].ray);
    }
    for (int bounce = 0; !w.active.empty(); ++bounce) {
        w.hits.resize(w.rays.size());
        // Camera rays are coherent and go as packets; after a bounce, rays scatter and Embree's
        // single-ray traversal is faster (measured: packets of diffuse bounce rays took 1.5-1.8x as
        // long per ray). Shadow rays, below, gain from packets either way.
        if (bounce == 0) {
            accel_.intersect(std::span<const Ray>(w.rays), std::span<Hit>(w.hits));
        } else {
            for (size_t j = 0; j < w.rays.size(); ++j) {
                w.hits[j] = Hit{};
                accel_.intersect(w.rays[j], w.hits[j]);
            }
        }
        counter.rays += w.rays.size();
        if constexpr (F::infinite && !F::media)
            if (mapEscapes_) locateEscapes(w);
        w.next.clear();
        w.nextRays.clear();
        w.pending.clear();
        w.shadowRays.clear();
        w.shadowMedia.clear();
        w.probes.clear();
        w.probeRays.clear();

        // Mesh data of hits a few ahead requested from memory while this one is shaded.
        constexpr size_t kIndicesAhead = 16, kVerticesAhead = 8, kLightsAhead = 4, kLocateAhead = 2;
        for (size_t j = 0; j < std::min(kIndicesAhead, w.hits.size()); ++j)
            prefetchHitIndices(scene_, w.hits[j]);
        if constexpr (!F::media)
            for (size_t j = 0; j < std::min(kLightsAhead, w.hits.size()); ++j)
                drawAhead(batch, w, j, bounce);
        for (size_t j = 0; j < w.active.size(); ++j) {
            if (j + kIndicesAhead < w.hits.size())
                prefetchHitIndices(scene_, w.hits[j + kIndicesAhead]);
            if (j + kVerticesAhead < w.hits.size())
                prefetchHitVertices(scene_, w.hits[j + kVerticesAhead]);
            if constexpr (!F::media)
                if (j + kLightsAhead < w.hits.size()) drawAhead(batch, w, j + kLightsAhead, bounce);
            // Only an environment map has samples to locate (F::infinite: a light at infinity).
            if constexpr (!F::media && F::infinite)
                if (j + kLocateAhead < w.hits.size()) locateAhead(batch, w, j + kLocateAhead);
            // With media, the boundaries a path passed through are no bounce of its.
            shadePath<F>(batch, w, j, F::media ? bounce - w.paths[w.active[j]].crossings : bounce);
        }
        if constexpr (F::media) counter.rays += std::exchange(w.walkRays, 0);
        resolveShadowRays<F>(batch, w, counter);
        resolveProbes<F>(batch, w, counter);
        w.active.swap(w.next);
        w.rays.swap(w.nextRays);
    }
}

// One path at one bounce: light from where its ray went, then its vertex's BSDF (a Lambertian
// surface takes the Lambert-only code in every scene: the general BSDF's dispatch slowed the walls
// of a box holding one metal object by a third).
template <class F>
void PathIntegrator::shadePath(std::span<CameraSample> batch, Scratch& w, size_t j,
                               int bounce) const {
    const uint32_t pi = w.active[j];
    PathState& st = w.paths[pi];
    SampleRecord& rec = batch[pi].record;
    const Ray& ray = w.rays[j];
    const Hit& hit = w.hits[j];
    if constexpr (F::media)
        if (crossMedium<F>(batch, w, j, bounce)) return;
    if (!hit.valid()) {
        const bool located = F::infinite && !F::media && mapEscapes_;
        addEscaped<F>(st, rec, ray, bounce, located ? &w.escaped[j] : nullptr);
        return;
    }
    SurfaceInteraction si = makeInteraction(scene_, ray, hit);
    const Material& mat = scene_.materials[si.material];
    if (bounce == 0) recordSurface(ray, hit, si, rec);
    if (maxComponent(mat.emission) > 0) addSurfaceEmission<F>(st, rec, ray, hit, si, bounce);
    if (bounce >= opt_.maxDepth) return;
    SurfaceInputs in = surfaceInputs(st, mat, ray, hit, si);
    const Vec3 woWorld = -normalize(ray.dir);
    const Vertex v{pi, bounce, st, batch[pi].sampler, si, mat, woWorld, shadingFrame(si, woWorld)};
    const bool lambertian = lambertian_[si.material];
    if constexpr (F::media)
        if (mat.kind == MaterialKind::Principled && mat.subsurface > 0) {
            shadeSubsurface<F>(v, in, w);
            return;
        }
    if (!F::diffuseOnly && !lambertian) {
        shadeVertex<F>(v, Bsdf(mat, opt_.microfacet, in), w);
        if constexpr (F::media) followTransmission(w, pi, hit, si);
        return;
    }
    LambertBsdf lambert(in.baseColour, !lambertian);
    // Guided where the bounce is traced (not at a light-only last vertex).
    const bool bounces = !(lightOnlyAtLastVertex_ && bounce + 1 == opt_.maxDepth);
    const GuideLeaf* leaf = guide_ && bounces ? guide_->leafAt(v.si.p) : nullptr;
    if (leaf)
        shadeVertex<F>(v, GuidedLambert(lambert, *leaf, v.si.p, v.frame), w);
    else
        shadeVertex<F>(v, lambert, w);
}

// A path's ray in a medium: a free flight, which may end in a scattering vertex; then an index-
// matched boundary at its end is passed straight through into the medium beyond it.
template <class F>
bool PathIntegrator::crossMedium(std::span<CameraSample> batch, Scratch& w, size_t j,
                                 int bounce) const {
    const uint32_t pi = w.active[j];
    PathState& st = w.paths[pi];
    const Ray& ray = w.rays[j];
    const Hit& hit = w.hits[j];
    Sampler& sampler = batch[pi].sampler;
    if (st.medium >= 0) {
        const HomogeneousMedium& m = media_.medium(st.medium);
        const float len = length(ray.dir);
        const float uChannel = sampler.next1D(), uDistance = sampler.next1D();
        FreeFlight flight =
            m.sample(hit.valid() ? hit.t * len : kInfinity, st.beta, uChannel, uDistance);
        st.beta *= flight.weight;
        if (!isFinite(st.beta) || maxComponent(st.beta) <= 0) return true;
        if (flight.scattered) {
            if (bounce >= opt_.maxDepth) return true;
            const Vec3 woWorld = -(ray.dir / len);
            const SurfaceInteraction si =
                surfacePoint(ray.origin + ray.dir * (flight.t / len), Vec3(0.0f), woWorld);
            static const Material kScatterer{};
            // The phase function takes the BSDF's place in the vertex's stages.
            shadeVertex<F>(Vertex{pi, bounce, st, sampler, si, kScatterer, woWorld, Frame(woWorld),
                                  Lobe::Volume},
                           PhaseAsBsdf(m.g()), w);
            return true;
        }
    }
    if (!hit.valid() || media_.interiorOf(hit) < 0) return false;
    const SurfaceInteraction si = makeInteraction(scene_, ray, hit);
    if (!media_.indexMatched(hit, si.material)) return false;
    // A ray trapped between boundaries (a mesh that is not closed) ends.
    constexpr int kMaxCrossings = 256;
    if (++st.crossings > kMaxCrossings) return true;
    st.medium = media_.beyond(hit, si.frontFace);
    w.next.push_back(pi);
    w.nextRays.push_back(spawnRay(si, ray.dir));
    return true;
}

// Blender 4's subsurface weight blends the diffuse lobe into a random walk: with that probability
// the vertex is its surface without the diffuse lobe plus the walk (chosen by the light that
// passes the specular layer, at most kMaxEntryChoice), else the principled surface as it is.
template <class F>
void PathIntegrator::shadeSubsurface(const Vertex& v, const SurfaceInputs& in, Scratch& w) const {
    PrincipledBsdf surface(v.mat, in);
    if (v.sampler.next1D() >= v.mat.subsurface) {
        shadeVertex<F>(v, surface, w);
        return;
    }
    surface.dropDiffuse();
    // The specular layer keeps some chance: a walk for every path would leave it unsampled.
    constexpr float kMaxEntryChoice = 0.9f;
    const float enter = surface.enteringFraction(std::abs(v.frame.toLocal(v.woWorld).z));
    const float pEnter = std::min(enter, kMaxEntryChoice);
    if (v.sampler.next1D() >= pEnter) {
        v.st.beta = v.st.beta / (1 - pEnter);
        shadeVertex<F>(v, surface, w);
        return;
    }
    v.st.beta = v.st.beta * (enter / pEnter);
    const WalkMedium walk =
        walkMedium(in.baseColour, v.mat.subsurfaceRadius * v.mat.subsurfaceScale);
    WalkExit exit;
    if (!randomWalk(scene_, accel_, v.si, walk, v.st.beta, v.sampler, exit, w.walkRays)) return;
    v.st.beta *= exit.weight;
    if (!isFinite(v.st.beta) || maxComponent(v.st.beta) <= 0) return;
    // The exit point is a white Lambertian surface facing out, at the same depth as the entry.
    const Vertex out{v.path,     v.bounce,          v.st,
                     v.sampler,  exit.si,           v.mat,
                     exit.si.ng, Frame(exit.si.ng), Lobe::Subsurface};
    shadeVertex<F>(out, LambertBsdf(Color(1.0f), false), w);
}

void PathIntegrator::followTransmission(Scratch& w, uint32_t path, const Hit& hit,
                                        const SurfaceInteraction& si) const {
    if (w.next.empty() || w.next.back() != path) return;  // the path ended here
    if (dot(w.nextRays.back().dir, si.ng) >= 0) return;   // reflected: the same medium
    w.paths[path].medium = media_.beyond(hit, si.frontFace);
}

// A ray that left the scene: the lights at infinity it sees.
template <class F>
void PathIntegrator::addEscaped(const PathState& st, SampleRecord& rec, const Ray& ray, int bounce,
                                const EscapedDirection* located) const {
    if constexpr (F::infinite) {
        const Vec3 dir = located ? located->dir : normalize(ray.dir);
        const LatLong* dirLatLong = located ? &located->at : nullptr;
        for (size_t i : lights_.infiniteLights()) {
            // The light's density for MIS comes with its radiance where the weight needs it.
            const std::optional<float> fixed = fixedEmissionWeight<F>(st, int(i));
            float pdf = 0;
            const bool camera = bounce == 0;
            Color Le = dirLatLong ? lights_.escaped(i, st.prevP, dir, *dirLatLong, camera,
                                                    fixed ? nullptr : &pdf)
                       : fixed    ? lights_.escaped(i, dir, camera)
                                  : lights_.escaped(i, st.prevP, dir, camera, pdf);
            if (maxComponent(Le) > 0)
                addLight<F::splitLight>(
                    rec, bounce, st.beta * Le * (fixed ? *fixed : neeWeight(st, int(i), pdf)),
                    st.firstLobe);
        }
    }
}

// Each ray's unit direction (addEscaped takes it from here) and its coordinates, those it would
// find alone (latLong is lane 0 of latLong4); its map texels and density entry asked for.
void PathIntegrator::locateEscapes(Scratch& w) const {
    w.escapes.clear();
    for (size_t j = 0; j < w.hits.size(); ++j)
        if (!w.hits[j].valid()) w.escapes.push_back(uint32_t(j));
    w.escaped.resize(w.rays.size());
    const size_t n = w.escapes.size();
    for (size_t k = 0; k < n; k += 4) {
        Vec3 unit[4];
        const Vec3* dirs[4];
        for (size_t l = 0; l < 4; ++l) {
            unit[l] = normalize(w.rays[w.escapes[std::min(k + l, n - 1)]].dir);
            dirs[l] = &unit[l];
        }
        LatLong found[4];
        latLong4(dirs, found);
        for (size_t l = 0; l < 4 && k + l < n; ++l) {
            w.escaped[w.escapes[k + l]] = {unit[l], found[l]};
            for (size_t i : lights_.infiniteLights()) lights_.prefetchEscape(i, found[l]);
        }
    }
}

// An emitting surface the path found, weighed against next-event estimation having sampled it.
template <class F>
void PathIntegrator::addSurfaceEmission(const PathState& st, SampleRecord& rec, const Ray& ray,
                                        const Hit& hit, const SurfaceInteraction& si,
                                        int bounce) const {
    int li = -1;
    Color Le = emissionAt(ray, hit, si, li);
    if (!rules_.emitterLights(li, bounce)) Le = Color(0.0f);
    addLight<F::splitLight>(
        rec, bounce, st.beta * Le * emissionWeight<F>(st, li, normalize(ray.dir), si.p, si.ng),
        st.firstLobe);
}

// Weight of emission found by following the BSDF-sampled ray, against NEE having sampled light li.
template <class F>
float PathIntegrator::emissionWeight(const PathState& st, int li, const Vec3& dir, const Vec3& x,
                                     const Vec3& n) const {
    if (const std::optional<float> fixed = fixedEmissionWeight<F>(st, li)) return *fixed;
    return neeWeight(st, li, lights_.pdf(size_t(li), st.prevP, dir, x, n));
}

// The weight where it does not depend on light li's density (none where it does).
template <class F>
std::optional<float> PathIntegrator::fixedEmissionWeight(const PathState& st, int li) const {
    if constexpr (F::deltaLightsOnly) return 1.0f;  // no light can be hit: emission is unweighted
    if (rules_.hemisphere && !st.specular) return 0.0f;  // the probes counted it
    if (st.specular || li < 0 || !useNee_) return 1.0f;
    if (opt_.sampling == DirectSampling::Light) return 0.0f;
    return std::nullopt;
}

// MIS weight of emission the BSDF-sampled ray found, light li's density towards it being lightPdf.
float PathIntegrator::neeWeight(const PathState& st, int li, float lightPdf) const {
    float pl = lights_.selectPmf(size_t(li)) * lightPdf;
    return misWeight(1, st.prevPdf, float(opt_.lightSamples), pl);
}

// The material at the vertex: textures and vertex colours looked up with the footprint the path
// has grown to, the normal map applied.
SurfaceInputs PathIntegrator::surfaceInputs(PathState& st, const Material& mat, const Ray& ray,
                                            const Hit& hit, SurfaceInteraction& si) const {
    if (!colourVaries_) return SurfaceInputs::of(mat);
    st.travelled += hit.t * length(ray.dir);
    const float footprint = st.travelled * opt_.pixelSpread;
    SurfaceInputs in = surfaceInputsAt(scene_, mat, hit, footprint);
    applyNormalMap(scene_, mat, hit, -normalize(ray.dir), footprint, si);
    return in;
}

// The vertex's stages in order: direct light (light sampling, or -H probes), then the
// continuation by BSDF sampling and roulette.
template <class F, class B>
void PathIntegrator::shadeVertex(const Vertex& v, const B& bsdf, Scratch& w) const {
    if (bsdf.isBlack()) return;
    const Vec3 wo = v.frame.toLocal(v.woWorld);
    // A diffuse last vertex takes its direct light from light sampling alone: its continuation
    // could only find emission, which MIS weighs low on a diffuse surface.
    const bool lightOnly =
        lightOnlyAtLastVertex_ && v.bounce + 1 == opt_.maxDepth && bsdf.isDiffuse();
    const bool gathers = !bsdf.isDelta() && rules_.gathersAt(v.bounce);
    if (useNee_ && gathers) sampleDirectLight<F>(v, bsdf, wo, lightOnly, w);
    if (rules_.hemisphere && gathers) queueHemisphereProbes(v, bsdf, wo, w);
    // With only delta lights and no emitters, a ray after the last bounce could find nothing.
    if constexpr (F::deltaLightsOnly)
        if (v.bounce + 1 >= opt_.maxDepth) return;
    if (lightOnly) return;
    continuePath(v, bsdf, wo, w);
}

// Next-event estimation, shadow rays queued: -l lights chosen by power, or each delta light once.
template <class F, class B>
void PathIntegrator::sampleDirectLight(const Vertex& v, const B& bsdf, const Vec3& wo,
                                       bool lightOnly, Scratch& w) const {
    const int samples = lightSamplesPerVertex_;
    if (!drawAheadPays_) {  // no tables to overlap: a sample at a time, no chunk's arrays to fill
        const std::optional<Sampler::Split> split = splitLights(v.sampler);
        for (int k = 0; k < samples; ++k) {
            LightDraw d;
            drawLights(v.sampler, split, k, 1, &d);
            LightSample ls;
            if (lights_.sample(d.light, v.si.p, d.u1, d.u2, ls) && d.pmf != 0)
                queueLightSample<F>(v, bsdf, wo, lightOnly, d, ls, w);
        }
        return;
    }
    // In chunks: every sample's numbers drawn (in the order a loop of single samples draws them)
    // and its first table entry asked for, then the lights sampled, then the estimates queued, so
    // the cache misses of an environment map's tables overlap instead of following one another.
    std::array<LightDraw, kLightChunk> draws;
    std::array<LightSample, kLightChunk> found;
    std::array<bool, kLightChunk> sampled;
    const DrawnAhead& ahead = w.ahead[v.path];
    const bool drawnAhead = ahead.dimension == v.sampler.dimension();
    const std::optional<Sampler::Split> split = drawnAhead ? ahead.split : splitLights(v.sampler);
    for (int k0 = 0; k0 < samples; k0 += kLightChunk) {
        const int m = std::min(kLightChunk, samples - k0);
        const bool taken = k0 == 0 && drawnAhead;
        if (taken) {  // the same numbers, drawn
            std::copy_n(ahead.draws.begin(), m, draws.begin());
            v.sampler = ahead.after;
        } else {
            drawLights(v.sampler, split, k0, m, draws.data());
        }
        for (size_t j = 0; j < size_t(m); ++j) {
            const LightDraw& d = draws[j];
            sampled[j] = (taken && ahead.locatedAll && ahead.located[j]
                              ? lights_.sampleLocated(d.light, ahead.points[j], found[j])
                              : lights_.sample(d.light, v.si.p, d.u1, d.u2, found[j])) &&
                         d.pmf != 0;
        }
        for (size_t j = 0; j < size_t(m); ++j)
            if (sampled[j]) queueLightSample<F>(v, bsdf, wo, lightOnly, draws[j], found[j], w);
    }
}

std::optional<Sampler::Split> PathIntegrator::splitLights(Sampler& sampler) const {
    const int samples = lightSamplesPerVertex_;
    if (rules_.eachDeltaLightOnce || samples < 2) return std::nullopt;
    // A pair for the light's choice (where there is one to make), a pair for the point on it.
    return sampler.split(lights_.size() > 1 ? 2 : 1, uint32_t(samples));
}

void PathIntegrator::drawLights(Sampler& sampler, std::optional<Sampler::Split> split, int k0,
                                int m, LightDraw* out, EnvironmentSample* rows,
                                bool* rowPicked) const {
    const bool choose = lights_.size() > 1;
    for (int j = 0; j < m; ++j) {
        LightDraw& d = out[j];
        d = {size_t(k0 + j), 1.0f, 0.5f, 0.5f};
        if (rules_.eachDeltaLightOnce) continue;
        if (!choose) d.light = 0, d.pmf = lights_.selectPmf(0);  // the one light: no choice
        if (split) {
            const uint32_t k = uint32_t(k0 + j);
            if (choose) d.light = lights_.select(sampler.splitDraw(*split, 0, k).u, d.pmf);
            const Sampler::Point2 p = sampler.splitDraw(*split, choose ? 1 : 0, k);
            d.u1 = p.u, d.u2 = p.v;
        } else {
            if (choose)
                d.light = lights_.select(sampler.next1D(), d.pmf);
            else
                sampler.skip1D();
            const Sampler::Point2 p = sampler.next2D();
            d.u1 = p.u, d.u2 = p.v;
        }
        if (rows)
            rowPicked[j] = lights_.pickRow(d.light, d.u1, d.u2, rows[j]);
        else
            lights_.prefetch(d.light, d.u1, d.u2);
    }
}

// Only where the vertex's first numbers are its light samples' (no media: a free flight draws
// first) and they fit one chunk; a guess that the vertex then does not take (a delta BSDF, say)
// costs the draws and nothing else.
void PathIntegrator::drawAhead(std::span<CameraSample> batch, Scratch& w, size_t k,
                               int bounce) const {
    const int samples = lightSamplesPerVertex_;
    if (!drawAheadPays_ || !useNee_ || rules_.eachDeltaLightOnce || samples > kLightChunk ||
        !w.hits[k].valid() || bounce >= opt_.maxDepth || !rules_.gathersAt(bounce))
        return;
    const uint32_t pi = w.active[k];
    DrawnAhead& a = w.ahead[pi];
    a.after = batch[pi].sampler;
    a.dimension = a.after.dimension();
    a.locatedAll = false;
    a.split = splitLights(a.after);
    drawLights(a.after, a.split, 0, samples, a.draws.data(), a.points.data(), a.rowPicked.data());
}

// The environment-light samples drawn ahead for ray k's path located, their texels asked for (their
// table entries were asked for when they were drawn, a few paths ago).
void PathIntegrator::locateAhead(std::span<CameraSample> batch, Scratch& w, size_t k) const {
    const uint32_t pi = w.active[k];
    DrawnAhead& a = w.ahead[pi];
    if (a.dimension != batch[pi].sampler.dimension()) return;  // none drawn for this vertex
    const int samples = lightSamplesPerVertex_;
    for (size_t j = 0; j < size_t(samples); ++j)
        a.located[j] =
            a.rowPicked[j] && lights_.locateInRow(a.draws[j].light, a.draws[j].u1, a.points[j]);
    a.locatedAll = true;
}

// One light sample's estimate, its shadow ray queued (MIS-weighted against the BSDF's sampling).
template <class F, class B>
void PathIntegrator::queueLightSample(const Vertex& v, const B& bsdf, const Vec3& wo,
                                      bool lightOnly, const LightDraw& d, const LightSample& ls,
                                      Scratch& w) const {
    const float nLight = float(opt_.lightSamples);
    const float perSample = rules_.eachDeltaLightOnce ? 1.0f : nLight;
    Vec3 wi = v.frame.toLocal(ls.wi);
    Color f = bsdf.eval(wo, wi) * std::abs(wi.z);
    // Geometric side check: no light from behind the actual surface through a bent normal.
    if (maxComponent(f) <= 0 || (dot(ls.wi, v.si.ng) <= 0 && !bsdf.hasTransmission())) return;
    float pl = d.pmf * ls.pdf;
    float weight = 1.0f;
    if constexpr (!F::deltaLightsOnly)
        if (!ls.delta && opt_.sampling != DirectSampling::Light && !lightOnly &&
            lights_.hittable(d.light))
            weight = misWeight(nLight, pl, 1, bsdf.pdf(wo, wi));
    w.shadowRays.push_back(ls.infinite ? spawnRay(v.si, ls.wi) : spawnRayTo(v.si, ls.p, ls.pError));
    // Light from the other side came through the surface (principled transmission: f is 0
    // there for every BSDF that does not transmit), its shadow ray in the medium beyond it.
    const bool through = wi.z * wo.z < 0;
    if constexpr (F::media)
        w.shadowMedia.push_back(through ? media_.across(v.si, v.st.medium) : v.st.medium);
    w.pending.push_back({v.path, v.bounce + 1, v.lobe(through),
                         v.st.beta * f * ls.Li * (weight / (pl * perSample))});
}

// -H (CS184's estimate_direct_lighting_hemisphere): -l uniform hemisphere rays, each adding the
// emission it finds; the continuing path then counts none.
template <class B>
void PathIntegrator::queueHemisphereProbes(const Vertex& v, const B& bsdf, const Vec3& wo,
                                           Scratch& w) const {
    const float nLight = float(opt_.lightSamples);
    // More than one probe: split draws of one pair, stratified among themselves (Sampler::split).
    std::optional<Sampler::Split> split;
    if (opt_.lightSamples > 1) split = v.sampler.split(1, uint32_t(opt_.lightSamples));
    for (int k = 0; k < opt_.lightSamples; ++k) {
        Sampler::Point2 p;
        if (split)
            p = v.sampler.splitDraw(*split, 0, uint32_t(k));
        else
            p.u = v.sampler.next1D(), p.v = v.sampler.next1D();
        Vec3 wi = uniformHemisphere(p.u, p.v);
        if (wo.z < 0) wi.z = -wi.z;
        Vec3 wiWorld = v.frame.toWorld(wi);
        Color f = bsdf.eval(wo, wi) * std::abs(wi.z);
        if (maxComponent(f) <= 0 || (dot(wiWorld, v.si.ng) > 0) != (dot(v.woWorld, v.si.ng) > 0))
            continue;
        w.probeRays.push_back(spawnRay(v.si, wiWorld));
        w.probes.push_back(
            {v.path, v.bounce + 1, v.lobe(), v.st.beta * f / (uniformHemispherePdf() * nLight)});
    }
}

// The bounce: a direction sampled from the BSDF, the throughput updated, roulette played, the
// next ray queued.
template <class B>
void PathIntegrator::continuePath(const Vertex& v, const B& bsdf, const Vec3& wo,
                                  Scratch& w) const {
    BsdfSample bs;
    float uc = 0.5f;  // the lobe choice, for BSDFs with more than one lobe
    if (bsdf.usesLobeChoice())
        uc = v.sampler.next1D();
    else
        v.sampler.skip1D();
    auto [u1, u2] = v.sampler.nextBounce2D();
    if (!bsdf.sample(wo, uc, u1, u2, bs)) return;
    if (bs.pdf <= 0 || maxComponent(bs.f) <= 0) return;
    // With -H, what a non-delta bounce's ray finds at the last depth the probes counted.
    if (rules_.hemisphere && !bs.delta && v.bounce + 1 >= opt_.maxDepth) return;
    // The shading frame may send a reflection below the real surface, or a refraction back out of
    // it: following either would leak light through thin walls.
    Vec3 wiWorld = v.frame.toWorld(bs.wi);
    if ((dot(wiWorld, v.si.ng) > 0) == bs.transmission) return;
    PathState& st = v.st;
    if (v.bounce == 0) st.firstLobe = v.lobe(bs.transmission);
    st.beta *= bs.f * (std::abs(bs.wi.z) / bs.pdf);
    st.specular = bs.delta;
    st.prevPdf = bs.misPdf > 0 ? bs.misPdf : bs.pdf;
    st.prevP = v.si.p;
    if (!playRoulette(st, v.sampler, v.bounce)) return;
    if (!isFinite(st.beta) || maxComponent(st.beta) <= 0) return;
    w.next.push_back(v.path);
    w.nextRays.push_back(spawnRay(v.si, wiWorld));
}

// Russian roulette: unbiased, the survivors carry 1 / continuation. Its dimension is spent at every
// vertex, played or not. False: the path ends.
bool PathIntegrator::playRoulette(PathState& st, Sampler& sampler, int bounce) const {
    if (opt_.roulette == Roulette::Throughput && bounce + 1 >= opt_.rouletteMinBounces) {
        float q = std::min(1.0f, maxComponent(st.beta));
        if (sampler.next1D() >= q) return false;
        st.beta = st.beta / q;
    } else if (opt_.roulette == Roulette::Fixed && bounce >= 1) {
        if (sampler.next1D() >= opt_.fixedContinuation) return false;
        st.beta = st.beta / opt_.fixedContinuation;
    } else {
        sampler.skip1D();
    }
    return true;
}

// The queued next-event estimates, traced together; in queue order, which is each path's own.
template <class F>
void PathIntegrator::resolveShadowRays(std::span<CameraSample> batch, Scratch& w,
                                       RayCounter& counter) const {
    if (w.shadowRays.empty()) return;
    if constexpr (F::media) {  // through index-matched boundaries, dimmed by the media
        for (size_t k = 0; k < w.pending.size(); ++k) {
            const PendingLight& p = w.pending[k];
            Color tr =
                media_.transmittance(accel_, w.shadowRays[k], w.shadowMedia[k], counter.rays);
            if (maxComponent(tr) > 0)
                addLight<F::splitLight>(batch[p.path].record, p.bounce, p.contribution * tr,
                                        p.lobe);
        }
        return;
    }
    w.occluded.resize(w.shadowRays.size());
    accel_.occluded(std::span<const Ray>(w.shadowRays), std::span<uint8_t>(w.occluded));
    counter.rays += w.shadowRays.size();
    for (size_t k = 0; k < w.pending.size(); ++k) {
        if (w.occluded[k]) continue;
        const PendingLight& p = w.pending[k];
        addLight<F::splitLight>(batch[p.path].record, p.bounce, p.contribution, p.lobe);
    }
}

// The queued -H probes, traced together: each adds the emission it found.
template <class F>
void PathIntegrator::resolveProbes(std::span<CameraSample> batch, Scratch& w,
                                   RayCounter& counter) const {
    if (w.probeRays.empty()) return;
    w.probeHits.resize(w.probeRays.size());
    accel_.intersect(std::span<const Ray>(w.probeRays), std::span<Hit>(w.probeHits));
    counter.rays += w.probeRays.size();
    for (size_t k = 0; k < w.probes.size(); ++k) {
        const PendingLight& p = w.probes[k];
        Color Le = probeEmission<F::infinite>(w.probeRays[k], w.probeHits[k]);
        if (maxComponent(Le) > 0)
            addLight<F::splitLight>(batch[p.path].record, p.bounce, p.contribution * Le, p.lobe);
    }
}

}  // namespace kiln
