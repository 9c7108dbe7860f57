#include "integrators/principled_bsdf.h"

#include <algorithm>

#include "integrators/ggx_albedo.h"

namespace kiln {
namespace {

// Below this, alpha makes D a spike float cannot hold (roughness 0 is then a very sharp GGX).
constexpr float kMinAlpha = 1e-3f;
// The specular lobe is always sampled a little: a black metal still has Fresnel's grazing sheen.
constexpr float kMinSpecularChoice = 0.05f;
// Nor is the transmission lobe's share Fresnel's alone (see choice()).
constexpr float kMinTransmissionChoice = 0.1f;

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

// The half vector of a refraction from wo (above) to wi (below) with etap = n_wi / n_wo, facing
// up; false where it is degenerate or either direction sees the facet from behind.
bool refractionHalfVector(const Vec3& wo, const Vec3& wi, float etap, Vec3& h) {
    Vec3 v = wo + wi * etap;
    float len2 = dot(v, v);
    if (!(len2 > 1e-12f)) return false;
    h = v / std::sqrt(len2);
    if (h.z < 0) h = -h;
    return dot(wo, h) > 0 && dot(wi, h) < 0;
}

}  // namespace

PrincipledBsdf::PrincipledBsdf(const Material& m, const SurfaceInputs& in)
    : base_(max(in.baseColour, Color(0.0f))),
      metallic_(std::clamp(in.mr.metallic, 0.0f, 1.0f)),
      coat_(std::clamp(in.coat.weight, 0.0f, 1.0f)),
      transmission_(std::clamp(in.layers.transmission, 0.0f, 1.0f)),
      ior_(m.ior),
      thin_(!(m.thickness > 0)),
      sheen_(max(in.layers.sheenColour, Color(0.0f)) * std::clamp(m.sheen, 0.0f, 1.0f)),
      specular_(ggx(in.mr.roughness)),
      coatLobe_(ggx(in.coat.roughness)),
      sheenLobe_(in.layers.sheenRoughness) {
    const MetallicRoughness& mr = in.mr;
    float r = (m.ior - 1) / (m.ior + 1);
    float f0 = m.specular * r * r;
    dielectricF0Colour_ = Color(std::clamp(f0 * m.specularColor.x, 0.0f, 1.0f),
                                std::clamp(f0 * m.specularColor.y, 0.0f, 1.0f),
                                std::clamp(f0 * m.specularColor.z, 0.0f, 1.0f));
    dielectricF0_ = maxComponent(dielectricF0Colour_);
    sheenMax_ = maxComponent(sheen_);
    roughness_ = std::clamp(mr.roughness, 0.0f, 1.0f);
    float kept = 1 - ggxDielectricAlbedoAverage(roughness_, dielectricF0_);
    diffuseNorm_ = kept > 1e-4f ? 1 / kept : 0.0f;
}

// What the diffuse lobe keeps in and out: (1 - E(n.wo)) (1 - E(n.wi)) / (1 - E_avg), E the
// specular lobe's directional albedo, so a white base reflects all the specular lobe leaves and no
// more (Kulla and Conty's albedo scaling); at normal view 1 - E(1) ~ 1 - F0, glTF's 1 - F(wo.h)
// there. Inside a volume (seen from below a transmissive surface), Fresnel at the normal on the
// outside's side, which knows total internal reflection.
float PrincipledBsdf::diffuseWeight(float cosO, float cosI, bool inside) const {
    if (inside)
        return (1 - dielectricFresnel(outsideCos(cosO, true))) *
               (1 - dielectricFresnel(outsideCos(cosI, true)));
    return (1 - ggxDielectricAlbedo(cosO, roughness_, dielectricF0_)) *
           (1 - ggxDielectricAlbedo(cosI, roughness_, dielectricF0_)) * diffuseNorm_;
}

float PrincipledBsdf::dielectricFresnel(float cosTheta) const {
    return dielectricF0_ + (1 - dielectricF0_) * schlickWeight(cosTheta);
}

Color PrincipledBsdf::dielectricFresnelColour(float cosTheta) const {
    return dielectricF0Colour_ + (Color(1.0f) - dielectricF0Colour_) * schlickWeight(cosTheta);
}

float PrincipledBsdf::outsideCos(float cosTheta, bool inside) const {
    if (!inside) return cosTheta;
    float sin2 = (1 - cosTheta * cosTheta) * ior_ * ior_;
    return sin2 >= 1 ? -1.0f : std::sqrt(1 - sin2);
}

PrincipledBsdf::LobeChoice PrincipledBsdf::choice(float cosO, bool inside) const {
    float fo = schlickWeight(cosO);
    float fd = dielectricFresnel(outsideCos(cosO, inside));
    Color fm = base_ + (Color(1.0f) - base_) * fo;
    LobeChoice c;
    float through = diffuseDropped_ ? 0.0f : (1 - metallic_) * luminance(base_) * (1 - fd);
    c.diffuse = through * (1 - transmission_) + (sheenMax_ > 0 ? sheenMax_ : 0.0f);
    c.specular = std::max(kMinSpecularChoice, (1 - metallic_) * fd + metallic_ * luminance(fm));
    c.coat = coat_ * (0.04f + 0.96f * fo);
    // Total internal reflection about the normal still lets tilted facets refract: never 0.
    c.transmission = (1 - metallic_) * luminance(base_) * std::max(1 - fd, kMinTransmissionChoice) *
                     transmission_;
    float sum = c.diffuse + c.specular + c.coat + c.transmission;
    c.diffuse /= sum, c.specular /= sum, c.coat /= sum, c.transmission /= sum;
    return c;
}

// The sheen and the coat over what the layers below reflect (wi.z > 0, h the half vector) or
// transmit (wi.z < 0): they take their share of the energy and add their own reflection.
Color PrincipledBsdf::layersAbove(const Color& below, const Vec3& wo, const Vec3& wi,
                                  const Vec3& h) const {
    Color f = below;
    const bool reflects = wi.z > 0;
    if (sheenMax_ > 0) {
        float e = std::max(sheenLobe_.albedo(wo.z), sheenLobe_.albedo(std::abs(wi.z)));
        f = f * std::max(0.0f, 1 - sheenMax_ * e);  // the fitted V_s exceeds 1 at grazing
        if (reflects) f += sheen_ * sheenLobe_.eval(wo, wi);
    }
    if (coat_ > 0) {
        float w = coat_ * (0.04f + 0.96f * schlickWeight(wo.z));
        f = f * (1 - w);
        if (reflects) f += Color(w * specularTerm(coatLobe_, wo, wi, h));
    }
    return f;
}

Color PrincipledBsdf::evalUpper(const Vec3& wo, const Vec3& wi, bool inside) const {
    if (wo.z <= 0) return Color(0.0f);
    if (wi.z < 0) {
        if (transmission_ <= 0) return Color(0.0f);
        float t = transmissionTerm(wo, wi, inside) * transmission_ * (1 - metallic_);
        return layersAbove(base_ * t, wo, wi, Vec3(0, 0, 1));
    }
    if (wi.z <= 0) return Color(0.0f);
    Vec3 h = normalize(wo + wi);
    float fh = schlickWeight(dot(wo, h));
    Color fd = dielectricFresnelColour(outsideCos(dot(wo, h), inside));
    Color fm = base_ + (Color(1.0f) - base_) * fh;
    float s = specularTerm(specular_, wo, wi, h);
    // glTF's diffuse weight (1 - F(wo.h)) reflects up to 1.7x what arrives at grazing angles
    // (white furnace): the diffuse lobe keeps what the specular lobe leaves instead.
    float through = diffuseDropped_ ? 0.0f : diffuseWeight(wo.z, wi.z, inside);
    Color f = (base_ * (kInvPi * through * (1 - transmission_)) + fd * s) * (1 - metallic_) +
              fm * (s * metallic_);
    return layersAbove(f, wo, wi, h);
}

// The dielectric's transmission, white, for wo above and wi below: thin-walled, the reflection
// about the same half vector mirrored through the surface; else refracted (Walter et al. 2007,
// as pbrt-v4's DielectricBxDF: D G2 (1 - F) |wi.h wo.h| / (cos_i cos_o (wi.h + wo.h / eta)^2),
// over eta^2 for radiance).
float PrincipledBsdf::transmissionTerm(const Vec3& wo, const Vec3& wi, bool inside) const {
    if (thin_) {
        Vec3 wr = upper(wi, true);
        Vec3 h = normalize(wo + wr);
        return (1 - dielectricFresnel(dot(wo, h))) * specularTerm(specular_, wo, wr, h);
    }
    float etap = inside ? 1 / ior_ : ior_;
    Vec3 h;
    if (!refractionHalfVector(wo, wi, etap, h)) return 0.0f;
    float dO = dot(wo, h), dI = dot(wi, h), denom = dI + dO / etap;
    float fresnel = dielectricFresnel(outsideCos(dO, inside));
    return specular_.D(h) * specular_.G(wo, wi) * (1 - fresnel) *
           std::abs(dI * dO / (denom * denom * wi.z * wo.z)) / (etap * etap);
}

float PrincipledBsdf::transmissionPdf(const Vec3& wo, const Vec3& wi, bool inside) const {
    if (thin_) {
        Vec3 wr = upper(wi, true);
        return reflectedPdf(specular_, wo, normalize(wo + wr));
    }
    float etap = inside ? 1 / ior_ : ior_;
    Vec3 h;
    if (!refractionHalfVector(wo, wi, etap, h)) return 0.0f;
    float dO = dot(wo, h), dI = dot(wi, h), denom = dI + dO / etap;
    return specular_.pdfVisible(wo, h) * std::abs(dI) / (denom * denom);
}

bool PrincipledBsdf::sampleTransmission(const Vec3& wo, float u1, float u2, bool inside,
                                        Vec3& wi) const {
    Vec3 h = specular_.sampleVisible(wo, u1, u2);
    if (dot(wo, h) <= 0) return false;
    if (thin_) {
        wi = upper(reflectAbout(wo, h), true);
        return wi.z < 0;
    }
    return refract(wo, h, inside ? 1 / ior_ : ior_, wi) && wi.z < 0;
}

float PrincipledBsdf::pdfUpper(const Vec3& wo, const Vec3& wi, bool inside) const {
    if (wo.z <= 0) return 0.0f;
    if (wi.z < 0) {
        if (transmission_ <= 0) return 0.0f;
        return choice(wo.z, inside).transmission * transmissionPdf(wo, wi, inside);
    }
    if (wi.z <= 0) return 0.0f;
    Vec3 h = normalize(wo + wi);
    LobeChoice c = choice(wo.z, inside);
    float p = c.diffuse * wi.z * kInvPi + c.specular * reflectedPdf(specular_, wo, h);
    if (c.coat > 0) p += c.coat * reflectedPdf(coatLobe_, wo, h);
    return p;
}

// The diffuse lobe's albedo for a white base (diffuseWeight integrated over wi), under the sheen
// and the coat as layersAbove weighs them from wo.
float PrincipledBsdf::enteringFraction(float cosO) const {
    float f = (1 - metallic_) * (1 - transmission_) *
              (1 - ggxDielectricAlbedo(cosO, roughness_, dielectricF0_));
    if (sheenMax_ > 0) f *= std::max(0.0f, 1 - sheenMax_ * sheenLobe_.albedo(cosO));
    return coat_ > 0 ? f * (1 - coat_ * (0.04f + 0.96f * schlickWeight(cosO))) : f;
}

Color PrincipledBsdf::eval(const Vec3& wo, const Vec3& wi) const {
    bool flip = wo.z < 0;  // seen from below: the surface mirrors itself, or wo is inside
    return evalUpper(upper(wo, flip), upper(wi, flip), flip && refracts());
}

float PrincipledBsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    bool flip = wo.z < 0;
    return pdfUpper(upper(wo, flip), upper(wi, flip), flip && refracts());
}

bool PrincipledBsdf::sample(const Vec3& woIn, float uc, float u1, float u2, BsdfSample& out) const {
    bool flip = woIn.z < 0, inside = flip && refracts();
    Vec3 wo = upper(woIn, flip);
    if (wo.z <= 0) return false;
    LobeChoice c = choice(wo.z, inside);
    Vec3 wi;
    const bool transmits = c.transmission > 0 && uc >= 1 - c.transmission;
    if (transmits) {
        if (!sampleTransmission(wo, u1, u2, inside, wi)) return false;
    } else if (uc < c.diffuse) {
        wi = cosineHemisphere(u1, u2);
    } else {
        const Microfacet& lobe = uc < c.diffuse + c.specular ? specular_ : coatLobe_;
        Vec3 h = lobe.sampleVisible(wo, u1, u2);
        float d = dot(wo, h);
        if (d <= 0) return false;
        wi = reflectAbout(wo, h);
    }
    if (!transmits && wi.z <= 0) return false;
    out = BsdfSample{};
    out.wi = upper(wi, flip);
    out.transmission = transmits;
    out.pdf = pdfUpper(wo, wi, inside);
    out.f = evalUpper(wo, wi, inside);
    return out.pdf > 0;
}

}  // namespace kiln
