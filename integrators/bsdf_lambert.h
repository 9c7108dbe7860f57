// The Lambertian BSDF (MaterialKind::Lambertian): albedo / pi, cosine-sampled. The path integrator
// also shades every surface of a diffuse-only scene with it (a pure emitter as a black one).
#pragma once

#include "integrators/bsdf_sample.h"
#include "integrators/microfacet.h"
#include "renderer/core/warp.h"
#include "renderer/geometry/material_lookup.h"

namespace kiln {

class LambertBsdf {
  public:
    static bool handles(MaterialKind k) { return k == MaterialKind::Lambertian; }
    static Color aovAlbedo(const Material&, const Color& baseColour) { return baseColour; }
    LambertBsdf(const Material&, MicrofacetModel, const SurfaceInputs& in)
        : LambertBsdf(in.baseColour, false) {}
    LambertBsdf(const Color& albedo, bool black) : albedo_(albedo), black_(black) {}

    bool isDelta() const { return false; }
    bool isBlack() const { return black_; }
    bool isDiffuse() const { return true; }
    bool hasTransmission() const { return false; }
    bool usesLobeChoice() const { return false; }
    Color eval(const Vec3& wo, const Vec3& wi) const {
        return wo.z * wi.z > 0 ? albedo_ * kInvPi : Color(0.0f);
    }
    float pdf(const Vec3& wo, const Vec3& wi) const {
        return wo.z * wi.z > 0 ? std::abs(wi.z) * kInvPi : 0.0f;
    }
    bool sample(const Vec3& wo, float, float u1, float u2, BsdfSample& out) const {
        if (wo.z == 0) return false;
        out = BsdfSample{};
        out.wi = cosineHemisphere(u1, u2);
        if (wo.z < 0) out.wi.z = -out.wi.z;
        out.pdf = std::abs(out.wi.z) * kInvPi;
        out.f = albedo_ * kInvPi;
        return out.pdf > 0;
    }

  private:
    Color albedo_;
    bool black_;
};

}  // namespace kiln
