// The integrator interface: radiance along a camera ray, given the scene and an accelerator.
#pragma once

#include <memory>
#include <string>

#include "renderer/accelerator.h"
#include "renderer/sampler.h"
#include "scene/scene.h"

namespace kiln {

struct RayCounter {
    uint64_t rays = 0;
};

class Integrator {
public:
    Integrator(const Scene& scene, const Accelerator& accel) : scene_(scene), accel_(accel) {}
    virtual ~Integrator() = default;
    virtual Color Li(const Ray& ray, Sampler& sampler, RayCounter& counter) const = 0;
    virtual const char* name() const = 0;

protected:
    const Scene& scene_;
    const Accelerator& accel_;
};

struct PathOptions;

// Names: "path" (the default), "normals". Throws std::invalid_argument for an unknown name.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const Scene& scene, const Accelerator& accel,
                                           const PathOptions& options);
const char* integratorNames();

}  // namespace kiln
