#include "integrators/bsdf.h"

#include "integrators/fresnel.h"

namespace kiln {
namespace {

bool sameHemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0; }
Vec3 reflectLocal(const Vec3& wo) { return {-wo.x, -wo.y, wo.z}; }
Vec3 reflectAbout(const Vec3& w, const Vec3& n) { return n * (2 * dot(w, n)) - w; }

// Phong lobe of the glossy material, around the mirror direction r: pdf (n+1)/(2 pi) cos^n.
float phongPdf(const Vec3& r, const Vec3& wi, float n) {
    float c = dot(r, wi);
    return c > 0 ? (n + 1) / (2 * kPi) * std::pow(c, n) : 0.0f;
}

}  // namespace

Bsdf::Bsdf(const Material& material, MicrofacetModel model, const Color& albedo,
           MetallicRoughness mr)
    : m_(material), albedo_(albedo) {
    micro_.model = model;
    micro_.alpha = std::max(1e-4f, material.alpha);
    delta_ = material.kind == MaterialKind::Mirror || material.kind == MaterialKind::Glass ||
             material.kind == MaterialKind::Refraction;
    if (material.kind == MaterialKind::Principled)
        principled_ = PrincipledBsdf(material, albedo, mr);
}

bool Bsdf::hasTransmission() const {
    return m_.kind == MaterialKind::Glass || m_.kind == MaterialKind::Refraction;
}

Color Bsdf::eval(const Vec3& wo, const Vec3& wi) const {
    switch (m_.kind) {
        case MaterialKind::Lambertian:
            return sameHemisphere(wo, wi) ? albedo_ * kInvPi : Color(0.0f);
        case MaterialKind::Microfacet: {
            if (!sameHemisphere(wo, wi)) return Color(0.0f);
            Vec3 o = wo.z < 0 ? -wo : wo,
                 i = wo.z < 0 ? -wi : wi;  // metal is opaque from both sides
            Vec3 h = o + i;
            if (dot(h, h) == 0) return Color(0.0f);
            h = normalize(h);
            Color F = fresnelConductor(dot(i, h), m_.eta, m_.k);
            return F * (micro_.D(h) * micro_.G(o, i) / (4 * o.z * i.z));
        }
        case MaterialKind::Glossy: {
            if (!sameHemisphere(wo, wi)) return Color(0.0f);
            float n = m_.shininess, c = dot(reflectLocal(wo), wi);
            return c > 0 ? m_.reflectance * ((n + 2) / (2 * kPi) * std::pow(c, n)) : Color(0.0f);
        }
        case MaterialKind::Principled:
            return principled_.eval(wo, wi);
        default:
            return Color(0.0f);  // delta lobes and emission
    }
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    switch (m_.kind) {
        case MaterialKind::Lambertian:
            return sameHemisphere(wo, wi) ? std::abs(wi.z) * kInvPi : 0.0f;
        case MaterialKind::Microfacet: {
            if (!sameHemisphere(wo, wi)) return 0.0f;
            Vec3 o = wo.z < 0 ? -wo : wo, i = wo.z < 0 ? -wi : wi;
            Vec3 h = o + i;
            if (dot(h, h) == 0) return 0.0f;
            h = normalize(h);
            float d = dot(o, h);
            return d > 0 ? micro_.pdfVisible(o, h) / (4 * d) : 0.0f;
        }
        case MaterialKind::Glossy:
            return sameHemisphere(wo, wi) ? phongPdf(reflectLocal(wo), wi, m_.shininess) : 0.0f;
        case MaterialKind::Principled:
            return principled_.pdf(wo, wi);
        default:
            return 0.0f;
    }
}

bool Bsdf::sample(const Vec3& wo, float uc, float u1, float u2, BsdfSample& out) const {
    if (wo.z == 0) return false;
    out = BsdfSample{};
    switch (m_.kind) {
        case MaterialKind::Lambertian: {
            Vec3 wi = cosineHemisphere(u1, u2);
            if (wo.z < 0) wi.z = -wi.z;
            out.wi = wi;
            out.pdf = pdf(wo, wi);
            out.f = eval(wo, wi);
            return out.pdf > 0;
        }
        case MaterialKind::Microfacet: {
            // Metal is opaque from both sides: work above the surface, flip back at the end.
            Vec3 o = wo.z < 0 ? -wo : wo;
            Vec3 h = micro_.sampleVisible(o, u1, u2);
            float oh = dot(o, h);
            if (oh <= 0) return false;
            Vec3 i = reflectAbout(o, h);
            if (i.z <= 0) return false;
            // eval() and pdf() at i, sharing D and Lambda(o): pdf = G1(o) D / (4 cos_o).
            float D = micro_.D(h), lo = micro_.lambda(o), li = micro_.lambda(i);
            Color F = fresnelConductor(dot(i, h), m_.eta, m_.k);
            out.wi = wo.z < 0 ? -i : i;
            out.pdf = D / (4 * o.z * (1 + lo));
            out.f = F * (D / (4 * o.z * i.z * (1 + lo + li)));
            return out.pdf > 0;
        }
        case MaterialKind::Glossy: {
            // Direction around the mirror direction with density (n+1)/(2 pi) cos^n.
            Vec3 r = reflectLocal(wo);
            float n = m_.shininess;
            float cosA = std::pow(u1, 1 / (n + 1)),
                  sinA = std::sqrt(std::max(0.0f, 1 - cosA * cosA));
            float phi = 2 * kPi * u2;
            Frame frame(r);
            Vec3 wi = frame.toWorld(Vec3(sinA * std::cos(phi), sinA * std::sin(phi), cosA));
            if (!sameHemisphere(wo, wi)) return false;
            out.wi = wi;
            out.pdf = pdf(wo, wi);
            out.f = eval(wo, wi);
            return out.pdf > 0;
        }
        case MaterialKind::Mirror: {
            out.wi = reflectLocal(wo);
            out.delta = true;
            out.pdf = 1;
            out.f = m_.reflectance / std::abs(out.wi.z);
            return true;
        }
        case MaterialKind::Glass:
        case MaterialKind::Refraction: {
            // eta = n_t / n_i: entering from outside (wo.z > 0) goes into the material.
            bool entering = wo.z > 0;
            float eta = entering ? m_.ior : 1 / m_.ior;
            float F = fresnelDielectric(wo.z, m_.ior);
            bool glass = m_.kind == MaterialKind::Glass;
            Vec3 n(0, 0, entering ? 1.0f : -1.0f);
            Vec3 wt;
            bool canRefract = refract(wo, n, eta, wt);
            out.delta = true;
            if (glass && (!canRefract || uc < F)) {
                // Reflection chosen with probability F (or always, under total internal
                // reflection).
                out.wi = reflectLocal(wo);
                out.pdf = canRefract ? F : 1.0f;
                out.f = m_.reflectance * (canRefract ? F : 1.0f) / std::abs(out.wi.z);
                return true;
            }
            if (!canRefract)
                return false;  // refraction-only material: total internal reflection absorbs
            out.wi = wt;
            out.transmission = true;
            float T = glass ? 1 - F : 1.0f;
            out.pdf = glass ? 1 - F : 1.0f;
            // Radiance is compressed by eta^2 crossing into the denser medium.
            out.f = m_.transmittance * (T / (eta * eta)) / std::abs(wt.z);
            return true;
        }
        case MaterialKind::Principled:
            return principled_.sample(wo, uc, u1, u2, out);
        case MaterialKind::Emission:
            return false;
    }
    return false;
}

}  // namespace kiln
