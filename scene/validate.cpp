#include <cmath>

#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace kiln {

void validateScene(const Scene& scene) {
    const std::string& file = scene.sourcePath;
    if (scene.uniqueTriangles() == 0 && scene.spheres.empty())
        throw SceneError(file, "empty scene: no triangles and no spheres to render");
    for (const TriangleMesh& mesh : scene.meshes) {
        size_t nv = mesh.vertexCount();
        for (size_t i = 0; i < 3 * nv; ++i)
            if (!std::isfinite(mesh.positions[i]))
                throw SceneError(file, "mesh '" + mesh.name +
                                           "' has a non-finite (NaN/Inf) coordinate at vertex " +
                                           std::to_string(i / 3));
        for (size_t i = 0; i < mesh.indices.size(); ++i)
            if (mesh.indices[i] >= nv)
                throw SceneError(file, "mesh '" + mesh.name + "' triangle " +
                                           std::to_string(i / 3) + " has vertex index " +
                                           std::to_string(mesh.indices[i]) + " out of range (" +
                                           std::to_string(nv) + " vertices)");
        for (size_t i = 0; i < mesh.normals.size(); ++i)
            if (!std::isfinite(mesh.normals[i]))
                throw SceneError(file, "mesh '" + mesh.name +
                                           "' has a non-finite normal at vertex " +
                                           std::to_string(i / 3));
        for (uint32_t m : mesh.materialIds)
            if (m >= scene.materials.size())
                throw SceneError(file, "mesh '" + mesh.name + "' names material " +
                                           std::to_string(m) + " which does not exist");
    }
    for (const Sphere& s : scene.spheres) {
        if (!isFinite(s.center) || !std::isfinite(s.radius) || !(s.radius > 0))
            throw SceneError(file,
                             "sphere '" + s.name + "' has a non-finite centre or a radius <= 0");
        if (s.material >= scene.materials.size())
            throw SceneError(file, "sphere '" + s.name + "' names a material which does not exist");
    }
    for (const Instance& inst : scene.instances) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j)
                if (!std::isfinite(inst.objectToWorld.m[i][j]))
                    throw SceneError(file, "an instance transform has a non-finite entry");
        if (inst.objectToWorld.determinant3() == 0)
            throw SceneError(file, "an instance transform is singular (zero scale)");
    }
    for (const Light& l : scene.lights) {
        if (!isFinite(l.radiance) || !isFinite(l.position) || !isFinite(l.direction))
            throw SceneError(file, "light '" + l.name + "' has a non-finite parameter");
        if (l.radiance.x < 0 || l.radiance.y < 0 || l.radiance.z < 0)
            throw SceneError(file, "light '" + l.name + "' has negative radiance");
    }
}

}  // namespace kiln
