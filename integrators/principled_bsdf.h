// The principled material (glTF 2.0 metallic-roughness with KHR_materials_specular, _clearcoat,
// _sheen, _transmission and _volume's thin/volume switch), as the glTF specification's appendix B
// writes it but for the diffuse lobe's weight (the spec's (1 - F_d(wo.h)) gains energy at grazing
// angles: kiln's keeps what the specular lobe leaves, integrators/ggx_albedo.h), in the local
// shading frame (z = normal):
//   f = (1 - m) [ (1 - t) W base / pi + F_d S + t base T ] + m F_m S,
//   W = (1 - E(n.wo)) (1 - E(n.wi)) / (1 - E_avg), E the F_d S lobe's directional albedo,
//   then the sheen: f' = (1 - s E_s) f + s C_s D_s V_s,  then the coat:
//   f'' = (1 - c F_c(n.wo)) f' + c F_c(n.wo) S_coat
// S = D G2 / (4 |n.wo| |n.wi|), GGX D with alpha = roughness^2 and the height-correlated Smith G2 =
// 1 / (1 + Lambda(wo) + Lambda(wi)); every F is Schlick's at the half vector (F_d: F0 = specular *
// specular colour * ((ior - 1) / (ior + 1))^2, 0.04 at ior 1.5; the diffuse weights take its
// largest channel; F_m: F0 = base colour), the coat's at the normal (F0 0.04). T is the rough
// dielectric transmission (Walter et al. 2007) through the same GGX with weight 1 - F_d: refracting
// through ior with radiance scaled by 1 / eta^2 where thickness > 0 (the surface bounds a volume:
// seen from below, wo is inside, F_d is taken on the outside's side and is 1 under total internal
// reflection, and W is Fresnel's at the normal, in and out), straight through (the reflection
// mirrored to the other side) where thickness is 0 (thin-walled). The sheen (sheen.h: Charlie D_s,
// Estevez-Kulla V_s, s = sheen * max(C_s)) takes s E_s = s max(E_s(n.wo), E_s(n.wi)) of the energy
// below it (glTF's albedo scaling).
// Without transmission the surface is opaque and two-sided: seen from below it mirrors itself.
// Sampling picks one lobe (diffuse and sheen: cosine; specular and coat: visible normals;
// transmission: visible normals, refracted) with probabilities from wo alone; pdf() is the
// mixture's density (one-sample MIS over the lobes), so sample, pdf and eval agree
// (tests/test_principled.cpp, tests/test_principled_lobes.cpp).
#pragma once

#include "integrators/bsdf_sample.h"
#include "integrators/fresnel.h"
#include "integrators/microfacet.h"
#include "integrators/sheen.h"
#include "renderer/geometry/material_lookup.h"
#include "scene/scene.h"

namespace kiln {

class PrincipledBsdf {
  public:
    static bool handles(MaterialKind k) { return k == MaterialKind::Principled; }
    static Color aovAlbedo(const Material&, const Color& baseColour) { return baseColour; }
    // in: the material's base colour, metallic, roughness, coat, transmission and sheen at this
    // point (textures, vertex colours: material_lookup.h), else its factors.
    PrincipledBsdf(const Material& material, MicrofacetModel, const SurfaceInputs& in)
        : PrincipledBsdf(material, in) {}
    PrincipledBsdf(const Material& material, const Color& baseColour)
        : PrincipledBsdf(material, baseColour, MetallicRoughness::of(material)) {}
    PrincipledBsdf(const Material& material, const Color& baseColour, MetallicRoughness mr)
        : PrincipledBsdf(material, {baseColour, mr, Coat::of(material), Layers::of(material)}) {}
    PrincipledBsdf(const Material& material, const SurfaceInputs& in);

    bool isDelta() const { return false; }
    bool isBlack() const { return false; }
    bool isDiffuse() const { return false; }
    bool hasTransmission() const { return transmission_ > 0; }
    bool usesLobeChoice() const { return true; }
    Color eval(const Vec3& wo, const Vec3& wi) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    bool sample(const Vec3& wo, float uc, float u1, float u2, BsdfSample& out) const;

    // Subsurface scattering takes the diffuse lobe's place (integrators/subsurface.h): the
    // surface without it, and the fraction of light from wo (cosine cosO) that passes the coat and
    // the specular layer into the diffuse (or subsurface) lobe.
    void dropDiffuse() { diffuseDropped_ = true; }
    float enteringFraction(float cosO) const;

  private:
    struct LobeChoice {
        float diffuse = 0, specular = 0, coat = 0, transmission = 0;  // summing to 1
    };
    // Seen from below, whether wo is inside a volume the surface bounds (else it mirrors itself).
    bool refracts() const { return transmission_ > 0 && !thin_; }
    LobeChoice choice(float cosO, bool inside) const;  // wo on the upper side
    Color evalUpper(const Vec3& wo, const Vec3& wi, bool inside) const;
    float pdfUpper(const Vec3& wo, const Vec3& wi, bool inside) const;
    float transmissionTerm(const Vec3& wo, const Vec3& wi, bool inside) const;
    float transmissionPdf(const Vec3& wo, const Vec3& wi, bool inside) const;
    bool sampleTransmission(const Vec3& wo, float u1, float u2, bool inside, Vec3& wi) const;
    Color layersAbove(const Color& below, const Vec3& wo, const Vec3& wi, const Vec3& h) const;
    // The cosine on the outside's side for cosTheta on wo's, -1 under total internal reflection.
    float outsideCos(float cosTheta, bool inside) const;
    float diffuseWeight(float cosO, float cosI, bool inside) const;
    float dielectricFresnel(float cosTheta) const;  // Schlick with the largest dielectric F0
    Color dielectricFresnelColour(float cosTheta) const;

    Color base_{0.0f}, dielectricF0Colour_{0.04f};
    float metallic_ = 0, dielectricF0_ = 0.04f, coat_ = 0;
    float transmission_ = 0, ior_ = 1.5f;
    float roughness_ = 0.5f, diffuseNorm_ = 1;  // the diffuse weight's table input, 1 / (1 - E_avg)
    bool thin_ = true;
    Color sheen_{0.0f};  // sheen weight times colour
    float sheenMax_ = 0;
    bool diffuseDropped_ = false;
    Microfacet specular_, coatLobe_;
    SheenLobe sheenLobe_;
};

}  // namespace kiln
