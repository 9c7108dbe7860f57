// Tangent-space normal maps: the shading normal bent by the map at the hit. The geometric normal is
// kept for every side and shadow test; a bent normal that would put the viewer below its tangent
// plane is tilted back towards the viewer.
#pragma once

#include "renderer/geometry/interaction.h"
#include "scene/scene.h"

namespace kiln {

// Perturbs si.ns and si.nsStored by the material's normal map (glTF convention: +x along the
// tangent, +y along the bitangent, texels raw data mapped from [0, 1] to [-1, 1], x and y times
// normalTexture.scale). Nothing happens without a map, UVs or tangents; a texel of exactly
// (0.5, 0.5, 1) leaves the normal bit for bit as it was.
void applyNormalMap(const Scene& scene, const Material& material, const Hit& hit,
                    const Vec3& woWorld, float worldWidth, SurfaceInteraction& si);

}  // namespace kiln
