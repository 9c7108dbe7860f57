#include "integrators/subsurface.h"

#include <algorithm>

namespace kiln {
namespace {

// Cycles' floor on the single-scattering albedo (subsurface_random_walk_coefficients).
constexpr float kMinAlpha = 0.2f;
// A walk longer than this is lost (the throughput is negligible long before in any real medium).
constexpr int kMaxSteps = 1024;

}  // namespace

WalkMedium walkMedium(const Color& albedo, const Color& meanFreePath) {
    Color sigmaT, sigmaS, weight(1.0f);
    for (int c = 0; c < 3; ++c) {
        float A = std::clamp(albedo[c], 0.0f, 1.0f);
        float d = std::max(meanFreePath[c], 1e-6f);
        float alpha = 1 - std::exp(A * (-5.09406f + A * (2.61188f - A * 4.31805f)));
        float s = 1.9f - A + 3.5f * (A - 0.8f) * (A - 0.8f);
        if (alpha < kMinAlpha) {
            weight[c] = alpha / kMinAlpha;
            alpha = kMinAlpha;
        }
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
        const bool found = accel.intersect(ray, hit);
        const float uChannel = sampler.next1D(), uDistance = sampler.next1D();
        FreeFlight flight =
            walk.medium.sample(found ? hit.t : kInfinity, pathBeta * beta, uChannel, uDistance);
        beta *= flight.weight;
        if (!isFinite(beta) || maxComponent(beta) <= 0) return false;
        if (!flight.scattered) {
            if (!found) return false;
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
