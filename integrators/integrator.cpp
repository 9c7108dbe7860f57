#include "integrators/integrator.h"

#include <stdexcept>

#include "integrators/normals.h"
#include "integrators/path.h"

namespace kiln {

const char* integratorNames() { return "path, normals"; }

std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const Scene& scene, const Accelerator& accel,
                                           const PathOptions& options) {
    if (name == "path") return std::make_unique<PathIntegrator>(scene, accel, options);
    if (name == "normals") return std::make_unique<NormalsIntegrator>(scene, accel);
    throw std::invalid_argument("unknown integrator '" + name + "' (known: " + integratorNames() + ")");
}

}  // namespace kiln
