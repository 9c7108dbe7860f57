#include "scene/scene_loader.h"

namespace kiln {

void addDefaultLightRig(Scene& scene) {
    // A key light from the upper front-left and a dim sky fill: readable shape, no pitch-black
    // sides.
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
            emits |= maxComponent(mat.emission) > 0;
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

void mergeAreaLightsWithEmitters(Scene& scene) {
    // The CS184 Cornell boxes hold the ceiling light twice: a CGL <area> rectangle (what light
    // sampling uses) and an emissive quad (what rays see). They are one light: the quad's geometry
    // with the area light's radiance, so it is neither counted twice nor seen with another
    // brightness than it lights.
    for (size_t a = 0; a < scene.lights.size(); ++a) {
        Light& area = scene.lights[a];
        if (area.kind != LightKind::Area || area.hasMesh) continue;
        float size = std::max(length(area.dimX), length(area.dimY));
        float rectArea = length(cross(area.dimX, area.dimY));
        for (size_t e = 0; e < scene.lights.size(); ++e) {
            const Light& emitter = scene.lights[e];
            if (emitter.kind != LightKind::MeshEmitter) continue;
            const TriangleMesh& m = scene.meshes[emitter.mesh];
            Vec3 n = normalize(area.direction), centroid(0.0f);
            bool coplanar = true;
            for (size_t v = 0; v < m.vertexCount(); ++v) {
                Vec3 p = m.vertex(uint32_t(v));
                centroid += p / float(m.vertexCount());
                coplanar &= std::abs(dot(p - area.position, n)) <= 0.01f * size;
            }
            float meshArea = 0;
            for (size_t t = 0; t < m.triangleCount(); ++t)
                meshArea +=
                    0.5f *
                    length(cross(m.vertex(m.indices[3 * t + 1]) - m.vertex(m.indices[3 * t]),
                                 m.vertex(m.indices[3 * t + 2]) - m.vertex(m.indices[3 * t])));
            bool sameSpot = length(centroid - area.position) <= 0.05f * size;
            bool sameArea = std::abs(meshArea - rectArea) <= 0.05f * rectArea;
            if (!(coplanar && sameSpot && sameArea)) continue;
            Color meshRadiance = emitter.radiance;
            area.hasMesh = true;
            area.mesh = emitter.mesh;
            if (!(meshRadiance == area.radiance))
                scene.warnings.push_back("area light '" + area.name + "' and emissive mesh '" +
                                         emitter.name +
                                         "' are one light; it emits the area light's radiance (" +
                                         std::to_string(area.radiance.x) + "), not the mesh's (" +
                                         std::to_string(meshRadiance.x) + ")");
            scene.lights.erase(scene.lights.begin() + long(e));
            if (e < a) --a;
            break;
        }
    }
}

}  // namespace kiln
