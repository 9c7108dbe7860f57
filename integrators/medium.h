// A homogeneous participating medium: Beer-Lambert transmittance, free-flight distance sampling
// and the Henyey-Greenstein phase function. Distances are sampled in one colour channel chosen in
// proportion to the path's throughput times the channel's single-scattering albedo (as Cycles),
// and weighed by the balance heuristic over the three channels (one-sample MIS, pbrt-v4's
// spectral MIS): the weight sigma_s T(t) / sum_c p_c sigma_t,c T_c(t) stays bounded however
// different the channels are. Tested against the densities in tests/test_media.cpp.
#pragma once

#include <algorithm>
#include <cmath>

#include "integrators/bsdf_sample.h"
#include "renderer/core/math.h"
#include "renderer/core/warp.h"
#include "scene/scene.h"

namespace kiln {

// Henyey-Greenstein with asymmetry g, as a density over the sphere of directions: cosTheta is
// the cosine between the direction light travelled before and after scattering (g > 0: forward).
inline float henyeyGreenstein(float cosTheta, float g) {
    float denom = 1 + g * g - 2 * g * cosTheta;
    return kInvPi * 0.25f * (1 - g * g) / (denom * std::sqrt(std::max(denom, 1e-12f)));
}

// A direction sampled from HG around the travel direction `forward` (unit), in the frame that
// `forward` is expressed in; its density is henyeyGreenstein(dot(forward, wi), g).
inline Vec3 sampleHenyeyGreenstein(const Vec3& forward, float g, float u1, float u2) {
    float cosTheta;
    if (std::abs(g) < 1e-3f) {
        cosTheta = 1 - 2 * u1;
    } else {
        float s = (1 - g * g) / (1 - g + 2 * g * u1);
        cosTheta = std::clamp((1 + g * g - s * s) / (2 * g), -1.0f, 1.0f);
    }
    float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
    float phi = 2 * kPi * u2;
    Frame f(forward);
    return f.toWorld(Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
}

// exp(-sigma d) per channel, 1 where sigma is 0 (also for an infinite d).
inline Color beerLambert(const Color& sigma, float d) {
    Color t;
    for (int c = 0; c < 3; ++c) t[c] = sigma[c] > 0 ? std::exp(-sigma[c] * d) : 1.0f;
    return t;
}

// What one free flight found: a scattering point at distance t, or the end of the segment; weight
// multiplies the path's throughput (transmittance, and sigma_s at a scattering point, over the
// density of what was sampled).
struct FreeFlight {
    bool scattered = false;
    float t = 0;
    Color weight{1.0f};
};

class HomogeneousMedium {
  public:
    HomogeneousMedium() = default;
    HomogeneousMedium(const Color& sigmaA, const Color& sigmaS, float g)
        : sigmaS_(sigmaS), sigmaT_(sigmaA + sigmaS), g_(g) {}
    explicit HomogeneousMedium(const Medium& m) : HomogeneousMedium(m.sigmaA, m.sigmaS, m.g) {}

    const Color& sigmaT() const { return sigmaT_; }
    const Color& sigmaS() const { return sigmaS_; }
    float g() const { return g_; }
    bool scatters() const { return maxComponent(sigmaS_) > 0; }
    Color transmittance(float d) const { return beerLambert(sigmaT_, d); }

    // The probability of sampling each channel for a path of throughput beta.
    Color channelPmf(const Color& beta) const {
        Color w;
        for (int c = 0; c < 3; ++c)
            w[c] = sigmaT_[c] > 0 ? std::max(beta[c], 0.0f) * sigmaS_[c] / sigmaT_[c] : 0.0f;
        float sum = w.x + w.y + w.z;
        return sum > 0 ? w / sum : Color(1.0f / 3);
    }

    // A free flight along a segment of length tMax (may be infinite) for a path of throughput
    // beta; uChannel picks the channel, uDistance the distance. A medium that only absorbs is not
    // sampled: its transmittance is the weight.
    FreeFlight sample(float tMax, const Color& beta, float uChannel, float uDistance) const {
        FreeFlight out;
        if (!scatters()) {
            out.weight = transmittance(tMax);
            return out;
        }
        Color pmf = channelPmf(beta);
        int c = uChannel < pmf.x ? 0 : uChannel < pmf.x + pmf.y ? 1 : 2;
        float t = sigmaT_[c] > 0 ? -std::log1p(-uDistance) / sigmaT_[c] : kInfinity;
        out.scattered = t < tMax;
        out.t = out.scattered ? t : tMax;
        Color tr = transmittance(out.t);
        // The balance heuristic over channels: the density of this event summed over them.
        Color density = out.scattered ? sigmaT_ * tr : tr;
        float pdf = dot(pmf, density);
        out.weight = pdf > 0 ? (out.scattered ? sigmaS_ * tr : tr) / pdf : Color(0.0f);
        return out;
    }

  private:
    Color sigmaS_{0.0f}, sigmaT_{0.0f};
    float g_ = 0;
};

// The phase function at a scattering point, shaped as the path loop's BSDFs are so that a medium
// vertex goes through the same stages as a surface's (next-event estimation with MIS, the
// continuation, roulette): local directions in any frame, and "eval" the phase function divided by
// |cos| because the loop multiplies what eval gives by |wi.z|. wo points back along the ray.
class PhaseAsBsdf {
  public:
    explicit PhaseAsBsdf(float g) : g_(g) {}
    bool isDelta() const { return false; }
    bool isBlack() const { return false; }
    bool isDiffuse() const { return false; }
    bool hasTransmission() const { return true; }
    bool usesLobeChoice() const { return false; }
    float pdf(const Vec3& wo, const Vec3& wi) const { return henyeyGreenstein(dot(-wo, wi), g_); }
    Color eval(const Vec3& wo, const Vec3& wi) const {
        return wi.z != 0 ? Color(pdf(wo, wi) / std::abs(wi.z)) : Color(0.0f);
    }
    bool sample(const Vec3& wo, float, float u1, float u2, BsdfSample& out) const {
        out = BsdfSample{};
        out.wi = sampleHenyeyGreenstein(-wo, g_, u1, u2);
        if (out.wi.z == 0) return false;
        out.pdf = pdf(wo, out.wi);
        out.f = Color(out.pdf / std::abs(out.wi.z));
        out.transmission = out.wi.z < 0;
        return out.pdf > 0;
    }

  private:
    float g_;
};

}  // namespace kiln
