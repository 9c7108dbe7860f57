// The integrator interface: radiance along a camera ray, given the scene and an accelerator.
#pragma once

#include <memory>
#include <span>
#include <string>

#include "renderer/accelerator.h"
#include "renderer/aov.h"
#include "renderer/sampler.h"
#include "scene/scene.h"

namespace kiln {

struct RayCounter {
    uint64_t rays = 0;
};

// One camera sample on its way through an integrator: its ray, its random numbers and what it
// records. Integrators take them in batches so rays of neighbouring samples travel as packets.
struct CameraSample {
    Ray ray;
    Sampler sampler;
    SampleRecord record;
};

class Integrator {
  public:
    Integrator(const Scene& scene, const Accelerator& accel) : scene_(scene), accel_(accel) {}
    virtual ~Integrator() = default;
    // Radiance along a camera ray into record.L, and the AOVs requested by setAovs().
    virtual void Li(const Ray& ray, Sampler& sampler, RayCounter& counter,
                    SampleRecord& record) const = 0;
    Color Li(const Ray& ray, Sampler& sampler, RayCounter& counter) const {
        SampleRecord r;
        r.reset(aovs_);
        Li(ray, sampler, counter, r);
        return r.L;
    }
    // A batch of camera samples (records already reset). The default traces them one by one; the
    // path integrator traces them together, a bounce at a time.
    virtual void Li(std::span<CameraSample> batch, RayCounter& counter) const {
        for (CameraSample& s : batch) Li(s.ray, s.sampler, counter, s.record);
    }
    virtual const char* name() const = 0;
    void setAovs(const AovRequest& aovs) { aovs_ = aovs; }

  protected:
    // First-visible-surface AOVs (albedo, N, P, Z, ids), shared by every integrator.
    void recordSurface(const Ray& ray, const Hit& hit, const struct SurfaceInteraction& si,
                       SampleRecord& r) const;

    const Scene& scene_;
    const Accelerator& accel_;
    AovRequest aovs_;
};

struct PathOptions;

// Names: "path" (the default), "normals". Throws std::invalid_argument for an unknown name.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name, const Scene& scene,
                                           const Accelerator& accel, const PathOptions& options);
const char* integratorNames();

}  // namespace kiln
