// Point and spot lights (LightKind::Point, Spot): intensity over the falloff the file states
// (1 / d^2 by default), a spot's smoothstep cone. Delta lights: only light sampling finds them.
#pragma once

#include <cmath>

#include "integrators/light_sample.h"
#include "scene/scene.h"

namespace kiln {

class PointEmitter {
  public:
    static bool handles(LightKind k) { return k == LightKind::Point || k == LightKind::Spot; }
    PointEmitter(const Light& l, const Scene&) : l_(l) {}

    float power(float) const {
        float lum = luminance(l_.radiance);
        if (l_.kind == LightKind::Point) return 4 * kPi * lum;
        return 2 * kPi * lum *
               (1 -
                0.5f * (std::cos(radians(l_.spotInnerDeg)) + std::cos(radians(l_.spotOuterDeg))));
    }
    bool sample(const Vec3& ref, float, float, LightSample& out) const {
        Vec3 d = l_.position - ref;
        float dist2 = dot(d, d);
        if (dist2 == 0) return false;
        out.wi = d / std::sqrt(dist2);
        out.p = l_.position;
        out.pdf = 1;
        out.delta = true;
        out.Li = l_.radiance / l_.falloffDenominator(dist2);
        if (l_.kind == LightKind::Spot) out.Li = out.Li * spotFalloff(-out.wi);
        return maxComponent(out.Li) > 0;
    }
    float pdf(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const { return 0.0f; }
    Color escaped(const Vec3&, bool) const { return Color(0.0f); }
    Color emitted(const Vec3&, const Vec3&, const Vec3&) const { return l_.radiance; }

  private:
    float spotFalloff(const Vec3& wFromLight) const {
        float c = dot(normalize(l_.direction), wFromLight);
        float cosOuter = std::cos(radians(l_.spotOuterDeg)),
              cosInner = std::cos(radians(l_.spotInnerDeg));
        if (c <= cosOuter) return 0;
        if (c >= cosInner) return 1;
        float t = (c - cosOuter) / (cosInner - cosOuter);
        return t * t * (3 - 2 * t);  // smoothstep
    }
    const Light& l_;
};

}  // namespace kiln
