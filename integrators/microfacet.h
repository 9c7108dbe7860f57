// Microfacet distributions (Beckmann, as the CS184 scenes; GGX as an option): D, Smith Lambda, and
// sampling of half vectors proportional to D(h) cos(theta_h). Local frame, z = normal.
#pragma once

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
    float lambda(const Vec3& w) const {
        float cos2 = w.z * w.z;
        if (cos2 <= 0) return 0;
        float tan = std::sqrt(std::max(0.0f, 1 - cos2) / cos2);
        if (tan == 0) return 0;
        if (model == MicrofacetModel::GGX)
            return 0.5f * (std::sqrt(1 + alpha * alpha * tan * tan) - 1);
        // Beckmann: Walter et al.'s rational approximation of Lambda.
        float a = 1 / (alpha * tan);
        if (a >= 1.6f) return 0;
        return (1 - 1.259f * a + 0.396f * a * a) / (3.535f * a + 2.181f * a * a);
    }
    float G(const Vec3& wo, const Vec3& wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }

    // h with density D(h) |cos theta_h| over solid angle.
    Vec3 sampleH(float u1, float u2) const {
        float tan2;
        if (model == MicrofacetModel::Beckmann)
            tan2 = -alpha * alpha * std::log(std::max(1e-12f, 1 - u1));
        else
            tan2 = alpha * alpha * u1 / std::max(1e-12f, 1 - u1);
        float cosT = 1 / std::sqrt(1 + tan2), sinT = std::sqrt(std::max(0.0f, 1 - cosT * cosT));
        float phi = 2 * kPi * u2;
        return {sinT * std::cos(phi), sinT * std::sin(phi), cosT};
    }
    float pdfH(const Vec3& h) const { return D(h) * std::abs(h.z); }
};

}  // namespace kiln
