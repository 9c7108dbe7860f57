// A smooth dielectric boundary: glass (MaterialKind::Glass) reflects with Fresnel's probability and
// refracts otherwise; refraction-only (MaterialKind::Refraction, CS184) always refracts and loses
// what total internal reflection would keep. Delta lobes; z < 0 is inside.
#pragma once

#include "integrators/bsdf_sample.h"
#include "integrators/microfacet.h"
#include "renderer/geometry/material_lookup.h"

namespace kiln {

class DielectricBsdf {
  public:
    static bool handles(MaterialKind k) {
        return k == MaterialKind::Glass || k == MaterialKind::Refraction;
    }
    static Color aovAlbedo(const Material& m, const Color&) { return m.transmittance; }
    DielectricBsdf(const Material& m, MicrofacetModel, const SurfaceInputs&)
        : m_(m), reflects_(m.kind == MaterialKind::Glass) {}

    bool isDelta() const { return true; }
    bool isBlack() const { return false; }
    bool isDiffuse() const { return false; }
    bool hasTransmission() const { return true; }
    bool usesLobeChoice() const { return reflects_; }
    Color eval(const Vec3&, const Vec3&) const { return Color(0.0f); }
    float pdf(const Vec3&, const Vec3&) const { return 0.0f; }
    bool sample(const Vec3& wo, float uc, float u1, float u2, BsdfSample& out) const;

  private:
    const Material& m_;
    bool reflects_;  // glass: Fresnel reflection too
};

}  // namespace kiln
