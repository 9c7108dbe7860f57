#include "integrators/subsurface.h"

#include <algorithm>

#include "integrators/slab_albedo.h"

namespace kiln {
namespace {

// Cycles' floor on the single-scattering albedo (subsurface_random_walk_coefficients).
constexpr float kMinAlpha = 0.2f;
// A walk longer than this is lost. On a semi-infinite medium of albedo 0.99 the walks still inside
// after 2^16 steps carry 0.03 % of what it reflects (after 1024 steps, 3 %; at 0.9, 0.08 %).
constexpr int kMaxSteps = 1 << 16;

}  // namespace

WalkMedium walkMedium(const Color& albedo, const Color& meanFreePath) {
    static const float floorAlbedo = float(slabAlbedo(kMinAlpha));
    Color sigmaT, sigmaS, weight(1.0f);
    for (int c = 0; c < 3; ++c) {
        float A = std::clamp(albedo[c], 0.0f, 1.0f);
        float d = std::max(meanFreePath[c], 1e-6f);
        float alpha = singleScatteringAlbedoFor(A);
        if (alpha < kMinAlpha) {  // the floor's medium reflects floorAlbedo: scaled to A
            weight[c] = A / floorAlbedo;
            alpha = kMinAlpha;
        }
        // Chiang et al.'s scale: the mean free path d sets the walk's extinction 1 / (d s(A)).
        float s = 1.9f - A + 3.5f * (A - 0.8f) * (A - 0.8f);
        sigmaT[c] = 1 / (d * s);
        sigmaS[c] = sigmaT[c] * alpha;
    }
    return {HomogeneousMedium(sigmaT - sigmaS, sigmaS, 0.0f), weight};
}

bool randomWalk(const Scene& scene, const Accelerator& accel, const SurfaceInteraction& entry,
                const WalkMedium& walk, const Color& pathBeta, Sampler& sampler, WalkExit& exit,
                uint64_t& rays) {
    auto [u1, u2] = sampler.next2D();
    Vec3 dir = Frame(-entry.ng).toWorld(cosineHemisphere(u1, u2));
    Ray ray = spawnRay(entry, dir);
    Color beta = walk.weight;
    for (int step = 0; step < kMaxSteps; ++step) {
        Hit hit;
        ++rays;
        // Inside a closed mesh every ray meets the surface; one that does not left through a hole.
        if (!accel.intersect(ray, hit)) return false;
        const float uChannel = sampler.next1D(), uDistance = sampler.next1D();
        FreeFlight flight = walk.medium.sample(hit.t, pathBeta * beta, uChannel, uDistance);
        beta *= flight.weight;
        if (!isFinite(beta) || maxComponent(beta) <= 0) return false;
        if (!flight.scattered) {
            exit.si = makeInteraction(scene, ray, hit);
            // Seen from outside: the normals and spawn origins turn round.
            exit.si.ng = -exit.si.ng, exit.si.ns = -exit.si.ns;
            exit.si.nsStored = exit.si.ng;
            std::swap(exit.si.originFront, exit.si.originBack);
            exit.weight = beta;
            return true;
        }
        auto [v1, v2] = sampler.next2D();
        ray = Ray{ray.origin + ray.dir * flight.t, 0.0f, uniformSphere(v1, v2), kInfinity};
    }
    return false;
}

}  // namespace kiln
