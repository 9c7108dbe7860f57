// The environment light (LightKind::Environment): a lat-long map at infinity, importance-sampled
// by its texels (or a uniform colour without an image).
#pragma once

#include "integrators/environment_map.h"
#include "integrators/light_sample.h"
#include "scene/scene.h"

namespace kiln {

class EnvironmentEmitter {
  public:
    static bool handles(LightKind k) { return k == LightKind::Environment; }
    EnvironmentEmitter(const Light& l, const Scene&, const LightSetOptions& o)
        : l_(l), env_(loadEnvironment(l, o.misWithBsdf)) {}

    float power(float r) const;
    bool sample(const Vec3& ref, float u1, float u2, LightSample& out) const;
    void prefetch(float u1, float u2) const {
        if (!env_.pixels.empty()) env_.prefetch(u1, u2);
    }
    // sample() in two steps (EnvironmentMap::locate): false from locate where there is no map or
    // no density (sample() then says so), false from sampleLocated where sample() is false.
    bool locate(float u1, float u2, EnvironmentSample& out) const {
        return !env_.pixels.empty() && env_.locate(u1, u2, out);
    }
    // locate in its two parts (EnvironmentMap::pickRow, locateInRow); false where there is no map.
    bool pickRow(float u1, float u2, EnvironmentSample& out) const {
        if (env_.pixels.empty()) return false;
        env_.pickRow(u1, u2, out);
        return true;
    }
    bool locateInRow(float u1, EnvironmentSample& out) const { return env_.locateInRow(u1, out); }
    bool sampleLocated(const EnvironmentSample& s, LightSample& out) const;
    float pdf(const Vec3& ref, const Vec3& wi, const Vec3& x, const Vec3& n) const;
    Color escaped(const Vec3& dir, bool) const { return env_.lookup(dir); }
    // escaped() and, in pdf, pdf() towards dir: the map coordinates found once for both.
    Color escaped(const Vec3& dir, float& pdf) const;
    // Both, from dir's coordinates found already (latLong4); pdf may be null.
    Color escapedAt(const Vec3& dir, const LatLong& ll, float* pdf) const;
    // Asks memory for what escapedAt(., ll, .) reads.
    void prefetchEscape(const LatLong& ll) const {
        if (env_.pixels.empty()) return;
        float u, v;
        env_.coordinates(ll, u, v);
        env_.prefetchLookup(u, v);
    }
    Color emitted(const Vec3&, const Vec3&, const Vec3&) const { return l_.radiance; }
    bool compensated() const { return env_.compensated; }

  private:
    const Light& l_;
    EnvironmentMap env_;
};

}  // namespace kiln
