// The ambient light (LightKind::Ambient): uniform radiance from the upper (+Y) hemisphere. It
// lights the scene but is not a visible background, as in CS184.
#pragma once

#include "integrators/light_sample.h"
#include "renderer/core/warp.h"
#include "scene/scene.h"

namespace kiln {

class AmbientEmitter {
  public:
    static bool handles(LightKind k) { return k == LightKind::Ambient; }
    AmbientEmitter(const Light& l, const Scene&) : l_(l) {}

    float power(float r) const { return luminance(l_.radiance) * kPi * kPi * r * r; }
    bool sample(const Vec3&, float u1, float u2, LightSample& out) const {
        // Uniform over the upper (+Y) hemisphere, the only part that emits.
        Vec3 w = uniformHemisphere(u1, u2);
        out.wi = Vec3(w.x, w.z, w.y);
        out.pdf = uniformHemispherePdf();
        out.infinite = true;
        out.Li = l_.radiance;
        return maxComponent(out.Li) > 0;
    }
    float pdf(const Vec3&, const Vec3& wi, const Vec3&, const Vec3&) const {
        return wi.y > 0 ? uniformHemispherePdf() : 0.0f;
    }
    Color escaped(const Vec3& dir, bool cameraRay) const {
        return !cameraRay && dir.y > 0 ? l_.radiance : Color(0.0f);
    }
    Color emitted(const Vec3&, const Vec3&, const Vec3&) const { return l_.radiance; }

  private:
    const Light& l_;
};

}  // namespace kiln
