// Sample warps from the unit square and their densities: one place for each formula.
#pragma once

#include <cmath>

#include "renderer/core/math.h"

namespace kiln {

constexpr float kInvPi = 1.0f / kPi;

inline Vec3 uniformHemisphere(float u1, float u2) {
    float z = u1, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniformHemispherePdf() { return 1.0f / (2 * kPi); }

inline Vec3 uniformSphere(float u1, float u2) {
    float z = 1 - 2 * u1, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniformSpherePdf() { return 1.0f / (4 * kPi); }

// sin and cos of t in [-pi/4, pi/4] by their Taylor polynomials (to t^9 and t^8: within 3e-8
// there): the concentric map's angles never leave that range, and the library call was 2 % of a
// diffuse render.
inline void sinCosQuarterPi(float t, float& s, float& c) {
    float t2 = t * t;
    s = t * (1 + t2 * (-1.0f / 6 + t2 * (1.0f / 120 + t2 * (-1.0f / 5040 + t2 * (1.0f / 362880)))));
    c = 1 + t2 * (-0.5f + t2 * (1.0f / 24 + t2 * (-1.0f / 720 + t2 * (1.0f / 40320))));
}

// Shirley-Chiu concentric map. Written with selects, not a branch on which of |a|, |b| is larger:
// that is a coin flip the predictor cannot learn.
inline void concentricDisk(float u1, float u2, float& x, float& y) {
    float a = 2 * u1 - 1, b = 2 * u2 - 1;
    if (a == 0 && b == 0) {
        x = y = 0;
        return;
    }
    // |a| > |b|: phi = pi/4 (b/a); else phi = pi/2 - pi/4 (a/b), where cos and sin trade places.
    bool wide = std::abs(a) > std::abs(b);
    float r = wide ? a : b, s, c;
    sinCosQuarterPi((kPi / 4) * ((wide ? b : a) / r), s, c);
    x = r * (wide ? c : s), y = r * (wide ? s : c);
}

inline Vec3 cosineHemisphere(float u1, float u2) {
    float x, y;
    concentricDisk(u1, u2, x, y);
    return {x, y, std::sqrt(std::max(0.0f, 1 - x * x - y * y))};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * kInvPi : 0.0f; }

// Uniform point on a triangle as barycentrics (b1, b2) (Heitz's low-distortion map).
// Written with selects, not a branch: the comparison is a coin flip the predictor cannot learn.
inline void uniformTriangle(float u1, float u2, float& b1, float& b2) {
    bool lower = u1 < u2;
    float h1 = u1 * 0.5f, h2 = u2 * 0.5f;
    b1 = lower ? h1 : u1 - h2;
    b2 = lower ? u2 - h1 : h2;
}

// Uniform direction in the cone of half-angle acos(cosMax) around +z, and its solid-angle density.
inline Vec3 uniformCone(float u1, float u2, float cosMax) {
    float z = 1 - u1 * (1 - cosMax), r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniformConePdf(float cosMax) { return 1 / (2 * kPi * (1 - cosMax)); }

// Local shading frame around a unit normal.
struct Frame {
    Vec3 s, t, n;
    explicit Frame(const Vec3& normal) : n(normal) { orthonormalBasis(n, s, t); }
    Vec3 toLocal(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 toWorld(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Multiple importance sampling weights for nf samples of pdf fPdf against ng samples of pdf gPdf.
inline float balanceHeuristic(float nf, float fPdf, float ng, float gPdf) {
    float f = nf * fPdf, g = ng * gPdf;
    return f + g > 0 ? f / (f + g) : 0.0f;
}
inline float powerHeuristic(float nf, float fPdf, float ng, float gPdf) {
    float f = nf * fPdf, g = ng * gPdf;
    if (std::isinf(f * f)) return 1.0f;
    return f * f + g * g > 0 ? (f * f) / (f * f + g * g) : 0.0f;
}

}  // namespace kiln
