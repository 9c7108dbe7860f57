// CS184 part 1 normal shading: the surface normal mapped to colour, n * 0.5 + 0.5.
#pragma once

#include "integrators/integrator.h"

namespace kiln {

class NormalsIntegrator final : public Integrator {
  public:
    using Integrator::Integrator;
    using Integrator::Li;
    void Li(const Ray& ray, Sampler& sampler, RayCounter& counter,
            SampleRecord& record) const override;
    const char* name() const override { return "normals"; }
};

}  // namespace kiln
