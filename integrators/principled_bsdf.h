// The principled material (glTF 2.0 metallic-roughness, KHR_materials_specular and _clearcoat), as
// the glTF specification's appendix B writes it but for the diffuse lobe's Fresnel weight (at the
// normal, in and out: the spec's (1 - F_d(wo.h)) gains energy at grazing angles), in the local
// shading frame (z = normal):
//   f = (1 - m) [ (1 - F_d(n.wo)) (1 - F_d(n.wi)) base / pi + F_d S ] + m F_m S,   then the coat:
//   f' = (1 - c F_c(n.wo)) f + c F_c(n.wo) S_coat
// S = D G2 / (4 |n.wo| |n.wi|), GGX D with alpha = roughness^2 and the height-correlated Smith G2 =
// 1 / (1 + Lambda(wo) + Lambda(wi)); every F is Schlick's at the half vector (F_d: F0 = specular *
// ((ior - 1) / (ior + 1))^2, 0.04 at ior 1.5; F_m: F0 = base colour), the coat's at the normal
// (F0 0.04). Opaque and two-sided. Sampling picks one lobe (diffuse: cosine; specular and coat:
// D cos of the half vector) with probabilities from wo alone; pdf() is the mixture's density (one-
// sample MIS over the lobes), so sample, pdf and eval agree (tests/test_principled.cpp).
#pragma once

#include "integrators/bsdf_sample.h"
#include "integrators/microfacet.h"
#include "renderer/geometry/material_lookup.h"
#include "scene/scene.h"

namespace kiln {

class PrincipledBsdf {
  public:
    static bool handles(MaterialKind k) { return k == MaterialKind::Principled; }
    static Color aovAlbedo(const Material&, const Color& baseColour) { return baseColour; }
    // in: the material's base colour, metallic and roughness at this point (textures, vertex
    // colours: material_lookup.h), else its factors.
    PrincipledBsdf(const Material& material, MicrofacetModel, const SurfaceInputs& in)
        : PrincipledBsdf(material, in.baseColour, in.mr) {}
    PrincipledBsdf(const Material& material, const Color& baseColour)
        : PrincipledBsdf(material, baseColour, MetallicRoughness::of(material)) {}
    PrincipledBsdf(const Material& material, const Color& baseColour, MetallicRoughness mr);

    bool isDelta() const { return false; }
    bool isBlack() const { return false; }
    bool isDiffuse() const { return false; }
    bool hasTransmission() const { return false; }
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
        float diffuse = 0, specular = 0, coat = 0;  // probabilities, summing to 1
    };
    LobeChoice choice(float cosO) const;  // wo on the upper side
    Color evalUpper(const Vec3& wo, const Vec3& wi) const;
    float pdfUpper(const Vec3& wo, const Vec3& wi) const;
    float dielectricFresnel(float cosTheta) const;  // Schlick with the dielectric F0

    Color base_{0.0f};
    float metallic_ = 0, dielectricF0_ = 0.04f, coat_ = 0;
    bool diffuseDropped_ = false;
    Microfacet specular_, coatLobe_;
};

// Schlick's Fresnel approximation: F0 + (1 - F0) (1 - cos)^5.
inline float schlickWeight(float cosTheta) {
    float m = std::clamp(1 - cosTheta, 0.0f, 1.0f), m2 = m * m;
    return m2 * m2 * m;
}

}  // namespace kiln
