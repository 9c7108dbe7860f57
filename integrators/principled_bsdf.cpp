#include "integrators/principled_bsdf.h"

#include <algorithm>

#include "integrators/fresnel.h"

namespace kiln {
namespace {

// Below this, alpha makes D a spike float cannot hold (roughness 0 is then a very sharp GGX).
constexpr float kMinAlpha = 1e-3f;
// The specular lobe is always sampled a little: a black metal still has Fresnel's grazing sheen.
constexpr float kMinSpecularChoice = 0.05f;

Microfacet ggx(float roughness) {
    Microfacet m;
    m.model = MicrofacetModel::GGX;
    float r = std::clamp(roughness, 0.0f, 1.0f);
    m.alpha = std::max(kMinAlpha, r * r);
    return m;
}

// D G2 / (4 cos_o cos_i) of a GGX lobe, both directions above the surface, h their half vector.
float specularTerm(const Microfacet& m, const Vec3& wo, const Vec3& wi, const Vec3& h) {
    return m.D(h) * m.G(wo, wi) / (4 * wo.z * wi.z);
}

// Density of wi when h is drawn among the normals visible from wo and wo reflected about it.
float reflectedPdf(const Microfacet& m, const Vec3& wo, const Vec3& h) {
    float d = dot(wo, h);
    return d > 0 ? m.pdfVisible(wo, h) / (4 * d) : 0.0f;
}

Vec3 upper(const Vec3& w, bool flip) { return flip ? Vec3(w.x, w.y, -w.z) : w; }

}  // namespace

PrincipledBsdf::PrincipledBsdf(const Material& m, const Color& baseColour, MetallicRoughness mr)
    : base_(max(baseColour, Color(0.0f))),
      metallic_(std::clamp(mr.metallic, 0.0f, 1.0f)),
      coat_(std::clamp(m.clearcoat, 0.0f, 1.0f)),
      specular_(ggx(mr.roughness)),
      coatLobe_(ggx(m.clearcoatRoughness)) {
    float r = (m.ior - 1) / (m.ior + 1);
    dielectricF0_ = std::clamp(m.specular * r * r, 0.0f, 1.0f);
}

float PrincipledBsdf::dielectricFresnel(float cosTheta) const {
    return dielectricF0_ + (1 - dielectricF0_) * schlickWeight(cosTheta);
}

PrincipledBsdf::LobeChoice PrincipledBsdf::choice(float cosO) const {
    float fo = schlickWeight(cosO);
    float fd = dielectricFresnel(cosO);
    Color fm = base_ + (Color(1.0f) - base_) * fo;
    LobeChoice c;
    c.diffuse = (1 - metallic_) * luminance(base_) * (1 - fd);
    if (diffuseDropped_) c.diffuse = 0;
    c.specular = std::max(kMinSpecularChoice, (1 - metallic_) * fd + metallic_ * luminance(fm));
    c.coat = coat_ * (0.04f + 0.96f * fo);
    float sum = c.diffuse + c.specular + c.coat;
    c.diffuse /= sum, c.specular /= sum, c.coat /= sum;
    return c;
}

Color PrincipledBsdf::evalUpper(const Vec3& wo, const Vec3& wi) const {
    if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
    Vec3 h = normalize(wo + wi);
    float fh = schlickWeight(dot(wo, h));
    float fd = dielectricFresnel(dot(wo, h));
    Color fm = base_ + (Color(1.0f) - base_) * fh;
    float s = specularTerm(specular_, wo, wi, h);
    // The diffuse lobe is what Fresnel lets through on the way in and out, at the normal: glTF's
    // (1 - F(wo.h)) reflects up to 1.7x what arrives at grazing angles (white furnace).
    float through = (1 - dielectricFresnel(wo.z)) * (1 - dielectricFresnel(wi.z));
    if (diffuseDropped_) through = 0;
    Color f = (base_ * (kInvPi * through) + Color(fd * s)) * (1 - metallic_) + fm * (s * metallic_);
    if (coat_ > 0) {
        float w = coat_ * (0.04f + 0.96f * schlickWeight(wo.z));
        f = f * (1 - w) + Color(w * specularTerm(coatLobe_, wo, wi, h));
    }
    return f;
}

float PrincipledBsdf::pdfUpper(const Vec3& wo, const Vec3& wi) const {
    if (wo.z <= 0 || wi.z <= 0) return 0.0f;
    Vec3 h = normalize(wo + wi);
    LobeChoice c = choice(wo.z);
    float p = c.diffuse * wi.z * kInvPi + c.specular * reflectedPdf(specular_, wo, h);
    if (c.coat > 0) p += c.coat * reflectedPdf(coatLobe_, wo, h);
    return p;
}

float PrincipledBsdf::enteringFraction(float cosO) const {
    float f = (1 - metallic_) * (1 - dielectricFresnel(cosO));
    return coat_ > 0 ? f * (1 - coat_ * (0.04f + 0.96f * schlickWeight(cosO))) : f;
}

Color PrincipledBsdf::eval(const Vec3& wo, const Vec3& wi) const {
    bool flip = wo.z < 0;  // two-sided: seen from below, the surface mirrors itself
    return evalUpper(upper(wo, flip), upper(wi, flip));
}

float PrincipledBsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    bool flip = wo.z < 0;
    return pdfUpper(upper(wo, flip), upper(wi, flip));
}

bool PrincipledBsdf::sample(const Vec3& woIn, float uc, float u1, float u2, BsdfSample& out) const {
    bool flip = woIn.z < 0;
    Vec3 wo = upper(woIn, flip);
    if (wo.z <= 0) return false;
    LobeChoice c = choice(wo.z);
    Vec3 wi;
    if (uc < c.diffuse) {
        wi = cosineHemisphere(u1, u2);
    } else {
        const Microfacet& lobe = uc < c.diffuse + c.specular ? specular_ : coatLobe_;
        Vec3 h = lobe.sampleVisible(wo, u1, u2);
        float d = dot(wo, h);
        if (d <= 0) return false;
        wi = reflectAbout(wo, h);
    }
    if (wi.z <= 0) return false;
    out = BsdfSample{};
    out.wi = upper(wi, flip);
    out.pdf = pdfUpper(wo, wi);
    out.f = evalUpper(wo, wi);
    return out.pdf > 0;
}

}  // namespace kiln
