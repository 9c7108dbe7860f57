// Mesh generators for scale tests: midpoint subdivision, binary PLY and OBJ writers.
#pragma once

#include <string>

#include "scene/scene.h"

namespace kiln {

// One level of 1-to-4 midpoint subdivision: each triangle becomes four, edge midpoints shared, so a
// closed mesh stays closed. Normals and UVs are dropped (the surface is unchanged, flat-shaded).
TriangleMesh subdivideMidpoint(const TriangleMesh& mesh);

// Binary little-endian PLY: float x y z per vertex, uchar-int face lists. Throws
// std::runtime_error.
void writeBinaryPly(const std::string& path, const TriangleMesh& mesh);

// ASCII OBJ (v and f lines, shortest round-trip floats). Throws std::runtime_error.
void writeObj(const std::string& path, const TriangleMesh& mesh);

}  // namespace kiln
