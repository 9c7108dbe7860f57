// The integrator interface: radiance along a camera ray, given the scene and an accelerator.
#pragma once

#include <memory>
#include <span>
#include <string>

#include "integrators/crypto_names.h"
#include "renderer/accel/accelerator.h"
#include "renderer/core/sampler.h"
#include "renderer/film/aov.h"
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
    // aovs: what every camera sample records beside the beauty (fixed for the integrator's life).
    // pixelSpread: radians a camera pixel spans (texture footprints; 0: the finest texels).
    Integrator(const Scene& scene, const Accelerator& accel, const AovRequest& aovs = {},
               float pixelSpread = 0);
    virtual ~Integrator() = default;
    // Radiance along a camera ray into record.L, and the AOVs requested at construction.
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
    const AovRequest& aovs() const { return aovs_; }

  protected:
    // First-visible-surface AOVs (albedo, N, P, Z, ids), shared by every integrator.
    void recordSurface(const Ray& ray, const Hit& hit, const struct SurfaceInteraction& si,
                       SampleRecord& r) const;

    const Scene& scene_;
    const Accelerator& accel_;
    const AovRequest aovs_;
    const float pixelSpread_;
    const bool colourVaries_;  // textures or vertex colours: albedo is looked up per hit

  private:
    Vec3 cameraForward_;
    CryptoIds cryptoIds_;  // only with a Cryptomatte AOV
};

}  // namespace kiln
