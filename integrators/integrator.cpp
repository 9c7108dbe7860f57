#include "integrators/integrator.h"

#include <stdexcept>

#include "integrators/normals.h"

namespace kiln {

const char* integratorNames() { return "normals"; }

std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const Scene& scene, const Accelerator& accel) {
    if (name == "normals") return std::make_unique<NormalsIntegrator>(scene, accel);
    throw std::invalid_argument("unknown integrator '" + name + "' (known: " + integratorNames() + ")");
}

}  // namespace kiln
