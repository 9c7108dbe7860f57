// A perfect mirror (MaterialKind::Mirror): one delta lobe, reflectance / cos.
#pragma once

#include "integrators/bsdf_sample.h"
#include "integrators/microfacet.h"
#include "renderer/geometry/material_lookup.h"

namespace kiln {

class MirrorBsdf {
  public:
    static bool handles(MaterialKind k) { return k == MaterialKind::Mirror; }
    static Color aovAlbedo(const Material& m, const Color&) { return m.reflectance; }
    MirrorBsdf(const Material& m, MicrofacetModel, const SurfaceInputs&) : m_(m) {}

    bool isDelta() const { return true; }
    bool isBlack() const { return false; }
    bool isDiffuse() const { return false; }
    bool hasTransmission() const { return false; }
    bool usesLobeChoice() const { return false; }
    Color eval(const Vec3&, const Vec3&) const { return Color(0.0f); }
    float pdf(const Vec3&, const Vec3&) const { return 0.0f; }
    bool sample(const Vec3& wo, float, float, float, BsdfSample& out) const {
        if (wo.z == 0) return false;
        out = BsdfSample{};
        out.wi = reflectLocal(wo);
        out.delta = true;
        out.pdf = 1;
        out.f = m_.reflectance / std::abs(out.wi.z);
        return true;
    }

  private:
    const Material& m_;
};

}  // namespace kiln
