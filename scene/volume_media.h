// KHR_materials_volume's absorption as a medium: a closed principled mesh that transmits through a
// volume (transmission > 0, thickness > 0) with a finite attenuation distance gets a homogeneous
// absorbing interior, so the path tracer's media (integrators/media.h) apply it.
#pragma once

#include "scene/scene.h"

namespace kiln {

// sigma_a = -ln(attenuation colour) / attenuation distance per channel (Beer-Lambert: the colour is
// what is left after the distance), no scattering. Meshes that already name an interior keep it.
void addVolumeMedia(Scene& scene);

}  // namespace kiln
