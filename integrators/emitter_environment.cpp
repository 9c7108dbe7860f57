#include "integrators/emitter_environment.h"

#include "renderer/core/warp.h"

namespace kiln {

float EnvironmentEmitter::power(float r) const {
    float avg = env_.pixels.empty() ? luminance(env_.constant) : 0.0f;
    for (const Color& c : env_.pixels) avg += luminance(c) / float(env_.pixels.size());
    return avg * 2 * kPi * kPi * r * r;
}

bool EnvironmentEmitter::sample(const Vec3&, float u1, float u2, LightSample& out) const {
    out.infinite = true;
    if (env_.pixels.empty()) {
        out.wi = uniformSphere(u1, u2);
        out.pdf = uniformSpherePdf();
        out.Li = env_.constant;
        return maxComponent(out.Li) > 0;
    }
    EnvironmentSample s;
    if (!env_.locate(u1, u2, s)) return false;
    return sampleLocated(s, out);
}

bool EnvironmentEmitter::sampleLocated(const EnvironmentSample& s, LightSample& out) const {
    out.infinite = true;
    out.wi = s.dir;
    out.pdf = s.pdf;
    out.Li = env_.radianceAt(s);
    return maxComponent(out.Li) > 0;
}

Color EnvironmentEmitter::escaped(const Vec3& dir, float& pdf) const {
    return escapedAt(dir, latLong(dir), &pdf);
}

Color EnvironmentEmitter::escapedAt(const Vec3& dir, const LatLong& ll, float* pdf) const {
    if (env_.pixels.empty()) {
        if (pdf) *pdf = uniformSpherePdf();
        return env_.constant;
    }
    float u, v;
    env_.coordinates(ll, u, v);
    if (pdf) *pdf = env_.pdf(u, v, dir);
    return env_.lookup(u, v);
}

float EnvironmentEmitter::pdf(const Vec3&, const Vec3& wi, const Vec3&, const Vec3&) const {
    return env_.pixels.empty() ? uniformSpherePdf() : env_.pdf(wi);
}

}  // namespace kiln
