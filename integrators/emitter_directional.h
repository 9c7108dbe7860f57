// A directional light (LightKind::Directional): irradiance from one direction at infinity.
#pragma once

#include "integrators/light_sample.h"
#include "scene/scene.h"

namespace kiln {

class DirectionalEmitter {
  public:
    static bool handles(LightKind k) { return k == LightKind::Directional; }
    DirectionalEmitter(const Light& l, const Scene&) : l_(l) {}

    // Power through a disc of the scene's radius.
    float power(float r) const { return luminance(l_.radiance) * kPi * r * r; }
    bool sample(const Vec3&, float, float, LightSample& out) const {
        out.wi = -normalize(l_.direction);
        out.pdf = 1;
        out.delta = out.infinite = true;
        out.Li = l_.radiance;
        return maxComponent(out.Li) > 0;
    }
    float pdf(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const { return 0.0f; }
    Color escaped(const Vec3&, bool) const { return Color(0.0f); }
    Color emitted(const Vec3&, const Vec3&, const Vec3&) const { return l_.radiance; }

  private:
    const Light& l_;
};

}  // namespace kiln
