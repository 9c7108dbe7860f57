#include "scene/scene.h"

#include <algorithm>
#include <cmath>

namespace kiln {

void TriangleMesh::finalizePadding() {
    if (positions.size() % 3 == 0) positions.push_back(0.0f);
}

std::vector<bool> Scene::prototypeMask() const {
    std::vector<bool> mask(meshes.size(), false);
    for (const Instance& inst : instances) mask[inst.mesh] = true;
    return mask;
}

Bounds3 Scene::storedBounds() const {
    Bounds3 b;
    std::vector<bool> proto = prototypeMask();
    for (size_t m = 0; m < meshes.size(); ++m) {
        if (proto[m]) continue;
        for (size_t v = 0; v < meshes[m].vertexCount(); ++v)
            b.extend(meshes[m].vertex(uint32_t(v)));
    }
    for (const Instance& inst : instances) {
        const TriangleMesh& mesh = meshes[inst.mesh];
        Bounds3 local;
        for (size_t v = 0; v < mesh.vertexCount(); ++v) local.extend(mesh.vertex(uint32_t(v)));
        if (local.empty()) continue;
        for (int c = 0; c < 8; ++c) {
            Vec3 corner{(c & 1) ? local.hi.x : local.lo.x, (c & 2) ? local.hi.y : local.lo.y,
                        (c & 4) ? local.hi.z : local.lo.z};
            b.extend(inst.objectToWorld.point(corner));
        }
    }
    for (const Sphere& s : spheres) {
        b.extend(s.center - Vec3(s.radius));
        b.extend(s.center + Vec3(s.radius));
    }
    return b;
}

uint64_t Scene::uniqueTriangles() const {
    uint64_t n = 0;
    for (const TriangleMesh& m : meshes) n += m.triangleCount();
    return n;
}

uint64_t Scene::instancedTriangles() const {
    uint64_t n = 0;
    std::vector<bool> proto = prototypeMask();
    for (size_t m = 0; m < meshes.size(); ++m)
        if (!proto[m]) n += meshes[m].triangleCount();
    for (const Instance& inst : instances) n += meshes[inst.mesh].triangleCount();
    return n;
}

bool Scene::holdsNothing() const {
    return meshes.empty() && spheres.empty() && lights.empty() && !hasFileCamera;
}

double Scene::brightestEmission() const {
    double brightest = 0;
    auto consider = [&brightest](const Color& c, double scale) {
        double v = double(maxComponent(c)) * scale;
        if (std::isfinite(v)) brightest = std::max(brightest, v);
    };
    for (const Material& m : materials) consider(m.emission, 1.0);
    for (const Light& l : lights) {
        consider(l.radiance, 1.0);
        if (l.environmentImage)
            for (const Color& c : l.environmentImage->pixels) consider(c, l.environmentScale);
    }
    return brightest;
}

namespace {

// Adds shift to every xyz of a position buffer in double, rounding once.
void shiftPositions(std::vector<float>& p, const Vec3d& shift) {
    for (size_t v = 0; v + 2 < p.size(); v += 3)
        for (int k = 0; k < 3; ++k) p[v + k] = float(double(p[v + k]) + shift[k]);
}

}  // namespace

void rebaseScene(Scene& scene, const Vec3d& origin) {
    Vec3d shift = scene.origin - origin;  // stored_new = stored_old + shift
    if (shift == Vec3d(0.0)) return;
    auto move = [&](Vec3& p) { p = Vec3(Vec3d(p) + shift); };
    std::vector<bool> proto = scene.prototypeMask();
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        if (!proto[m]) shiftPositions(scene.meshes[m].positions, shift);  // not object space
    }
    for (Instance& inst : scene.instances) {
        for (int r = 0; r < 3; ++r) inst.objectToWorld.m[r][3] += shift[r];
        inst.worldToObject = inst.objectToWorld.inverse();
    }
    for (Sphere& s : scene.spheres) move(s.center);
    for (Light& l : scene.lights) move(l.position);
    move(scene.camera.position);
    scene.origin = origin;
}

Vec3d originFor(const Bounds3T<double>& bounds) {
    if (bounds.empty()) return Vec3d(0.0);
    Vec3d c = (bounds.lo + bounds.hi) * 0.5;
    return maxComponent(abs(c)) > 4 * maxComponent(bounds.hi - bounds.lo) ? c : Vec3d(0.0);
}

Vec3d streamOrigin(const Vec3d& firstVertex) {
    return maxComponent(abs(firstVertex)) > kFarFirstVertex ? firstVertex : Vec3d(0.0);
}

void appendMesh(Scene& scene, TriangleMesh&& mesh, const Vec3d& meshOrigin) {
    Vec3d shift = meshOrigin - adoptOrigin(scene, meshOrigin);
    if (shift != Vec3d(0.0)) shiftPositions(mesh.positions, shift);
    scene.meshes.push_back(std::move(mesh));
}

Vec3d adoptOrigin(Scene& scene, const Vec3d& wanted) {
    if (scene.holdsNothing()) scene.origin = wanted;
    return scene.origin;
}

}  // namespace kiln
