#include "integrators/bsdf_dielectric.h"

#include "integrators/fresnel.h"

namespace kiln {

bool DielectricBsdf::sample(const Vec3& wo, float uc, float, float, BsdfSample& out) const {
    if (wo.z == 0) return false;
    out = BsdfSample{};
    // eta = n_t / n_i: entering from outside (wo.z > 0) goes into the material.
    bool entering = wo.z > 0;
    float eta = entering ? m_.ior : 1 / m_.ior;
    float F = fresnelDielectric(wo.z, m_.ior);
    Vec3 n(0, 0, entering ? 1.0f : -1.0f);
    Vec3 wt;
    bool canRefract = refract(wo, n, eta, wt);
    out.delta = true;
    if (reflects_ && (!canRefract || uc < F)) {
        // Reflection chosen with probability F (or always, under total internal reflection).
        out.wi = reflectLocal(wo);
        out.pdf = canRefract ? F : 1.0f;
        out.f = m_.reflectance * (canRefract ? F : 1.0f) / std::abs(out.wi.z);
        return true;
    }
    if (!canRefract) return false;  // refraction-only: total internal reflection absorbs
    out.wi = wt;
    out.transmission = true;
    float T = reflects_ ? 1 - F : 1.0f;
    out.pdf = reflects_ ? 1 - F : 1.0f;
    // Radiance is compressed by eta^2 crossing into the denser medium.
    out.f = m_.transmittance * (T / (eta * eta)) / std::abs(wt.z);
    return true;
}

}  // namespace kiln
