// Microfacet distributions (Beckmann, as the CS184 scenes; GGX as an option): D, Smith Lambda, and
// sampling of the normals visible from a direction. Local frame, z = normal.
#pragma once

#include <algorithm>
#include <cmath>

#include "renderer/core/enum_names.h"
#include "renderer/core/warp.h"

namespace kiln {

enum class MicrofacetModel { Beckmann, GGX };
template <>
struct EnumNames<MicrofacetModel> {
    static constexpr std::pair<MicrofacetModel, const char*> table[] = {
        {MicrofacetModel::Beckmann, "beckmann"}, {MicrofacetModel::GGX, "ggx"}};
};

struct Microfacet {
    MicrofacetModel model = MicrofacetModel::Beckmann;
    float alpha = 0.1f;

    float D(const Vec3& h) const {
        float cos2 = h.z * h.z;
        if (cos2 <= 0) return 0;
        float tan2 = (1 - cos2) / cos2, a2 = alpha * alpha;
        if (model == MicrofacetModel::Beckmann)
            return std::exp(-tan2 / a2) / (kPi * a2 * cos2 * cos2);
        float d = a2 + tan2;
        return a2 / (kPi * cos2 * cos2 * d * d);
    }
    // Smith's Lambda, exact for both distributions (Beckmann's through erf): the visible-normal
    // sampler below draws exactly G1(wo) max(0, wo.h) D(h) / cos(theta_o), so its pdf needs this
    // G1.
    float lambda(const Vec3& w) const {
        float cos2 = w.z * w.z;
        if (cos2 <= 0) return 0;
        float tan = std::sqrt(std::max(0.0f, 1 - cos2) / cos2);
        if (tan == 0) return 0;
        if (model == MicrofacetModel::GGX)
            return 0.5f * (std::sqrt(1 + alpha * alpha * tan * tan) - 1);
        float a = 1 / (alpha * tan);
        if (a > 9) return 0;  // below float precision
        return std::max(0.0f, 0.5f * (std::erf(a) - 1) + std::exp(-a * a) / (2 * a * kSqrtPi));
    }
    float G1(const Vec3& w) const { return 1 / (1 + lambda(w)); }
    float G(const Vec3& wo, const Vec3& wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }

    // A normal visible from wo (wo.z > 0), drawn with density pdfVisible (Heitz and d'Eon 2014;
    // GGX by Heitz 2018). Against drawing h by D(h) cos(theta_h) this never picks a facet wo cannot
    // see, and a reflection's weight f cos / pdf is F G2 / G1(wo) <= F, where the old one grew as
    // 1 / cos(theta_o) at grazing angles (fireflies on rough metal silhouettes).
    Vec3 sampleVisible(const Vec3& wo, float u1, float u2) const {
        // Stretch wo to unit roughness, draw a visible slope there, unstretch.
        Vec3 ws = normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
        if (model == MicrofacetModel::GGX) return ggxVisible(ws, u1, u2);
        float sx, sy;
        beckmannVisibleSlopes(ws.z, u1, u2, sx, sy);
        float r = std::sqrt(ws.x * ws.x + ws.y * ws.y);
        float cosPhi = r > 0 ? ws.x / r : 1.0f, sinPhi = r > 0 ? ws.y / r : 0.0f;
        float tx = cosPhi * sx - sinPhi * sy, ty = sinPhi * sx + cosPhi * sy;
        return normalize(Vec3(-alpha * tx, -alpha * ty, 1.0f));
    }
    float pdfVisible(const Vec3& wo, const Vec3& h) const {
        float d = dot(wo, h);
        return d > 0 && h.z > 0 && wo.z > 0 ? G1(wo) * d * D(h) / wo.z : 0.0f;
    }

  private:
    static constexpr float kSqrtPi = 1.77245385090551602729f;

    // Heitz's GGX sampler: a point on the projected hemisphere seen from ws (unit roughness),
    // its normal unstretched.
    Vec3 ggxVisible(const Vec3& ws, float u1, float u2) const {
        float len2 = ws.x * ws.x + ws.y * ws.y;
        Vec3 t1 = len2 > 0 ? Vec3(-ws.y, ws.x, 0) / std::sqrt(len2) : Vec3(1, 0, 0);
        Vec3 t2 = cross(ws, t1);
        float r = std::sqrt(u1), phi = 2 * kPi * u2;
        float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
        float s = 0.5f * (1 + ws.z);
        p2 = (1 - s) * std::sqrt(std::max(0.0f, 1 - p1 * p1)) + s * p2;
        Vec3 n = t1 * p1 + t2 * p2 + ws * std::sqrt(std::max(0.0f, 1 - p1 * p1 - p2 * p2));
        return normalize(Vec3(alpha * n.x, alpha * n.y, std::max(1e-6f, n.z)));
    }

    // Slopes of the visible normals of a unit-roughness Beckmann surface seen at cosTheta: x by
    // inverting its marginal CDF in the erf domain (Newton steps kept inside a bisection bracket,
    // Jakob's continuous inversion as in Mitsuba and pbrt-v3), y a Gaussian.
    static void beckmannVisibleSlopes(float cosTheta, float u1, float u2, float& sx, float& sy) {
        cosTheta = std::min(cosTheta, 1.0f);
        float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
        float tanTheta = sinTheta / cosTheta, cotTheta = cosTheta / sinTheta;
        float a = -1, c = std::erf(cotTheta), u = std::max(u1, 1e-6f);
        float theta = std::acos(cosTheta);  // a fitted first guess
        float fit = 1 + theta * (-0.876f + theta * (0.4265f - 0.0594f * theta));
        float b = c - (1 + c) * std::pow(1 - u, fit);
        float tail = tanTheta * std::exp(-cotTheta * cotTheta) / kSqrtPi;
        if (!(tail >= 0)) tail = 0;  // normal incidence: 0 * exp(-inf)
        float norm = 1 / (1 + c + tail);
        for (int it = 0; it < 10; ++it) {
            if (!(b >= a && b <= c)) b = 0.5f * (a + c);  // also catches NaN
            float x = erfInv(b);
            float value = norm * (1 + b + tanTheta * std::exp(-x * x) / kSqrtPi) - u;
            if (std::abs(value) < 1e-5f) break;
            (value > 0 ? c : a) = b;
            b -= value / (norm * (1 - x * tanTheta));
        }
        sx = erfInv(b);
        sy = erfInv(2 * std::max(u2, 1e-6f) - 1);
    }
};

}  // namespace kiln
