// A rough conductor (MaterialKind::Microfacet, CS184): Beckmann or GGX microfacets with the
// conductor's complex Fresnel, visible normals sampled. Opaque from both sides.
#pragma once

#include <algorithm>

#include "integrators/bsdf_sample.h"
#include "integrators/microfacet.h"
#include "renderer/geometry/material_lookup.h"

namespace kiln {

class ConductorBsdf {
  public:
    static bool handles(MaterialKind k) { return k == MaterialKind::Microfacet; }
    static Color aovAlbedo(const Material& m, const Color&);  // F at normal incidence
    ConductorBsdf(const Material& m, MicrofacetModel model, const SurfaceInputs&) : m_(m) {
        micro_.model = model;
        micro_.alpha = std::max(1e-4f, m.alpha);
    }

    bool isDelta() const { return false; }
    bool isBlack() const { return false; }
    bool isDiffuse() const { return false; }
    bool hasTransmission() const { return false; }
    bool usesLobeChoice() const { return false; }
    Color eval(const Vec3& wo, const Vec3& wi) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    bool sample(const Vec3& wo, float uc, float u1, float u2, BsdfSample& out) const;

  private:
    const Material& m_;
    Microfacet micro_;
};

}  // namespace kiln
