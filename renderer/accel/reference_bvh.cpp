#include "renderer/accel/reference_bvh.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "renderer/geometry/opacity.h"
#include "renderer/geometry/shapes.h"

namespace kiln {
namespace {

Bounds3 triangleBounds(const TriangleMesh& m, uint32_t tri) {
    Bounds3 b;
    for (int k = 0; k < 3; ++k) b.extend(m.vertex(m.indices[3 * tri + k]));
    return b;
}

}  // namespace

ReferenceAccelerator::ReferenceAccelerator(const Scene& scene, const ReferenceBvhOptions& options)
    : scene_(scene) {
    auto start = std::chrono::steady_clock::now();
    std::vector<bool> proto = scene.prototypeMask();
    std::vector<Bounds3> boxes;
    prototypeBvh_.resize(scene.meshes.size());
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) alphaMesh_.push_back(meshHasAlpha(scene, m));
    hasAlpha_ = std::find(alphaMesh_.begin(), alphaMesh_.end(), true) != alphaMesh_.end();
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.meshes[m];
        uint32_t n = uint32_t(mesh.triangleCount());
        if (proto[m]) {
            std::vector<Bounds3> local(n);
            for (uint32_t t = 0; t < n; ++t) local[t] = triangleBounds(mesh, t);
            prototypeBvh_[m].build(local, options);
            continue;
        }
        for (uint32_t t = 0; t < n; ++t) {
            items_.push_back({ItemKind::Triangle, m, t});
            boxes.push_back(triangleBounds(mesh, t));
        }
    }
    for (uint32_t s = 0; s < scene.spheres.size(); ++s) {
        const Sphere& sp = scene.spheres[s];
        items_.push_back({ItemKind::Sphere, s, 0});
        Bounds3 b;
        float pad = sp.radius * 1e-6f;
        b.extend(sp.center - Vec3(sp.radius + pad));
        b.extend(sp.center + Vec3(sp.radius + pad));
        boxes.push_back(b);
    }
    for (uint32_t j = 0; j < scene.instances.size(); ++j) {
        const Instance& inst = scene.instances[j];
        const Bounds3& local = prototypeBvh_[inst.mesh].bounds();
        if (local.empty()) continue;
        Bounds3 b;
        for (int c = 0; c < 8; ++c)
            b.extend(inst.objectToWorld.point(Vec3((c & 1) ? local.hi.x : local.lo.x,
                                                   (c & 2) ? local.hi.y : local.lo.y,
                                                   (c & 4) ? local.hi.z : local.lo.z)));
        items_.push_back({ItemKind::Instance, j, 0});
        boxes.push_back(b);
    }
    top_.build(boxes, options);
    stats_.buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats_.memoryBytes = top_.memoryBytes() + items_.size() * sizeof(Item);
    for (const Bvh& b : prototypeBvh_) stats_.memoryBytes += b.memoryBytes();
    stats_.description = std::string("reference bvh ") + toString(options.split) + " leaf " + std::to_string(options.maxLeafSize);
}

bool ReferenceAccelerator::testTriangle(const TriangleMesh& mesh, uint32_t tri, Ray& ray, Hit* hit,
                                        uint32_t instance, uint32_t seed) const {
    const uint32_t* idx = &mesh.indices[3 * tri];
    float t, u, v;
    if (!intersectTriangle(ray, mesh.vertex(idx[0]), mesh.vertex(idx[1]), mesh.vertex(idx[2]), t, u,
                           v))
        return false;
    uint32_t shape = uint32_t(&mesh - scene_.meshes.data());
    if (alphaMesh_[shape] && !surfaceStopsRay(scene_, shape, tri, u, v, instance, seed))
        return false;
    // A tie with the current hit (duplicate surfaces): the lowest (mesh, triangle) wins, as in
    // Embree.
    if (hit && t == ray.tMax && hit->shape != kInvalidId && hit->instance == kInvalidId &&
        std::make_pair(shape, tri) > std::make_pair(hit->shape, hit->prim))
        return false;
    ray.tMax = t;
    if (hit) hit->t = t, hit->u = u, hit->v = v, hit->prim = tri;
    return true;
}

template <bool AnyHit>
bool ReferenceAccelerator::trace(Ray& ray, Hit* hit, TraversalCounters* counters) const {
    uint32_t seed = hasAlpha_ ? raySeed(ray) : 0;
    return top_.traverse<AnyHit>(
        ray,
        [&](uint32_t itemIndex, Ray& r) {
            const Item& item = items_[itemIndex];
            switch (item.kind) {
                case ItemKind::Triangle:
                    if (!testTriangle(scene_.meshes[item.a], item.b, r, hit, kInvalidId, seed))
                        return false;
                    if (hit) hit->shape = item.a, hit->instance = kInvalidId;
                    return true;
                case ItemKind::Sphere: {
                    const Sphere& s = scene_.spheres[item.a];
                    float t;
                    if (!intersectSphere(r, s.center, s.radius, t)) return false;
                    r.tMax = t;
                    if (hit) *hit = Hit{t, 0, 0, kSphereShape, item.a, kInvalidId};
                    return true;
                }
                case ItemKind::Instance: {
                    // Same parametrisation in object space: transform origin and direction, keep t.
                    const Mat4& w2o = scene_.instances[item.a].worldToObject;
                    uint32_t mesh = scene_.instances[item.a].mesh;
                    Ray local{w2o.point(r.origin), r.tMin, w2o.vector(r.dir), r.tMax};
                    bool any = prototypeBvh_[mesh].traverse<AnyHit>(
                        local,
                        [&](uint32_t tri, Ray& lr) {
                            return testTriangle(scene_.meshes[mesh], tri, lr, hit, item.a, seed);
                        },
                        counters);
                    if (!any) return false;
                    r.tMax = local.tMax;
                    if (hit) hit->shape = mesh, hit->instance = item.a;
                    return true;
                }
            }
            return false;
        },
        counters);
}

bool ReferenceAccelerator::intersect(const Ray& ray, Hit& hit) const {
    Ray r = ray;
    Hit h;
    if (!trace<false>(r, &h, nullptr)) return false;
    hit = h;
    return true;
}

bool ReferenceAccelerator::intersect(const Ray& ray, Hit& hit, TraversalCounters& counters) const {
    Ray r = ray;
    Hit h;
    if (!trace<false>(r, &h, &counters)) return false;
    hit = h;
    return true;
}

bool ReferenceAccelerator::occluded(const Ray& ray) const {
    Ray r = ray;
    return trace<true>(r, nullptr, nullptr);
}

std::unique_ptr<Accelerator> makeReferenceAccelerator(const Scene& scene,
                                                      const ReferenceBvhOptions& options) {
    return std::make_unique<ReferenceAccelerator>(scene, options);
}

}  // namespace kiln
