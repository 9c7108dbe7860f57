// The guide field's training (guiding.h): photons from the emitting surfaces, followed through
// glossy and specular bounces to the first diffuse surface they land on.
#include "integrators/path.h"
#include "renderer/geometry/interaction.h"
#include "scene/material_kinds.h"

namespace kiln {
namespace {

// Bounces a photon may take through glossy and specular surfaces before it lands (or the path
// depth, if smaller): longer chains carry little light a diffuse bounce would miss.
constexpr int kMaxPhotonBounces = 8;

}  // namespace

void PathIntegrator::traceCausticPhotons(uint64_t first, size_t count, uint64_t seed,
                                         std::vector<GuideRecord>& records) const {
    const int maxBounces = std::min(kMaxPhotonBounces, opt_.maxDepth);
    for (uint64_t k = first; k < first + count; ++k) {
        Sampler s(seed, k, 0, SamplerKind::Independent);
        float uLight = s.next1D(), u1 = s.next1D(), u2 = s.next1D(), uSide = s.next1D(),
              u3 = s.next1D(), u4 = s.next1D();
        EmissionSample emitted;
        if (!lights_.sampleEmission(uLight, u1, u2, uSide, u3, u4, emitted)) continue;
        Ray ray = spawnRay(emitted.from, emitted.dir);
        Color power = emitted.power;
        Vec3 source;  // the glossy or specular point the photon last left
        // A path from the landing point back to the light can end by hitting the light, or by
        // light sampling at the photon's first bounce unless that was a delta one (a mirror).
        bool reachable = emitted.hittable;
        for (int bounce = 0; bounce < maxBounces; ++bounce) {
            Hit hit;
            if (!accel_.intersect(ray, hit)) break;
            SurfaceInteraction si = makeInteraction(scene_, ray, hit);
            const Material& mat = scene_.materials[si.material];
            const Vec3 woWorld = -normalize(ray.dir);
            const MaterialKindSpec& kind = specOf(mat.kind);
            if (kind.lambertian) {
                // Landed (light straight from an emitter is next-event estimation's, not the
                // guide's; light no camera path could carry back is not guided towards; a black
                // surface, such as an emitter's, reflects none of it).
                if (bounce > 0 && reachable && maxComponent(mat.albedo) > 0)
                    records.push_back({si.p, source, luminance(power)});
                break;
            }
            if (kind.black) break;
            Bsdf bsdf(mat, opt_.microfacet, SurfaceInputs::of(mat));
            Frame frame = shadingFrame(si, woWorld);
            float uc = s.next1D(), v1 = s.next1D(), v2 = s.next1D();
            BsdfSample bs;
            if (!bsdf.sample(frame.toLocal(woWorld), uc, v1, v2, bs) || bs.pdf <= 0) break;
            Vec3 wi = frame.toWorld(bs.wi);
            if ((dot(wi, si.ng) > 0) == bs.transmission) break;
            power *= bs.f * (std::abs(bs.wi.z) / bs.pdf);
            if (!isFinite(power) || maxComponent(power) <= 0) break;
            ray = spawnRay(si, wi);
            source = si.p;
            if (bounce == 0) reachable |= !bs.delta;
        }
    }
}

}  // namespace kiln
