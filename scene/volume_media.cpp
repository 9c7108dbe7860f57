#include "scene/volume_media.h"

#include <algorithm>
#include <cmath>

#include "scene/material_kinds.h"

namespace kiln {
namespace {

// A colour channel of 0 would need an infinite coefficient: this little is left instead.
constexpr float kMinAttenuation = 1e-6f;

bool absorbingVolume(const Material& m) {
    const MaterialKindSpec& k = specOf(m.kind);
    return k.transmits && k.transmits(m) && m.thickness > 0 &&
           std::isfinite(m.attenuationDistance) && m.attenuationDistance > 0 &&
           std::min({m.attenuationColor.x, m.attenuationColor.y, m.attenuationColor.z}) < 1;
}

Medium absorption(const Material& m) {
    Medium medium;
    medium.name = "volume of " + m.name;
    for (int k = 0; k < 3; ++k)
        medium.sigmaA[k] = -std::log(std::clamp(m.attenuationColor[k], kMinAttenuation, 1.0f)) /
                           m.attenuationDistance;
    return medium;
}

// The one material of a mesh, or -1 where its triangles have several.
int onlyMaterial(const TriangleMesh& mesh) {
    if (mesh.materialIds.empty()) return -1;
    const uint32_t first = mesh.materialIds[0];
    for (uint32_t id : mesh.materialIds)
        if (id != first) return -1;
    return int(first);
}

}  // namespace

void addVolumeMedia(Scene& scene) {
    std::vector<int> mediumOf(scene.materials.size(), -1);  // one medium per material
    for (TriangleMesh& mesh : scene.meshes) {
        const int mat = onlyMaterial(mesh);
        if (mesh.interior >= 0 || mat < 0 || !absorbingVolume(scene.materials[size_t(mat)]))
            continue;
        int& medium = mediumOf[size_t(mat)];
        if (medium < 0) {
            medium = int(scene.media.size());
            scene.media.push_back(absorption(scene.materials[size_t(mat)]));
        }
        mesh.interior = medium;
    }
}

}  // namespace kiln
