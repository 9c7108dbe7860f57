#include "renderer/geometry/interaction.h"

#include <cmath>

namespace kiln {
namespace {

void faceForward(SurfaceInteraction& si, const Vec3& rayDir) {
    si.nsStored = si.ns;
    si.frontFace = dot(si.ng, rayDir) < 0;
    if (!si.frontFace) si.ng = -si.ng;
    if (dot(si.ns, si.ng) < 0) si.ns = -si.ns;
}

// The error bound of a point alone is not enough for Embree: its float intersection test reports t
// with an error of a few ulps of the coordinates involved (a point exactly on the plane y = 0 has a
// zero bound, yet Embree finds t = 0 there). So offsets never fall below kTraversalUlps ulps of the
// largest coordinate; docs/accelerators.md shows the crosscheck that found it.
constexpr float kTraversalUlps = 32.0f;

float traversalError(const Vec3& p) {
    return kTraversalUlps * std::numeric_limits<float>::epsilon() * maxComponent(abs(p));
}

// Both spawn origins: p pushed off along ng by the error bound projected on it (never below the
// traversal error). Adding the offset rounds each coordinate by at most half an ulp of the largest
// one, which moves the origin along ng by under sqrt(3) / 2 ulps: the offset carries 2 ulps more,
// so the origin always ends at least the bound away from p along ng (pbrt nudges each coordinate
// one ulp instead, a branch per axis on the offset's sign).
void setSpawnOrigins(SurfaceInteraction& si) {
    float largest = maxComponent(abs(si.p));
    float d = std::max(dot(abs(si.ng), si.pError), traversalError(si.p)) +
              2 * std::numeric_limits<float>::epsilon() * largest;
    Vec3 offset = si.ng * d;
    si.originFront = si.p + offset, si.originBack = si.p - offset;
}

}  // namespace

void prefetchHitIndices(const Scene& scene, const Hit& hit) {
    if (!hit.valid() || hit.shape == kSphereShape) return;
    __builtin_prefetch(&scene.meshes[hit.shape].indices[3 * size_t(hit.prim)]);
}

void prefetchHitVertices(const Scene& scene, const Hit& hit) {
    if (!hit.valid() || hit.shape == kSphereShape) return;
    const TriangleMesh& mesh = scene.meshes[hit.shape];
    const uint32_t* idx = &mesh.indices[3 * size_t(hit.prim)];
    for (int k = 0; k < 3; ++k) {
        __builtin_prefetch(&mesh.positions[3 * size_t(idx[k])]);
        if (!mesh.normals.empty()) __builtin_prefetch(&mesh.normals[3 * size_t(idx[k])]);
    }
}

SurfaceInteraction surfacePoint(const Vec3& p, const Vec3& pError, const Vec3& n) {
    SurfaceInteraction si;
    si.p = p, si.pError = pError;
    si.ng = si.ns = si.nsStored = n;
    setSpawnOrigins(si);
    return si;
}

namespace {

SurfaceInteraction sphereInteraction(const Scene& scene, const Ray& ray, const Hit& hit) {
    const Sphere& s = scene.spheres[hit.prim];
    SurfaceInteraction si;
    si.t = hit.t;
    si.shape = hit.shape, si.prim = hit.prim, si.instance = hit.instance;
    Vec3 p = ray.origin + ray.dir * hit.t;
    Vec3 n = normalize(p - s.center);
    // Reproject onto the surface: the error is then a few ulps of the sphere's extent (pbrt).
    si.p = s.center + n * s.radius;
    si.pError = gamma(5) * (abs(s.center) + abs(n * s.radius));
    si.ng = si.ns = n;
    si.material = s.material;
    faceForward(si, ray.dir);
    setSpawnOrigins(si);
    return si;
}

}  // namespace

SurfaceInteraction makeInteraction(const Scene& scene, const Ray& ray, const Hit& hit) {
    if (hit.shape == kSphereShape) return sphereInteraction(scene, ray, hit);
    const TriangleMesh& mesh = scene.meshes[hit.shape];
    const uint32_t* idx = &mesh.indices[3 * hit.prim];
    Vec3 p0 = mesh.vertex(idx[0]), p1 = mesh.vertex(idx[1]), p2 = mesh.vertex(idx[2]);
    float b1 = hit.u, b2 = hit.v, b0 = 1 - b1 - b2;
    Vec3 p = p0 * b0 + p1 * b1 + p2 * b2;
    Vec3 err = gamma(7) * (abs(p0 * b0) + abs(p1 * b1) + abs(p2 * b2));
    Vec3 ng = cross(p1 - p0, p2 - p0);
    Vec3 ns = ng;
    if (!mesh.normals.empty()) {
        auto normalAt = [&](uint32_t i) {
            return Vec3(mesh.normals[3 * i], mesh.normals[3 * i + 1], mesh.normals[3 * i + 2]);
        };
        Vec3 n = normalAt(idx[0]) * b0 + normalAt(idx[1]) * b1 + normalAt(idx[2]) * b2;
        if (dot(n, n) > 0) ns = n;
    }
    if (hit.instance != kInvalidId) {
        const Mat4& xf = scene.instances[hit.instance].objectToWorld;
        Vec3 pw = xf.point(p);
        // Transforming adds its own rounding: bound it from the matrix magnitudes (pbrt's
        // Transform).
        Vec3 absP = abs(p), terr;
        for (int r = 0; r < 3; ++r) {
            double absRow = std::abs(xf.m[r][0]) * absP.x + std::abs(xf.m[r][1]) * absP.y +
                            std::abs(xf.m[r][2]) * absP.z + std::abs(xf.m[r][3]);
            double errRow = std::abs(xf.m[r][0]) * err.x + std::abs(xf.m[r][1]) * err.y +
                            std::abs(xf.m[r][2]) * err.z;
            terr[r] = float((gamma(3) + 1) * errRow + gamma(3) * absRow);
        }
        err = terr;
        p = pw;
        const Mat4& inv = scene.instances[hit.instance].worldToObject;
        ng = transformNormal(inv, ng);
        ns = transformNormal(inv, ns);
    }
    Vec3 unitNg = normalize(ng);
    if (!isFinite(unitNg)) unitNg = -normalize(ray.dir);  // zero-area triangle: face the ray
    Vec3 unitNs = mesh.normals.empty() ? unitNg : normalize(ns);
    if (!isFinite(unitNs)) unitNs = unitNg;
    // Every field given here, once: a default-constructed interaction was zeroed in memory first
    // (a string store on every hit) and then overwritten.
    SurfaceInteraction si{.p = p,
                          .pError = err,
                          .ng = unitNg,
                          .ns = unitNs,
                          .nsStored = unitNs,
                          .originFront = p,
                          .originBack = p,
                          .t = hit.t,
                          .material = mesh.materialOf(hit.prim),
                          .shape = hit.shape,
                          .prim = hit.prim,
                          .instance = hit.instance,
                          .frontFace = true};
    faceForward(si, ray.dir);
    setSpawnOrigins(si);
    return si;
}

Ray spawnRay(const SurfaceInteraction& si, const Vec3& dir) {
    return Ray{offsetRayOrigin(si, dir), 0.0f, dir, kInfinity};
}

Ray spawnRayTo(const SurfaceInteraction& si, const Vec3& target, const Vec3& targetError) {
    Vec3 o = offsetRayOrigin(si, target - si.p);
    Vec3 d = target - o;
    float len2 = dot(d, d);
    if (len2 == 0) return Ray{o, 0.0f, d, 0.0f};
    // Stop short of the target by its own error bound along the ray (and Embree's distance error),
    // so the surface the target lies on cannot occlude it: a bound, not a guess. In units of t (|d|
    // = len): (dot(|d|, err) / len + traversal) / len.
    float invLen = 1.0f / std::sqrt(len2);
    float shortBy = dot(abs(d), targetError) * invLen + traversalError(target);
    return Ray{o, 0.0f, d, std::max(0.0f, 1.0f - 2 * shortBy * invLen)};
}

}  // namespace kiln
