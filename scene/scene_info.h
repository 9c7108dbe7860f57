// What `kiln info` prints: a human summary and a stable JSON form (documented in
// docs/info-json.md).
#pragma once

#include <map>
#include <string>

#include "scene/scene.h"

namespace kiln {

struct SceneSummary {
    uint64_t triangles = 0;        // as rendered (instances expanded)
    uint64_t uniqueTriangles = 0;  // stored
    uint64_t spheres = 0, meshes = 0, instances = 0, vertices = 0;
    std::map<std::string, int> materials;  // kind -> count of materials in use
    std::map<std::string, int> lights;     // kind -> count
    uint64_t geometryBytes = 0;            // scene model buffers
};

SceneSummary summarize(const Scene& scene);
Bounds3 worldBoundsOf(const Scene& scene);  // world coordinates (adds Scene::origin back)
Bounds3T<double> worldBoundsExact(const Scene& scene);  // the same in double (far scenes)
std::string sceneInfoText(const Scene& scene);
std::string sceneInfoJson(const Scene& scene);

}  // namespace kiln
