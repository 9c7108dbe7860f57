#include "integrators/ggx_albedo.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "integrators/fresnel.h"
#include "integrators/microfacet.h"

namespace kiln {
namespace {

// kCos cosines by kRough perceptual roughnesses (0 to 1), bilinear; the cosines are squares of cell
// midpoints, dense at grazing angles where E climbs steeply towards 1.
constexpr int kCos = 32, kRough = 32, kNodes = 48;

struct Tables {
    std::array<float, kCos * kRough> one{}, schlick{};
    std::array<float, kRough> oneAvg{}, schlickAvg{};
};

float alphaOf(float roughness) { return std::max(1e-3f, roughness * roughness); }

const Tables& tables() {
    static const Tables t = [] {
        Tables out;
        for (int r = 0; r < kRough; ++r) {
            float alpha = alphaOf(float(r) / (kRough - 1));
            double oneSum = 0, schlickSum = 0;
            for (int c = 0; c < kCos; ++c) {
                float x = (float(c) + 0.5f) / kCos, cosTheta = x * x;
                GgxAlbedoParts p = ggxAlbedoByQuadrature(cosTheta, alpha, kNodes);
                out.one[size_t(r * kCos + c)] = float(p.one);
                out.schlick[size_t(r * kCos + c)] = float(p.schlick);
                // 2 int E(mu) mu dmu with mu = x^2: 4 int E x^3 dx
                oneSum += p.one * x * cosTheta, schlickSum += p.schlick * x * cosTheta;
            }
            out.oneAvg[size_t(r)] = float(4 * oneSum / kCos);
            out.schlickAvg[size_t(r)] = float(4 * schlickSum / kCos);
        }
        return out;
    }();
    return t;
}

float lerp(float a, float b, float t) { return a + (b - a) * t; }

// The roughness cell and its fraction.
void roughnessCell(float roughness, int& r0, float& fr) {
    float r = std::clamp(roughness, 0.0f, 1.0f) * (kRough - 1);
    r0 = std::min(int(r), kRough - 2);
    fr = r - float(r0);
}

float lookup(const std::array<float, kCos * kRough>& t, float cosTheta, float roughness) {
    int r0;
    float fr;
    roughnessCell(roughness, r0, fr);
    float c = std::sqrt(std::clamp(cosTheta, 0.0f, 1.0f)) * kCos - 0.5f;
    int c0 = std::clamp(int(std::floor(c)), 0, kCos - 2);
    float fc = std::clamp(c - float(c0), 0.0f, 1.0f);
    auto at = [&](int r, int j) { return t[size_t(r * kCos + j)]; };
    return lerp(lerp(at(r0, c0), at(r0, c0 + 1), fc), lerp(at(r0 + 1, c0), at(r0 + 1, c0 + 1), fc),
                fr);
}

}  // namespace

// Half vectors in the measure D(h) cos(theta_h) dw_h = du dphi / (2 pi), tan^2(theta_h) =
// alpha^2 u / (1 - u); wi = reflect(wo, h) carries G2 (wo.h) / (wo.z h.z), times Schlick's weight.
GgxAlbedoParts ggxAlbedoByQuadrature(float cosTheta, float alpha, int n) {
    Microfacet m;
    m.model = MicrofacetModel::GGX;
    m.alpha = alpha;
    float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
    Vec3 wo(sinTheta, 0, cosTheta);
    GgxAlbedoParts sum;
    for (int a = 0; a < n; ++a) {
        double u = (a + 0.5) / n;
        double tan2 = double(alpha) * alpha * u / (1 - u);
        float cosH = float(1 / std::sqrt(1 + tan2)), sinH = std::sqrt(1 - cosH * cosH);
        for (int b = 0; b < 2 * n; ++b) {
            float phi = kPi * (float(b) + 0.5f) / float(n);
            Vec3 h(sinH * std::cos(phi), sinH * std::sin(phi), cosH);
            float d = dot(wo, h);
            if (d <= 0) continue;
            Vec3 wi = h * (2 * d) - wo;
            if (wi.z <= 0) continue;
            double w = m.G(wo, wi) * d / (wo.z * cosH);
            sum.one += w;
            sum.schlick += w * schlickWeight(d);
        }
    }
    sum.one /= 2.0 * n * n, sum.schlick /= 2.0 * n * n;
    return sum;
}

float ggxDielectricAlbedo(float cosTheta, float roughness, float f0) {
    const Tables& t = tables();
    return f0 * lookup(t.one, cosTheta, roughness) +
           (1 - f0) * lookup(t.schlick, cosTheta, roughness);
}

float ggxDielectricAlbedoAverage(float roughness, float f0) {
    const Tables& t = tables();
    int r0;
    float fr;
    roughnessCell(roughness, r0, fr);
    float one = lerp(t.oneAvg[size_t(r0)], t.oneAvg[size_t(r0 + 1)], fr);
    float schlick = lerp(t.schlickAvg[size_t(r0)], t.schlickAvg[size_t(r0 + 1)], fr);
    return f0 * one + (1 - f0) * schlick;
}

}  // namespace kiln
