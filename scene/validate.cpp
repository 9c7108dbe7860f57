#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace kiln {

namespace {

uint64_t zeroAreaTriangles(const TriangleMesh& mesh) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, mesh.triangleCount(), 1 << 16), uint64_t(0),
        [&](const tbb::blocked_range<size_t>& r, uint64_t n) {
            for (size_t t = r.begin(); t != r.end(); ++t) {
                Vec3 a = mesh.vertex(mesh.indices[3 * t]), b = mesh.vertex(mesh.indices[3 * t + 1]),
                     c = mesh.vertex(mesh.indices[3 * t + 2]);
                Vec3 n2 = cross(b - a, c - a);
                n += !(dot(n2, n2) > 0);
            }
            return n;
        },
        std::plus<uint64_t>());
}

// Meshes made only of zero-area triangles show nothing: a warning each, an error when nothing
// else is left to render. Called after the index checks.
void checkDegenerate(Scene& scene) {
    uint64_t visible = 0;
    for (const TriangleMesh& mesh : scene.meshes) {
        uint64_t zero = zeroAreaTriangles(mesh);
        uint64_t rest = mesh.triangleCount() - zero;
        visible += rest;
        if (zero > 0 && rest == 0)
            scene.warnings.push_back("mesh '" + mesh.name + "': all " + std::to_string(zero) +
                                     " triangles have zero area and cannot be seen");
    }
    if (visible == 0 && scene.spheres.empty())
        throw SceneError(
            scene.sourcePath,
            "nothing to render: every triangle has zero area and there are no spheres");
}

}  // namespace

void validateCamera(const std::string& file, const Camera& c) {
    if (!isFinite(c.position) || !isFinite(c.forward) || !isFinite(c.up))
        throw SceneError(file, "the camera has a non-finite position or direction");
    if (!(length(c.forward) > 0)) throw SceneError(file, "the camera has no view direction");
    if (c.orthographic()) {
        if (!(std::isfinite(c.orthoHalfWidth) && c.orthoHalfHeight > 0 &&
              std::isfinite(c.orthoHalfHeight)))
            throw SceneError(file, "the orthographic camera's width or height is not positive");
    } else if (!(c.hFovDeg > 0 && c.hFovDeg < 180 && c.vFovDeg > 0 && c.vFovDeg < 180)) {
        throw SceneError(file, "the camera's field of view is outside (0, 180) degrees");
    }
    if (!(c.nearClip >= 0 && c.farClip > c.nearClip))
        throw SceneError(file, "the camera's clip planes are not 0 <= near < far");
    if (!(c.apertureRadius >= 0 && std::isfinite(c.apertureRadius) && c.focalDistance > 0))
        throw SceneError(file, "the camera's lens has a negative aperture or no focal distance");
}

void validateView(const Scene& scene) { validateView(scene, scene.storedBounds()); }

void validateView(const Scene& scene, const Bounds3& storedBounds) {
    validateCamera(scene.sourcePath, scene.camera);
    Bounds3 b = storedBounds;
    b.extend(scene.camera.position);
    float extent = maxComponent(b.diagonal());
    float reach = std::max(maxComponent(abs(b.lo)), maxComponent(abs(b.hi)));
    if (!(extent <= kMaxSceneExtent && reach <= kMaxSceneExtent)) {
        throw SceneError(scene.sourcePath,
                         fmt::format("the scene and camera span {:.3g} units; kiln traces at most "
                                     "{:.0e} (float distances would overflow)",
                                     double(std::max(extent, reach)), double(kMaxSceneExtent)));
    }
}

void validateScene(Scene& scene) {
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
    checkDegenerate(scene);
}

}  // namespace kiln
