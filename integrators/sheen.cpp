#include "integrators/sheen.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace kiln {
namespace {

float lerp(float a, float b, float t) { return a + (b - a) * t; }

// The albedo table: kRough perceptual roughnesses from kMinRoughness to 1 by kCos cosines (cell
// midpoints), looked up bilinearly.
constexpr int kRough = 16, kCos = 32;
using AlbedoTable = std::array<float, kRough * kCos>;

float roughnessAt(int k) {
    return SheenLobe::kMinRoughness + (1 - SheenLobe::kMinRoughness) * float(k) / (kRough - 1);
}

const AlbedoTable& albedoTable() {
    static const AlbedoTable table = [] {
        AlbedoTable t{};
        for (int k = 0; k < kRough; ++k) {
            SheenLobe lobe(roughnessAt(k));
            for (int c = 0; c < kCos; ++c)
                t[size_t(k * kCos + c)] =
                    float(sheenAlbedoByHalfVectors(lobe, (float(c) + 0.5f) / kCos, 48));
        }
        return t;
    }();
    return table;
}

}  // namespace

SheenLobe::SheenLobe(float roughness)
    : roughness_(std::clamp(roughness, kMinRoughness, 1.0f)), alpha_(roughness_ * roughness_) {
    float t = (1 - alpha_) * (1 - alpha_);
    fitA_ = lerp(21.5473f, 25.3245f, t);
    fitB_ = lerp(3.82987f, 3.32435f, t);
    fitC_ = lerp(0.19823f, 0.16801f, t);
    fitD_ = lerp(-1.97760f, -1.27393f, t);
    fitE_ = lerp(-4.32054f, -4.85967f, t);
}

float SheenLobe::fit(float x) const {
    return fitA_ / (1 + fitB_ * std::pow(x, fitC_)) + fitD_ * x + fitE_;
}

// Estevez-Kulla's Lambda, exp of the fit below cos 0.5 and its reflection above.
float SheenLobe::lambda(float cosTheta) const {
    float c = std::abs(cosTheta);
    return c < 0.5f ? std::exp(fit(c)) : std::exp(2 * fit(0.5f) - fit(1 - c));
}

float SheenLobe::distribution(const Vec3& h) const {
    float sin2 = std::max(0.0f, 1 - h.z * h.z);
    float invAlpha = 1 / alpha_;
    return (2 + invAlpha) * std::pow(sin2, 0.5f * invAlpha) / (2 * kPi);
}

float SheenLobe::eval(const Vec3& wo, const Vec3& wi) const {
    if (wo.z <= 0 || wi.z <= 0) return 0.0f;
    float v = 1 / ((1 + lambda(wo.z) + lambda(wi.z)) * 4 * wo.z * wi.z);
    return distribution(normalize(wo + wi)) * v;
}

float SheenLobe::albedo(float cosTheta) const {
    const AlbedoTable& t = albedoTable();
    float r = (roughness_ - kMinRoughness) / (1 - kMinRoughness) * (kRough - 1);
    float c = std::clamp(cosTheta, 0.0f, 1.0f) * kCos - 0.5f;
    int r0 = std::clamp(int(r), 0, kRough - 2), c0 = std::clamp(int(std::floor(c)), 0, kCos - 2);
    float fr = std::clamp(r - float(r0), 0.0f, 1.0f), fc = std::clamp(c - float(c0), 0.0f, 1.0f);
    auto at = [&](int k, int j) { return t[size_t(k * kCos + j)]; };
    return lerp(lerp(at(r0, c0), at(r0, c0 + 1), fc), lerp(at(r0 + 1, c0), at(r0 + 1, c0 + 1), fc),
                fr);
}

// Midpoint quadrature in (cos^2, phi): f cos dw = du dphi / 2 with u = cos^2 of wi.
double sheenAlbedoByQuadrature(const SheenLobe& lobe, float cosTheta, int n) {
    float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
    Vec3 wo(sinTheta, 0, cosTheta);
    double sum = 0;
    for (int a = 0; a < n; ++a) {
        float u = (float(a) + 0.5f) / float(n);
        float ci = std::sqrt(u), si = std::sqrt(1 - u);
        for (int b = 0; b < 2 * n; ++b) {
            float phi = kPi * (float(b) + 0.5f) / float(2 * n);  // half the circle: symmetric
            sum += lobe.eval(wo, Vec3(si * std::cos(phi), si * std::sin(phi), ci));
        }
    }
    return sum * kPi / (2.0 * n * n);  // du = 1 / n, dphi = pi / 2n, both halves, the 1 / 2
}

// Midpoint quadrature over half vectors in the measure D(h) cos(theta_h) dw_h, where the Charlie
// D's grazing peak is flat: sin(theta_h) = u^(1 / (2 + 1 / alpha)) with u and phi uniform, and
// wi = reflect(wo, h) carries f cos_i 4 (wo.h) / (D cos_h) = (wo.h) / (cos_o cos_h (1 + L_o +
// L_i)).
double sheenAlbedoByHalfVectors(const SheenLobe& lobe, float cosTheta, int n) {
    float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
    Vec3 wo(sinTheta, 0, cosTheta);
    float exponent = 1 / (2 + 1 / (lobe.roughness() * lobe.roughness()));
    double sum = 0;
    for (int a = 0; a < n; ++a) {
        float sh = std::pow((float(a) + 0.5f) / float(n), exponent);
        float ch = std::sqrt(std::max(0.0f, 1 - sh * sh));
        for (int b = 0; b < 2 * n; ++b) {
            float phi = kPi * (float(b) + 0.5f) / float(2 * n);
            Vec3 h(sh * std::cos(phi), sh * std::sin(phi), ch);
            float d = dot(wo, h);
            Vec3 wi = h * (2 * d) - wo;
            if (d <= 0 || wi.z <= 0 || ch <= 0) continue;
            float density = lobe.eval(wo, wi) * wi.z * 4 * d;  // f cos / (dw_h / dw_i)
            sum += density / (lobe.distribution(h) * ch);
        }
    }
    return sum / (2.0 * n * n);  // the measure integrates to 1 over the hemisphere of h
}

}  // namespace kiln
