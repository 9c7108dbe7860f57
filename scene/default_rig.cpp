#include "scene/scene_loader.h"

namespace kiln {

void addDefaultLightRig(Scene& scene) {
    // A key light from the upper front-left and a dim sky fill: readable shape, no pitch-black sides.
    Light key;
    key.name = "default-key";
    key.kind = LightKind::Directional;
    key.direction = normalize(Vec3(0.5f, -0.8f, -0.6f));
    key.radiance = Color(2.5f);
    scene.lights.push_back(key);
    Light fill;
    fill.name = "default-sky";
    fill.kind = LightKind::Ambient;
    fill.direction = Vec3(0, 1, 0);
    fill.radiance = Color(0.35f);
    scene.lights.push_back(fill);
}

void addEmissiveMeshLights(Scene& scene) {
    std::vector<bool> proto = scene.prototypeMask();
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        bool emits = false;
        for (uint32_t id : mesh.materialIds) {
            const Material& mat = scene.materials[id];
            emits |= mat.kind == MaterialKind::Emission && maxComponent(mat.emission) > 0;
        }
        if (!emits || proto[m]) continue;  // instanced emitters are not sampled as lights (yet)
        Light l;
        l.name = mesh.name;
        l.kind = LightKind::MeshEmitter;
        l.mesh = uint32_t(m);
        l.radiance = scene.materials[mesh.materialOf(0)].emission;
        scene.lights.push_back(l);
    }
}

}  // namespace kiln
