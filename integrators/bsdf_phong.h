// The CS184 glossy material (MaterialKind::Glossy): a normalised Phong lobe around the mirror
// direction, reflectance (n + 2) / (2 pi) cos^n, sampled with density (n + 1) / (2 pi) cos^n.
#pragma once

#include "integrators/bsdf_sample.h"
#include "integrators/microfacet.h"
#include "renderer/geometry/material_lookup.h"

namespace kiln {

class PhongBsdf {
  public:
    static bool handles(MaterialKind k) { return k == MaterialKind::Glossy; }
    static Color aovAlbedo(const Material& m, const Color&) { return m.reflectance; }
    PhongBsdf(const Material& m, MicrofacetModel, const SurfaceInputs&) : m_(m) {}

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
};

}  // namespace kiln
