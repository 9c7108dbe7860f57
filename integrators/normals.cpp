#include "integrators/normals.h"

#include "renderer/interaction.h"

namespace kiln {

Color NormalsIntegrator::Li(const Ray& ray, Sampler&, RayCounter& counter) const {
    ++counter.rays;
    Hit hit;
    if (!accel_.intersect(ray, hit)) return Color(0.0f);
    SurfaceInteraction si = makeInteraction(scene_, ray, hit);
    // The course shows the stored normal, not the one turned towards the viewer.
    return si.nsStored * 0.5f + Vec3(0.5f);
}

}  // namespace kiln
