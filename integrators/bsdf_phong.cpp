#include "integrators/bsdf_phong.h"

#include <cmath>

namespace kiln {
namespace {

// Density of the lobe around the mirror direction r: (n+1)/(2 pi) cos^n.
float phongPdf(const Vec3& r, const Vec3& wi, float n) {
    float c = dot(r, wi);
    return c > 0 ? (n + 1) / (2 * kPi) * std::pow(c, n) : 0.0f;
}

}  // namespace

Color PhongBsdf::eval(const Vec3& wo, const Vec3& wi) const {
    if (!(wo.z * wi.z > 0)) return Color(0.0f);
    float n = m_.shininess, c = dot(reflectLocal(wo), wi);
    return c > 0 ? m_.reflectance * ((n + 2) / (2 * kPi) * std::pow(c, n)) : Color(0.0f);
}

float PhongBsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    return wo.z * wi.z > 0 ? phongPdf(reflectLocal(wo), wi, m_.shininess) : 0.0f;
}

bool PhongBsdf::sample(const Vec3& wo, float, float u1, float u2, BsdfSample& out) const {
    if (wo.z == 0) return false;
    out = BsdfSample{};
    // A direction around the mirror direction with density (n+1)/(2 pi) cos^n.
    Vec3 r = reflectLocal(wo);
    float n = m_.shininess;
    float cosA = std::pow(u1, 1 / (n + 1)), sinA = std::sqrt(std::max(0.0f, 1 - cosA * cosA));
    float phi = 2 * kPi * u2;
    Frame frame(r);
    Vec3 wi = frame.toWorld(Vec3(sinA * std::cos(phi), sinA * std::sin(phi), cosA));
    if (!(wo.z * wi.z > 0)) return false;
    out.wi = wi;
    out.pdf = pdf(wo, wi);
    out.f = eval(wo, wi);
    return out.pdf > 0;
}

}  // namespace kiln
