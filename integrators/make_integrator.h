// The one place an integrator is chosen: by kind, specialised for the render plan.
#pragma once

#include <memory>

#include "integrators/integrator.h"
#include "integrators/path_options.h"
#include "integrators/render_plan.h"

namespace kiln {

// The integrator of that kind, complete: specialised for the plan, recording plan.aovs.
std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind, const Scene& scene,
                                           const Accelerator& accel, const PathOptions& options,
                                           const RenderPlan& plan);

}  // namespace kiln
