// BSDFs of every material kind, evaluated in the local shading frame (z = the shading normal as the
// file orients it, so z < 0 is "inside" for dielectrics). Sampling, pdf and evaluation agree
// (chi-square tests).
#pragma once

#include "integrators/bsdf_sample.h"
#include "integrators/microfacet.h"
#include "integrators/principled_bsdf.h"
#include "renderer/core/warp.h"
#include "renderer/geometry/interaction.h"
#include "scene/scene.h"

namespace kiln {

class Bsdf {
  public:
    explicit Bsdf(const Material& material, MicrofacetModel model = MicrofacetModel::Beckmann)
        : Bsdf(material, model, material.albedo) {}
    // albedo: the Lambertian colour at this point (textures, vertex colours: surface_albedo.h);
    // mr: a principled material's metallic and roughness there (else its factors).
    Bsdf(const Material& material, MicrofacetModel model, const Color& albedo)
        : Bsdf(material, model, albedo, MetallicRoughness::of(material)) {}
    Bsdf(const Material& material, MicrofacetModel model, const Color& albedo,
         MetallicRoughness mr);
    bool isDelta() const { return delta_; }
    bool isBlack() const { return m_.kind == MaterialKind::Emission; }
    bool isDiffuse() const { return m_.kind == MaterialKind::Lambertian; }
    // sample() reads uc (a lobe to choose: glass, principled); else the caller skips drawing it.
    bool usesLobeChoice() const {
        return m_.kind == MaterialKind::Glass || m_.kind == MaterialKind::Principled;
    }
    bool hasTransmission() const;

    Color eval(const Vec3& wo, const Vec3& wi) const;  // local directions; 0 for delta lobes
    float pdf(const Vec3& wo, const Vec3& wi) const;   // 0 for delta lobes
    // uc picks a lobe (glass), (u1, u2) the direction. False when no direction is produced.
    bool sample(const Vec3& wo, float uc, float u1, float u2, BsdfSample& out) const;

  private:
    const Material& m_;
    Color albedo_;
    Microfacet micro_;
    PrincipledBsdf principled_;  // MaterialKind::Principled only
    bool delta_;
};

// The frame a vertex shades in, seen from woWorld. A shading normal bent so far that the viewer is
// below its tangent plane would make the surface black: such a vertex shades with the geometric
// normal instead (on the stored normal's side).
inline Frame shadingFrame(const SurfaceInteraction& si, const Vec3& woWorld) {
    if (dot(woWorld, si.ns) > 0) return Frame(si.nsStored);
    return Frame(dot(si.ns, si.nsStored) >= 0 ? si.ng : -si.ng);
}

}  // namespace kiln
