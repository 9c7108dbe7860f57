// What maps need of the scene's meshes and materials: every texture id a material holds, UVs at a
// point of a triangle, tangents for normal maps.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace kiln {

// Every texture id a material holds (Material::albedoTexture and those of its maps), so code
// that moves or renumbers texture ids (merging scenes, opening textures) misses none.
std::vector<int*> textureIds(Material& m);

// Barycentric interpolation of the mesh's UVs at triangle `prim` (b1, b2: weights of its vertices
// 1 and 2). The mesh must have UVs.
void uvAt(const TriangleMesh& mesh, uint32_t prim, float b1, float b2, float& u, float& v);

// Per-vertex tangents from the UVs (the one place for the formula): the direction of increasing
// u, summed over a vertex's triangles and made perpendicular to its normal, with the handedness
// of increasing v. Files that state tangents (glTF TANGENT) keep theirs.
void computeTangents(TriangleMesh& mesh);
// Tangents for every mesh with a normal-mapped material that lacks them (a warning for a mesh
// without UVs, whose normal map then does nothing).
void addMissingTangents(Scene& scene);

}  // namespace kiln
