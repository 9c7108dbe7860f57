// A pugixml pass over COLLADA files for what Assimp drops: the CGL/CMU462 <technique> extras
// (area lights, emission, mirror/glass/microfacet/refraction/glossy, analytic spheres), the
// lights and camera as the CS184 course program reads them, and the node transforms they sit under.
#pragma once

#include <map>
#include <optional>
#include <pugixml.hpp>
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
    double unitMeters =
        1.0;  // <unit meter>: Assimp scales the geometry by it, so this pass does too
    // Everything below is stored relative to `origin` (world = stored + origin), chosen in double
    // as the centre of what the file places, so a scene far from the world origin keeps its digits.
    Vec3d origin{0.0};
    std::vector<Sphere> spheres;  // up-axis fix and unit applied
    std::vector<std::string> sphereMaterialIds;
    std::vector<Light> lights;
    std::optional<Camera> camera;
    // World transform of every <node> with an id, composed in double (Assimp names nodes by id).
    std::map<std::string, Mat4> nodeWorldById;
    std::vector<std::string> warnings;
    // Set when the file needed patching before Assimp could read it (CBgems' 15-number matrix).
    std::optional<std::string> patchedXml;
};

// Throws SceneError on malformed XML, a CGL block with missing or garbled values, or geometry
// arrays Assimp would misread (counts that are not non-negative integers or do not match the data).
ColladaExtras parseColladaExtras(const std::string& path);

// Checks what Assimp's COLLADA reader trusts without checking (it dereferences null or allocates
// without bound otherwise): array counts, accessor ranges and index lists of every geometry.
void checkColladaGeometry(const std::string& path, pugi::xml_node collada);

}  // namespace kiln
