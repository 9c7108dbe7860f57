// Format readers. Each fills a Scene in world space (Y up) and throws SceneError on bad input.
#pragma once

#include <string>

#include "scene/cgl_extras.h"
#include "scene/scene.h"

namespace kiln {

// Any format Assimp reads. With extras (COLLADA), materials, lights, spheres and the camera come
// from the CGL pass and the course's up-axis convention replaces Assimp's.
void importWithAssimp(const std::string& path, const ColladaExtras* extras, Scene& scene);

// Direct binary/ASCII PLY reader: face lists and tristrips (which Assimp 5.2 reads as one
// triangle).
void readPly(const std::string& path, Scene& scene);

}  // namespace kiln
