// A surface that reflects nothing (MaterialKind::Emission: a pure emitter). Its light is the
// emitter's, found by rays and light samples; as a BSDF it ends the path.
#pragma once

#include "integrators/bsdf_sample.h"
#include "integrators/microfacet.h"
#include "renderer/geometry/material_lookup.h"

namespace kiln {

class BlackBsdf {
  public:
    static bool handles(MaterialKind k) { return k == MaterialKind::Emission; }
    static Color aovAlbedo(const Material&, const Color&) { return Color(0.0f); }
    BlackBsdf(const Material&, MicrofacetModel, const SurfaceInputs&) {}

    bool isDelta() const { return false; }
    bool isBlack() const { return true; }
    bool isDiffuse() const { return false; }
    bool hasTransmission() const { return false; }
    bool usesLobeChoice() const { return false; }
    Color eval(const Vec3&, const Vec3&) const { return Color(0.0f); }
    float pdf(const Vec3&, const Vec3&) const { return 0.0f; }
    bool sample(const Vec3&, float, float, float, BsdfSample&) const { return false; }
};

}  // namespace kiln
