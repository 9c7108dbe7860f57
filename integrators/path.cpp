#include "integrators/path.h"

#include <type_traits>

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
      lights_(scene) {
    for (const Material& m : scene.materials) lambertian_.push_back(specOf(m.kind).lambertian);
    opt_.lightSamples = resolvedLightSamples(options, plan);
    // Up to 64 delta lights, as the course does; beyond that (a many-light scene) a shadow ray per
    // light per vertex would swamp the render, and -l picks by power instead.
    constexpr size_t kMaxDeltaLightsTakenEach = 64;
    eachDeltaLightOnce_ =
        lights_.size() > 0 && lights_.size() <= kMaxDeltaLightsTakenEach && lights_.allDelta();
    // Only where light sampling sees every emitter and MIS would otherwise weigh what the last
    // continuation finds (not with -H probes or BSDF-only direct light).
    lightOnlyAtLastVertex_ =
        lights_.size() > 0 && lights_.everyEmitterSampled() &&
        (options.sampling == DirectSampling::Mis || options.sampling == DirectSampling::Light);
}

PathIntegrator::TraceFn PathIntegrator::pathFor(const RenderPlan& plan) {
    if (plan.general) return &PathIntegrator::trace<false, true, false, true>;
    bool diffuse = plan.diffuseOnly, infinite = plan.infiniteLights;
    bool deltaOnly = plan.deltaLightsOnly && !plan.emitters && !plan.infiniteLights;
    bool split = plan.aovs.splitsLight();
    // Chosen once per render: each combination is its own instantiation.
    static constexpr TraceFn kTable[2][2][2][2] = {
        {{{&PathIntegrator::trace<false, false, false, false>,
           &PathIntegrator::trace<false, false, false, true>},
          {&PathIntegrator::trace<false, false, true, false>,
           &PathIntegrator::trace<false, false, true, true>}},
         {{&PathIntegrator::trace<false, true, false, false>,
           &PathIntegrator::trace<false, true, false, true>},
          {&PathIntegrator::trace<false, true, true, false>,
           &PathIntegrator::trace<false, true, true, true>}}},
        {{{&PathIntegrator::trace<true, false, false, false>,
           &PathIntegrator::trace<true, false, false, true>},
          {&PathIntegrator::trace<true, false, true, false>,
           &PathIntegrator::trace<true, false, true, true>}},
         {{&PathIntegrator::trace<true, true, false, false>,
           &PathIntegrator::trace<true, true, false, true>},
          {&PathIntegrator::trace<true, true, true, false>,
           &PathIntegrator::trace<true, true, true, true>}}}};
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
    if (!opt_.accumulateBounces && bounce != opt_.maxDepth) return;
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

namespace {

// What a path carries from one vertex to the next (its next ray waits in BatchScratch::nextRays).
struct PathState {
    Color beta{1.0f};
    bool specular = true;  // the previous vertex was the camera or a delta lobe: nothing else could
                           // see the light
    float prevPdf = 0;
    Vec3 prevP;
    Lobe firstLobe = Lobe::Diffuse;  // how the path left its first vertex (for the lobe AOVs)
    float travelled = 0;             // path length so far: the texture footprint grows with it
};

// A next-event estimate waiting for its shadow ray: added to its path's record if unoccluded.
struct PendingLight {
    uint32_t path;
    int bounce;
    Lobe lobe;
    Color contribution;
};

// Scratch reused by every batch a thread traces.
struct BatchScratch {
    std::vector<PathState> paths;
    std::vector<uint32_t> active, next;  // live paths, and their rays in the same order
    std::vector<Ray> rays, nextRays, shadowRays;
    std::vector<Hit> hits;
    std::vector<PendingLight> pending;
    std::vector<uint8_t> occluded;
    // -H: hemisphere probes (closest-hit rays whose emission is the direct light), their
    // throughput waiting in PendingLight::contribution.
    std::vector<Ray> probeRays;
    std::vector<Hit> probeHits;
    std::vector<PendingLight> probes;
};

}  // namespace

// Wavefront over a batch: every live path's next ray is traced together (Embree packets), then
// every path is shaded, its next-event shadow rays queued; the queue is traced together and the
// unoccluded estimates added. Each path still draws its random numbers and adds its light in the
// same order as a path traced alone, so the image does not depend on how samples are batched.
template <bool DiffuseOnly, bool Infinite, bool DeltaLightsOnly, bool SplitLight>
void PathIntegrator::trace(std::span<CameraSample> batch, RayCounter& counter) const {
    thread_local BatchScratch scratch;
    BatchScratch& w = scratch;
    w.paths.assign(batch.size(), PathState{});
    size_t perVertex = eachDeltaLightOnce_ ? lights_.size() : size_t(opt_.lightSamples);
    w.pending.reserve(batch.size() * perVertex);
    w.shadowRays.reserve(batch.size() * perVertex);
    w.active.clear();
    w.rays.clear();
    for (uint32_t i = 0; i < batch.size(); ++i) {
        w.paths[i].prevP = batch[i].ray.origin;
        w.active.push_back(i);
        w.rays.push_back(batch[i].ray);
    }
    const float nLight = float(opt_.lightSamples);
    const bool hemisphere = opt_.sampling == DirectSampling::Hemisphere;
    // Without next-event estimation (bsdf) emission found by the path counts in full (weight 1).
    const bool useNee = !hemisphere && opt_.sampling != DirectSampling::Bsdf && lights_.size() > 0;

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
        w.next.clear();
        w.nextRays.clear();
        w.pending.clear();
        w.shadowRays.clear();
        w.probes.clear();
        w.probeRays.clear();

        // Mesh data of hits a few ahead requested from memory while this one is shaded.
        constexpr size_t kIndicesAhead = 16, kVerticesAhead = 8;
        for (size_t j = 0; j < std::min(kIndicesAhead, w.hits.size()); ++j)
            prefetchHitIndices(scene_, w.hits[j]);
        for (size_t j = 0; j < w.active.size(); ++j) {
            if (j + kIndicesAhead < w.hits.size())
                prefetchHitIndices(scene_, w.hits[j + kIndicesAhead]);
            if (j + kVerticesAhead < w.hits.size())
                prefetchHitVertices(scene_, w.hits[j + kVerticesAhead]);
            uint32_t pi = w.active[j];
            PathState& st = w.paths[pi];
            Sampler& sampler = batch[pi].sampler;
            SampleRecord& rec = batch[pi].record;
            const Ray& ray = w.rays[j];
            const Hit& hit = w.hits[j];

            // Weight of emission found by following the BSDF-sampled ray, against NEE having
            // sampled light li.
            auto emissionWeight = [&](int li, const Vec3& dir, const Vec3& x, const Vec3& n) {
                if constexpr (DeltaLightsOnly)
                    return 1.0f;  // no light can be hit: emission here is unweighted
                if (hemisphere && !st.specular) return 0.0f;  // the probes counted it
                if (st.specular || li < 0 || !useNee) return 1.0f;
                if (opt_.sampling == DirectSampling::Light) return 0.0f;
                float pl =
                    lights_.selectPmf(size_t(li)) * lights_.pdf(size_t(li), st.prevP, dir, x, n);
                return misWeight(1, st.prevPdf, nLight, pl);
            };

            if (!hit.valid()) {
                if constexpr (Infinite) {
                    Vec3 dir = normalize(ray.dir);
                    for (size_t i : lights_.infiniteLights()) {
                        Color Le = lights_.escaped(i, dir, bounce == 0);
                        if (maxComponent(Le) > 0)
                            addLight<SplitLight>(
                                rec, bounce,
                                st.beta * Le * emissionWeight(int(i), dir, Vec3(0.0f), Vec3(0.0f)),
                                st.firstLobe);
                    }
                }
                continue;
            }
            SurfaceInteraction si = makeInteraction(scene_, ray, hit);
            const Material& mat = scene_.materials[si.material];
            if (bounce == 0) recordSurface(ray, hit, si, rec);
            if (maxComponent(mat.emission) > 0) {
                int li = -1;
                Color Le = emissionAt(ray, hit, si, li);
                if (li < 0 && bounce > 0 && !opt_.unsampledEmittersLight) Le = Color(0.0f);
                addLight<SplitLight>(
                    rec, bounce, st.beta * Le * emissionWeight(li, normalize(ray.dir), si.p, si.ng),
                    st.firstLobe);
            }
            if (bounce >= opt_.maxDepth) continue;
            SurfaceInputs in = SurfaceInputs::of(mat);
            if (colourVaries_) {
                st.travelled += hit.t * length(ray.dir);
                const float footprint = st.travelled * opt_.pixelSpread;
                in = surfaceInputsAt(scene_, mat, hit, footprint);
                applyNormalMap(scene_, mat, hit, -normalize(ray.dir), footprint, si);
            }
            // The rest of the vertex, for its BSDF: a Lambertian surface takes the Lambert-only
            // code in every scene (measured: the general BSDF's dispatch slowed the walls of a box
            // holding one metal object by a third).
            const Vec3 woWorld = -normalize(ray.dir);
            const Frame frame = shadingFrame(si, woWorld);
            auto shade = [&](const auto& bsdf) {
                if (bsdf.isBlack()) return;
                Vec3 wo = frame.toLocal(woWorld);
                // A diffuse last vertex takes its direct light from light sampling alone: its
                // continuation could only find emission, which MIS weighs low on a diffuse surface.
                const bool lightOnly =
                    lightOnlyAtLastVertex_ && bounce + 1 == opt_.maxDepth && bsdf.isDiffuse();

                // Next-event estimation, shadow rays queued: -l lights chosen by power, or, when
                // every light is a delta light, each light once (CS184's "a point light gets one
                // sample": more samples of a point would repeat the same ray).
                if (useNee && !bsdf.isDelta() &&
                    (opt_.accumulateBounces || bounce + 1 == opt_.maxDepth)) {
                    const int samples =
                        eachDeltaLightOnce_ ? int(lights_.size()) : opt_.lightSamples;
                    const float perSample = eachDeltaLightOnce_ ? 1.0f : nLight;
                    for (int k = 0; k < samples; ++k) {
                        float pmf = 1.0f, u1 = 0.5f, u2 = 0.5f;
                        size_t li = size_t(k);
                        if (!eachDeltaLightOnce_) {
                            if (lights_.size() == 1) {  // the one light: no choice to draw
                                sampler.skip1D();
                                li = 0, pmf = lights_.selectPmf(0);
                            } else {
                                li = lights_.select(sampler.next1D(), pmf);
                            }
                            auto [a, b] = sampler.next2D();
                            u1 = a, u2 = b;
                        }
                        LightSample ls;
                        if (!lights_.sample(li, si.p, u1, u2, ls) || pmf == 0) continue;
                        Vec3 wi = frame.toLocal(ls.wi);
                        Color f = bsdf.eval(wo, wi) * std::abs(wi.z);
                        // Geometric side check: no light from behind the actual surface through a
                        // bent normal.
                        if (maxComponent(f) <= 0 ||
                            (dot(ls.wi, si.ng) <= 0 && !bsdf.hasTransmission()))
                            continue;
                        float pl = pmf * ls.pdf;
                        float weight = 1.0f;
                        if constexpr (!DeltaLightsOnly)
                            if (!ls.delta && opt_.sampling != DirectSampling::Light && !lightOnly &&
                                lights_.hittable(li))
                                weight = misWeight(nLight, pl, 1, bsdf.pdf(wo, wi));
                        w.shadowRays.push_back(ls.infinite ? spawnRay(si, ls.wi)
                                                           : spawnRayTo(si, ls.p, ls.pError));
                        w.pending.push_back({pi, bounce + 1,
                                             bounce == 0 ? lobeOf(mat, false) : st.firstLobe,
                                             st.beta * f * ls.Li * (weight / (pl * perSample))});
                    }
                }

                // -H (CS184's estimate_direct_lighting_hemisphere): -l uniform hemisphere rays,
                // each adding the emission it finds; the continuing path then counts none.
                if (hemisphere && !bsdf.isDelta() &&
                    (opt_.accumulateBounces || bounce + 1 == opt_.maxDepth)) {
                    for (int k = 0; k < opt_.lightSamples; ++k) {
                        Vec3 wi = uniformHemisphere(sampler.next1D(), sampler.next1D());
                        if (wo.z < 0) wi.z = -wi.z;
                        Vec3 wiWorld = frame.toWorld(wi);
                        Color f = bsdf.eval(wo, wi) * std::abs(wi.z);
                        if (maxComponent(f) <= 0 ||
                            (dot(wiWorld, si.ng) > 0) != (dot(woWorld, si.ng) > 0))
                            continue;
                        w.probeRays.push_back(spawnRay(si, wiWorld));
                        w.probes.push_back({pi, bounce + 1,
                                            bounce == 0 ? lobeOf(mat, false) : st.firstLobe,
                                            st.beta * f / (uniformHemispherePdf() * nLight)});
                    }
                }

                // Continue the path. With only delta lights and no emitters, a ray after the last
                // bounce could find nothing: not traced.
                if constexpr (DeltaLightsOnly)
                    if (bounce + 1 >= opt_.maxDepth) return;
                if (lightOnly) return;
                BsdfSample bs;
                float uc = 0.5f;  // the lobe choice, for BSDFs with more than one lobe
                if (bsdf.usesLobeChoice())
                    uc = sampler.next1D();
                else
                    sampler.skip1D();
                auto [u1, u2] = sampler.next2D();
                if (!bsdf.sample(wo, uc, u1, u2, bs)) return;
                if (bs.pdf <= 0 || maxComponent(bs.f) <= 0) return;
                // With -H, what a non-delta bounce's ray finds at the last depth the probes
                // counted.
                if (hemisphere && !bs.delta && bounce + 1 >= opt_.maxDepth) return;
                // The shading frame may send a reflection below the real surface, or a refraction
                // back out of it: following either would leak light through thin walls.
                Vec3 wiWorld = frame.toWorld(bs.wi);
                if ((dot(wiWorld, si.ng) > 0) == bs.transmission) return;
                if (bounce == 0) st.firstLobe = lobeOf(mat, bs.transmission);
                st.beta *= bs.f * (std::abs(bs.wi.z) / bs.pdf);
                st.specular = bs.delta;
                st.prevPdf = bs.misPdf > 0 ? bs.misPdf : bs.pdf;
                st.prevP = si.p;

                // Russian roulette: unbiased, the survivors carry 1 / continuation. Its dimension
                // is spent at every vertex, played or not.
                if (opt_.roulette == Roulette::Throughput &&
                    bounce + 1 >= opt_.rouletteMinBounces) {
                    float q = std::min(1.0f, maxComponent(st.beta));
                    if (sampler.next1D() >= q) return;
                    st.beta = st.beta / q;
                } else if (opt_.roulette == Roulette::Fixed && bounce >= 1) {
                    if (sampler.next1D() >= opt_.fixedContinuation) return;
                    st.beta = st.beta / opt_.fixedContinuation;
                } else {
                    sampler.skip1D();
                }
                if (!isFinite(st.beta) || maxComponent(st.beta) <= 0) return;
                w.next.push_back(pi);
                w.nextRays.push_back(spawnRay(si, wiWorld));
            };
            if (DiffuseOnly || lambertian_[si.material]) {
                LambertBsdf lambert(in.baseColour, !lambertian_[si.material]);
                // Guided where the bounce is traced (not at a light-only last vertex).
                const bool bounces = !(lightOnlyAtLastVertex_ && bounce + 1 == opt_.maxDepth);
                const GuideLeaf* leaf = guide_ && bounces ? guide_->leafAt(si.p) : nullptr;
                if (leaf)
                    shade(GuidedLambert(lambert, *leaf, si.p, frame));
                else
                    shade(lambert);
            } else {
                shade(Bsdf(mat, opt_.microfacet, in));
            }
        }

        // The queued next-event estimates, traced together; in queue order, which is each path's
        // own order.
        if (!w.shadowRays.empty()) {
            w.occluded.resize(w.shadowRays.size());
            accel_.occluded(std::span<const Ray>(w.shadowRays), std::span<uint8_t>(w.occluded));
            counter.rays += w.shadowRays.size();
            for (size_t k = 0; k < w.pending.size(); ++k) {
                if (w.occluded[k]) continue;
                const PendingLight& p = w.pending[k];
                addLight<SplitLight>(batch[p.path].record, p.bounce, p.contribution, p.lobe);
            }
        }
        if (!w.probeRays.empty()) {
            w.probeHits.resize(w.probeRays.size());
            accel_.intersect(std::span<const Ray>(w.probeRays), std::span<Hit>(w.probeHits));
            counter.rays += w.probeRays.size();
            for (size_t k = 0; k < w.probes.size(); ++k) {
                const PendingLight& p = w.probes[k];
                Color Le = probeEmission<Infinite>(w.probeRays[k], w.probeHits[k]);
                if (maxComponent(Le) > 0)
                    addLight<SplitLight>(batch[p.path].record, p.bounce, p.contribution * Le,
                                         p.lobe);
            }
        }
        w.active.swap(w.next);
        w.rays.swap(w.nextRays);
    }
}

}  // namespace kiln
