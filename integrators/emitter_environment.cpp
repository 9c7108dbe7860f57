#include "integrators/emitter_environment.h"

#include <cmath>

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
    float u, v, pdfUV;
    env_.distribution.sample(u1, u2, u, v, pdfUV);
    float sinTheta = std::sin(v * kPi);
    if (pdfUV == 0 || sinTheta == 0) return false;
    out.wi = env_.direction(u, v);
    out.pdf = pdfUV / (2 * kPi * kPi * sinTheta);
    out.Li = env_.lookup(out.wi);
    return maxComponent(out.Li) > 0;
}

float EnvironmentEmitter::pdf(const Vec3&, const Vec3& wi, const Vec3&, const Vec3&) const {
    if (env_.pixels.empty()) return uniformSpherePdf();
    float u, v;
    env_.coordinates(wi, u, v);
    float sinTheta = std::sin(v * kPi);
    return sinTheta > 0 ? env_.distribution.pdf(u, v) / (2 * kPi * kPi * sinTheta) : 0.0f;
}

}  // namespace kiln
