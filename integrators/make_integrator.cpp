#include "integrators/make_integrator.h"

#include "integrators/normals.h"
#include "integrators/path.h"

namespace kiln {

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind, const Scene& scene,
                                           const Accelerator& accel, const PathOptions& options,
                                           const RenderPlan& plan) {
    if (kind == IntegratorKind::Normals)
        return std::make_unique<NormalsIntegrator>(scene, accel, plan.aovs);
    return std::make_unique<PathIntegrator>(scene, accel, options, plan);
}

}  // namespace kiln
