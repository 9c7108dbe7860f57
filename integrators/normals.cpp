#include "integrators/normals.h"

#include "renderer/geometry/interaction.h"

namespace kiln {

void NormalsIntegrator::Li(const Ray& ray, Sampler&, RayCounter& counter,
                           SampleRecord& record) const {
    ++counter.rays;
    Hit hit;
    if (!accel_.intersect(ray, hit)) return;
    SurfaceInteraction si = makeInteraction(scene_, ray, hit);
    recordSurface(ray, hit, si, record);
    // The course shows the stored normal, not the one turned towards the viewer.
    record.L = si.nsStored * 0.5f + Vec3(0.5f);
    record.emission =
        record.L;  // all of it is "seen directly": the light AOVs still sum to the beauty
}

}  // namespace kiln
