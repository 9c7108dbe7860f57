// A pugixml pass over COLLADA files for what Assimp drops: the CGL/CMU462 <technique> extras
// (area lights, emission, mirror/glass/microfacet/refraction/glossy, analytic spheres), the
// lights and camera as the CS184 course program reads them, and the node transforms they sit under.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace kiln {

struct ColladaExtras {
    bool zUp = false;
    Mat4 upAxisFix;  // course convention: Z-up files are pre-multiplied by swap-Y/Z, negate-X
    // Material id and name -> material parsed from its effect (kind and parameters).
    std::map<std::string, Material> materialsById;
    std::map<std::string, std::string> materialIdByName;
    std::vector<Sphere> spheres;  // world space (up-axis fix applied)
    std::vector<std::string> sphereMaterialIds;
    std::vector<Light> lights;     // world space
    std::optional<Camera> camera;  // world space
    std::vector<std::string> warnings;
    // Set when the file needed patching before Assimp could read it (CBgems' 15-number matrix).
    std::optional<std::string> patchedXml;
};

// Throws SceneError on malformed XML or a CGL block with missing or garbled values.
ColladaExtras parseColladaExtras(const std::string& path);

}  // namespace kiln
