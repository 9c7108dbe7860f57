// Helpers shared by the principled BSDF tests: directions by angle, materials by their inputs, and
// the directional albedo estimated by the BSDF's own sampling.
#pragma once

#include <cmath>

#include "integrators/bsdf.h"
#include "renderer/core/sampler.h"

namespace kiln::test {

inline Vec3 direction(float thetaDeg, float phiDeg = 30) {
    float t = radians(thetaDeg), p = radians(phiDeg);
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

inline Material principled(float metallic, float roughness, float clearcoat = 0,
                           float coatRough = 0, Color base = Color(0.8f, 0.5f, 0.2f)) {
    Material m;
    m.kind = MaterialKind::Principled;
    m.albedo = base;
    m.metallic = metallic;
    m.roughness = roughness;
    m.clearcoat = clearcoat;
    m.clearcoatRoughness = coatRough;
    return m;
}

// Directional albedo sum(f cos / pdf) / N of the red channel, with its standard error; samples
// through the surface count transmittedScale times (eta^2 undoes the radiance's compression).
struct Albedo {
    double mean = 0, stdError = 0;
};

inline Albedo directionalAlbedo(const Bsdf& bsdf, const Vec3& wo, int n, uint64_t seed,
                                double transmittedScale = 1) {
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        Sampler s(seed, uint64_t(i), 0);
        BsdfSample bs;
        float uc = s.next1D(), u1 = s.next1D(), u2 = s.next1D();
        double x = 0;
        if (bsdf.sample(wo, uc, u1, u2, bs)) x = double(bs.f.x) * std::abs(bs.wi.z) / bs.pdf;
        if (bs.wi.z * wo.z < 0) x *= transmittedScale;
        sum += x, sum2 += x * x;
    }
    double mean = sum / n, var = std::max(0.0, sum2 / n - mean * mean);
    return {mean, std::sqrt(var / n)};
}

}  // namespace kiln::test
