#include "integrators/bsdf_conductor.h"

#include "integrators/fresnel.h"

namespace kiln {
namespace {

// Metal is opaque from both sides: work above the surface.
Vec3 above(const Vec3& w, const Vec3& wo) { return wo.z < 0 ? -w : w; }

}  // namespace

Color ConductorBsdf::aovAlbedo(const Material& m, const Color&) {
    return fresnelConductor(1.0f, m.eta, m.k);
}

Color ConductorBsdf::eval(const Vec3& wo, const Vec3& wi) const {
    if (!(wo.z * wi.z > 0)) return Color(0.0f);
    Vec3 o = above(wo, wo), i = above(wi, wo);
    Vec3 h = o + i;
    if (dot(h, h) == 0) return Color(0.0f);
    h = normalize(h);
    Color F = fresnelConductor(dot(i, h), m_.eta, m_.k);
    return F * (micro_.D(h) * micro_.G(o, i) / (4 * o.z * i.z));
}

float ConductorBsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    if (!(wo.z * wi.z > 0)) return 0.0f;
    Vec3 o = above(wo, wo), i = above(wi, wo);
    Vec3 h = o + i;
    if (dot(h, h) == 0) return 0.0f;
    h = normalize(h);
    float d = dot(o, h);
    return d > 0 ? micro_.pdfVisible(o, h) / (4 * d) : 0.0f;
}

bool ConductorBsdf::sample(const Vec3& wo, float, float u1, float u2, BsdfSample& out) const {
    if (wo.z == 0) return false;
    out = BsdfSample{};
    Vec3 o = above(wo, wo);
    Vec3 h = micro_.sampleVisible(o, u1, u2);
    float oh = dot(o, h);
    if (oh <= 0) return false;
    Vec3 i = reflectAbout(o, h);
    if (i.z <= 0) return false;
    // eval() and pdf() at i, sharing D and Lambda(o): pdf = G1(o) D / (4 cos_o).
    float D = micro_.D(h), lo = micro_.lambda(o), li = micro_.lambda(i);
    Color F = fresnelConductor(dot(i, h), m_.eta, m_.k);
    out.wi = above(i, wo);
    out.pdf = D / (4 * o.z * (1 + lo));
    out.f = F * (D / (4 * o.z * i.z * (1 + lo + li)));
    return out.pdf > 0;
}

}  // namespace kiln
