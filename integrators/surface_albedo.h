// The diffuse colour a surface has where a ray hit it: the material's albedo times its base-colour
// texture (a filtered lookup at the hit's UV) and the mesh's vertex colours. Without either it is
// the material's albedo, unchanged.
#pragma once

#include "integrators/principled_bsdf.h"
#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

// Whether any material has a texture (colour or normal map) or any mesh vertex colours (else
// albedoAt is plain albedo and no normal is mapped).
bool hasSurfaceColourVariation(const Scene& scene);

// Footprint rule (docs/import.md): without ray differentials, a lookup covers the width a pixel
// spans at the distance the path has travelled (travelled * pixelSpread, in scene units), mapped to
// texture space by the triangle's UV-to-surface scale, sqrt(UV area / area).
// The footprint's width in texture (s, t) units for a hit on a triangle: the world width mapped by
// the triangle's UV-to-surface scale and the texture transform's scale.
float textureWidth(const Scene& scene, const Hit& hit, const UvTransform& uvTransform,
                   float worldWidth);

Color albedoAt(const Scene& scene, const Material& material, const Hit& hit, float travelled,
               float pixelSpread);

// A principled material's metallic and roughness at the hit: its factors times the
// metallic-roughness texture's channels (glTF: B and G), looked up with the same footprint rule.
MetallicRoughness metallicRoughnessAt(const Scene& scene, const Material& material, const Hit& hit,
                                      float travelled, float pixelSpread);

// The emission texture's colour at a point of triangle `prim` of mesh `mesh` (b1, b2: weights of
// its vertices 1 and 2), 1 where the material has none: it multiplies the emitted radiance. Read at
// the finest level, with no footprint, so that a ray hitting the point and a light sample picking
// it see the same radiance (MIS weighs the two as estimates of one integrand).
Color emissionTexelAt(const Scene& scene, const Material& material, uint32_t mesh, uint32_t prim,
                      float b1, float b2);
// Whether any material of the mesh has an emission texture it can read (the mesh has UVs).
bool hasEmissionTexture(const Scene& scene, uint32_t mesh);

}  // namespace kiln
