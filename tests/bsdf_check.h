// Checks shared by the BSDF sampling tests.
#pragma once

#include <cmath>

#include "integrators/bsdf.h"

namespace kiln::test {

// True when a sample's value or density differs (beyond 1e-3 relative) from what eval() and pdf()
// give for its direction.
inline bool disagreesWithEvalAndPdf(const Bsdf& bsdf, const Vec3& wo, const BsdfSample& bs) {
    float pdf = bsdf.pdf(wo, bs.wi);
    Color f = bsdf.eval(wo, bs.wi);
    return std::abs(pdf - bs.pdf) > 1e-3f * pdf ||
           maxComponent(abs(f - bs.f)) > 1e-3f * maxComponent(f);
}

}  // namespace kiln::test
