// Fresnel reflectance: dielectric interfaces and conductors (exact, unpolarised).
#pragma once

#include <algorithm>
#include <cmath>

#include "renderer/core/math.h"

namespace kiln {

// Schlick's Fresnel approximation is F0 + (1 - F0) w with this weight w = (1 - cos)^5.
inline float schlickWeight(float cosTheta) {
    float m = std::clamp(1 - cosTheta, 0.0f, 1.0f), m2 = m * m;
    return m2 * m2 * m;
}

// Reflectance of a dielectric interface; cosThetaI > 0 means arriving from the side with index 1
// and eta = n_t / n_i. Handles leaving (cosThetaI < 0) and total internal reflection (returns 1).
inline float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
    if (cosThetaI < 0) {
        eta = 1 / eta;
        cosThetaI = -cosThetaI;
    }
    float sin2ThetaI = 1 - cosThetaI * cosThetaI;
    float sin2ThetaT = sin2ThetaI / (eta * eta);
    if (sin2ThetaT >= 1) return 1.0f;
    float cosThetaT = std::sqrt(std::max(0.0f, 1 - sin2ThetaT));
    float rParl = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    float rPerp = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5f * (rParl * rParl + rPerp * rPerp);
}

// Reflectance of a conductor with complex index eta + i k (relative to the outside medium), per
// channel.
inline float fresnelConductor1(float cosThetaI, float eta, float k) {
    cosThetaI = std::clamp(cosThetaI, 0.0f, 1.0f);
    float cos2 = cosThetaI * cosThetaI, sin2 = 1 - cos2;
    float eta2 = eta * eta, k2 = k * k;
    float t0 = eta2 - k2 - sin2;
    float a2plusb2 = std::sqrt(std::max(0.0f, t0 * t0 + 4 * eta2 * k2));
    float t1 = a2plusb2 + cos2;
    float a = std::sqrt(std::max(0.0f, 0.5f * (a2plusb2 + t0)));
    float t2 = 2 * cosThetaI * a;
    float rs = (t1 - t2) / (t1 + t2);
    float t3 = cos2 * a2plusb2 + sin2 * sin2;
    float t4 = t2 * sin2;
    float rp = rs * (t3 - t4) / (t3 + t4);
    return 0.5f * (rp + rs);
}

inline Color fresnelConductor(float cosThetaI, const Color& eta, const Color& k) {
    return {fresnelConductor1(cosThetaI, eta.x, k.x), fresnelConductor1(cosThetaI, eta.y, k.y),
            fresnelConductor1(cosThetaI, eta.z, k.z)};
}

// Refracts wi (pointing away from the surface, on the side of n) through n with eta = n_t / n_i.
// Returns false on total internal reflection.
inline bool refract(const Vec3& wi, const Vec3& n, float eta, Vec3& wt) {
    float cosI = dot(n, wi);
    float sin2I = std::max(0.0f, 1 - cosI * cosI);
    float sin2T = sin2I / (eta * eta);
    if (sin2T >= 1) return false;
    float cosT = std::sqrt(1 - sin2T);
    wt = -wi / eta + n * (cosI / eta - cosT);
    return true;
}

}  // namespace kiln
