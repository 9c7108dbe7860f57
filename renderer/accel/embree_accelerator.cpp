// Embree 3 traversal over the scene model's buffers (shared, not copied). Spheres are user geometry
// that runs the same sphere test as the reference BVH; instances use Embree instancing.
#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "renderer/accel/accelerator.h"
#include "renderer/geometry/opacity.h"
#include "renderer/geometry/shapes.h"

namespace kiln {
namespace {

std::atomic<int64_t> gEmbreeBytes{0};

// Embree calls this from C code, so it records the error instead of throwing through Embree; the
// accelerator checks after every build step and turns it into an exception with Embree's message.
void embreeError(void* userPtr, RTCError code, const char* message) {
    auto* last = static_cast<std::string*>(userPtr);
    if (last->empty())
        *last = "Embree error " + std::to_string(int(code)) + ": " +
                (message ? message : "(no message)");
}

bool embreeMemory(void*, ssize_t bytes, bool) {
    gEmbreeBytes += bytes;
    return true;
}

// Embree traverses user geometry without its robust box test (only triangles get one): the slab
// distances then carry rounding of a few ulps of the coordinates of the box and of the ray
// origin. User primitives' boxes are padded by 2^-20 of the scene's largest coordinate, which
// covers ray origins up to about 8x that far out.
float userBoundsPad(const Scene& scene) {
    Bounds3 b = scene.storedBounds();
    if (b.empty()) return 0;
    Vec3 m = max(abs(b.lo), abs(b.hi));
    return std::max({m.x, m.y, m.z}) * 0x1p-20f;
}

struct SphereData {
    const std::vector<Sphere>* spheres;
    float pad = 0;
};

void sphereBounds(const RTCBoundsFunctionArguments* args) {
    const auto* data = static_cast<const SphereData*>(args->geometryUserPtr);
    const Sphere& s = (*data->spheres)[args->primID];
    // Padded by a relative ulp so Embree's float box never clips the exact sphere.
    float pad = s.radius * 1e-6f + data->pad + 1e-30f;
    args->bounds_o->lower_x = s.center.x - s.radius - pad;
    args->bounds_o->lower_y = s.center.y - s.radius - pad;
    args->bounds_o->lower_z = s.center.z - s.radius - pad;
    args->bounds_o->upper_x = s.center.x + s.radius + pad;
    args->bounds_o->upper_y = s.center.y + s.radius + pad;
    args->bounds_o->upper_z = s.center.z + s.radius + pad;
}

// Sphere callbacks for any packet width N (rtcIntersect1 calls with N = 1, rtcIntersect16 with 16).
Ray lane(RTCRayN* r, unsigned N, unsigned i) {
    return Ray{Vec3(RTCRayN_org_x(r, N, i), RTCRayN_org_y(r, N, i), RTCRayN_org_z(r, N, i)),
               RTCRayN_tnear(r, N, i),
               Vec3(RTCRayN_dir_x(r, N, i), RTCRayN_dir_y(r, N, i), RTCRayN_dir_z(r, N, i)),
               RTCRayN_tfar(r, N, i)};
}

void sphereIntersect(const RTCIntersectFunctionNArguments* args) {
    const Sphere& s =
        (*static_cast<const SphereData*>(args->geometryUserPtr)->spheres)[args->primID];
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (!args->valid[i]) continue;
        Ray ray = lane(rays, args->N, i);
        float t;
        if (!intersectSphere(ray, s.center, s.radius, t)) continue;
        RTCRayN_tfar(rays, args->N, i) = t;
        Vec3 n = ray.origin + ray.dir * t - s.center;
        RTCHitN_Ng_x(hits, args->N, i) = n.x;
        RTCHitN_Ng_y(hits, args->N, i) = n.y;
        RTCHitN_Ng_z(hits, args->N, i) = n.z;
        RTCHitN_u(hits, args->N, i) = 0;
        RTCHitN_v(hits, args->N, i) = 0;
        RTCHitN_primID(hits, args->N, i) = args->primID;
        RTCHitN_geomID(hits, args->N, i) = args->geomID;
        RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
    }
}

void sphereOccluded(const RTCOccludedFunctionNArguments* args) {
    const Sphere& s =
        (*static_cast<const SphereData*>(args->geometryUserPtr)->spheres)[args->primID];
    for (unsigned i = 0; i < args->N; ++i) {
        if (!args->valid[i]) continue;
        float t;
        if (intersectSphere(lane(args->ray, args->N, i), s.center, s.radius, t))
            RTCRayN_tfar(args->ray, args->N, i) = -kInfinity;
    }
}

// Triangles as user geometry (EmbreeOptions::watertight): Embree's BVH, kiln's watertight
// double-precision test (the reference BVH's, shapes.h). Embree's own float test is watertight
// along shared edges but can miss a ray passing within rounding of a shared vertex.
struct WatertightMeshData {
    const TriangleMesh* mesh;
    float pad = 0;
    const Scene* scene = nullptr;
    uint32_t index = 0;  // the mesh's index in the scene
    bool alpha = false;  // its materials have alpha: candidates pass the alpha test (opacity.h)
};

// A candidate the alpha test lets through (the ray's seed travels in its id, set from the
// world-space ray, so instanced geometry sees the same coin).
bool passesAlpha(const WatertightMeshData& d, unsigned prim, float u, float v, unsigned inst,
                 unsigned seed) {
    return d.alpha && !surfaceStopsRay(*d.scene, d.index, prim, u, v,
                                       inst == RTC_INVALID_GEOMETRY_ID ? kInvalidId : inst, seed);
}

void triangleCorners(const void* userPtr, unsigned prim, Vec3& a, Vec3& b, Vec3& c) {
    const TriangleMesh& m = *static_cast<const WatertightMeshData*>(userPtr)->mesh;
    const uint32_t* idx = &m.indices[3 * size_t(prim)];
    a = m.vertex(idx[0]), b = m.vertex(idx[1]), c = m.vertex(idx[2]);
}

void triangleBounds(const RTCBoundsFunctionArguments* args) {
    Vec3 a, b, c;
    triangleCorners(args->geometryUserPtr, args->primID, a, b, c);
    Vec3 lo = min(a, min(b, c)), hi = max(a, max(b, c));
    // The test's barycentric slack (1e-9 of an edge) may reach just past the float box: 1e-6 of
    // the extent covers it; the traversal's rounding is covered by the scene-wide pad.
    float scenePad = static_cast<const WatertightMeshData*>(args->geometryUserPtr)->pad;
    Vec3 pad = (hi - lo) * 1e-6f + Vec3(scenePad + 1e-30f);
    lo = lo - pad, hi = hi + pad;
    args->bounds_o->lower_x = lo.x, args->bounds_o->lower_y = lo.y, args->bounds_o->lower_z = lo.z;
    args->bounds_o->upper_x = hi.x, args->bounds_o->upper_y = hi.y, args->bounds_o->upper_z = hi.z;
}

bool watertightHit(const void* userPtr, unsigned prim, const Ray& ray, float& t, float& u,
                   float& v) {
    Vec3 a, b, c;
    triangleCorners(userPtr, prim, a, b, c);
    return intersectTriangle(ray, a, b, c, t, u, v);
}

void watertightIntersect(const RTCIntersectFunctionNArguments* args) {
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (!args->valid[i]) continue;
        float t, u, v;
        if (!watertightHit(args->geometryUserPtr, args->primID, lane(rays, args->N, i), t, u, v) ||
            passesAlpha(*static_cast<const WatertightMeshData*>(args->geometryUserPtr),
                        args->primID, u, v, args->context->instID[0], RTCRayN_id(rays, args->N, i)))
            continue;
        // A tie (duplicate triangles) goes to the lowest (geometry, triangle), as in the
        // reference BVH.
        unsigned curGeom = RTCHitN_geomID(hits, args->N, i);
        if (t == RTCRayN_tfar(rays, args->N, i) && curGeom != RTC_INVALID_GEOMETRY_ID &&
            std::make_pair(args->geomID, args->primID) >=
                std::make_pair(curGeom, RTCHitN_primID(hits, args->N, i)))
            continue;
        RTCRayN_tfar(rays, args->N, i) = t;
        RTCHitN_u(hits, args->N, i) = u;
        RTCHitN_v(hits, args->N, i) = v;
        RTCHitN_primID(hits, args->N, i) = args->primID;
        RTCHitN_geomID(hits, args->N, i) = args->geomID;
        RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
    }
}

void watertightOccluded(const RTCOccludedFunctionNArguments* args) {
    for (unsigned i = 0; i < args->N; ++i) {
        float t, u, v;
        if (args->valid[i] &&
            watertightHit(args->geometryUserPtr, args->primID, lane(args->ray, args->N, i), t, u,
                          v) &&
            !passesAlpha(*static_cast<const WatertightMeshData*>(args->geometryUserPtr),
                         args->primID, u, v, args->context->instID[0],
                         RTCRayN_id(args->ray, args->N, i)))
            RTCRayN_tfar(args->ray, args->N, i) = -kInfinity;
    }
}

// Exact duplicate triangles (the same surface twice) are hit at the same t; the lowest (mesh,
// triangle) wins, as in the reference BVH, so the image does not depend on which one a BVH visits
// first. Embree gives the filter the candidate and, in the RayHitN layout, the hit it would
// replace. Only installed on scenes that have duplicates (Scene::duplicateTriangles): it costs a
// callback per candidate hit.

bool sameTriangle(const Scene& scene, unsigned geomA, unsigned primA, unsigned geomB,
                  unsigned primB) {
    if (geomA >= scene.meshes.size() || geomB >= scene.meshes.size()) return false;
    const TriangleMesh& ma = scene.meshes[geomA];
    const TriangleMesh& mb = scene.meshes[geomB];
    Vec3 a[3], b[3];
    for (int k = 0; k < 3; ++k)
        a[k] = ma.vertex(ma.indices[3 * primA + k]), b[k] = mb.vertex(mb.indices[3 * primB + k]);
    for (int k = 0; k < 3; ++k)
        if (!(a[k] == b[0] || a[k] == b[1] || a[k] == b[2])) return false;
    return true;
}

// Candidates on a mesh with alpha that the alpha test lets through are rejected (valid = 0), for
// closest hits and occlusion alike.
void alphaFilter(const RTCFilterFunctionNArguments* args) {
    const auto& d = *static_cast<const WatertightMeshData*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i)
        if (args->valid[i] &&
            passesAlpha(d, RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
                        RTCHitN_v(args->hit, args->N, i), RTCHitN_instID(args->hit, args->N, i, 0),
                        RTCRayN_id(args->ray, args->N, i)))
            args->valid[i] = 0;
}

void lowestIdWinsFilter(const RTCFilterFunctionNArguments* args) {
    const auto& d = *static_cast<const WatertightMeshData*>(args->geometryUserPtr);
    const Scene& scene = *d.scene;
    if (d.alpha) alphaFilter(args);
    RTCHitN* current = RTCRayHitN_HitN(reinterpret_cast<RTCRayHitN*>(args->ray), args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (!args->valid[i]) continue;
        unsigned curGeom = RTCHitN_geomID(current, args->N, i),
                 curPrim = RTCHitN_primID(current, args->N, i);
        unsigned newGeom = RTCHitN_geomID(args->hit, args->N, i),
                 newPrim = RTCHitN_primID(args->hit, args->N, i);
        if (curGeom == RTC_INVALID_GEOMETRY_ID ||
            RTCHitN_instID(current, args->N, i, 0) != RTC_INVALID_GEOMETRY_ID)
            continue;
        if (std::make_pair(newGeom, newPrim) > std::make_pair(curGeom, curPrim) &&
            sameTriangle(scene, curGeom, curPrim, newGeom, newPrim))
            args->valid[i] = 0;
    }
}

RTCBuildQuality toEmbree(EmbreeOptions::Quality q) {
    switch (q) {
        case EmbreeOptions::Quality::Low:
            return RTC_BUILD_QUALITY_LOW;
        case EmbreeOptions::Quality::High:
            return RTC_BUILD_QUALITY_HIGH;
        default:
            return RTC_BUILD_QUALITY_MEDIUM;
    }
}

class EmbreeAccelerator final : public Accelerator {
  public:
    EmbreeAccelerator(const Scene& scene, const EmbreeOptions& options) : scene_(scene) {
        auto start = std::chrono::steady_clock::now();
        int64_t bytesBefore = gEmbreeBytes.load();
        std::string config =
            options.threads > 0 ? "threads=" + std::to_string(options.threads) : "";
        device_ = rtcNewDevice(config.c_str());
        if (!device_)
            throw std::runtime_error("Embree: cannot create device (error " +
                                     std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
        rtcSetDeviceErrorFunction(device_, embreeError, &lastError_);
        rtcSetDeviceMemoryMonitorFunction(device_, embreeMemory, nullptr);

        RTCSceneFlags flags = RTC_SCENE_FLAG_NONE;
        if (options.robust) flags = RTCSceneFlags(flags | RTC_SCENE_FLAG_ROBUST);
        if (options.compact) flags = RTCSceneFlags(flags | RTC_SCENE_FLAG_COMPACT);
        top_ = newScene(flags, options.quality);

        numMeshes_ = uint32_t(scene.meshes.size());
        watertight_ = options.watertight;
        float pad = userBoundsPad(scene);
        hasAlpha_ = sceneHasAlpha(scene);
        for (uint32_t m = 0; m < numMeshes_; ++m)
            watertightData_.push_back(
                {&scene.meshes[m], pad, &scene, m, hasAlpha_ && meshHasAlpha(scene, m)});
        std::vector<bool> proto = scene.prototypeMask();
        std::vector<RTCScene> protoScenes(scene.meshes.size(), nullptr);
        for (uint32_t m = 0; m < numMeshes_; ++m) {
            if (scene.meshes[m].triangleCount() == 0) continue;
            RTCGeometry g = options.watertight ? watertightGeometry(m, options.quality)
                                               : meshGeometry(scene.meshes[m], options.quality);
            if (!options.watertight) installFilters(g, m, proto[m]);
            if (proto[m]) {
                protoScenes[m] = newScene(flags, options.quality);
                rtcAttachGeometryByID(protoScenes[m], g, 0);
                rtcReleaseGeometry(g);
                rtcCommitScene(protoScenes[m]);
                prototypes_.push_back(protoScenes[m]);
            } else {
                rtcAttachGeometryByID(top_, g, m);
                rtcReleaseGeometry(g);
            }
        }
        if (!scene.spheres.empty()) {
            sphereData_.spheres = &scene.spheres;
            sphereData_.pad = userBoundsPad(scene);
            RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(g, unsigned(scene.spheres.size()));
            rtcSetGeometryUserData(g, &sphereData_);
            rtcSetGeometryBoundsFunction(g, sphereBounds, nullptr);
            rtcSetGeometryIntersectFunction(g, sphereIntersect);
            rtcSetGeometryOccludedFunction(g, sphereOccluded);
            rtcCommitGeometry(g);
            rtcAttachGeometryByID(top_, g, numMeshes_);
            rtcReleaseGeometry(g);
        }
        for (uint32_t j = 0; j < scene.instances.size(); ++j) {
            const Instance& inst = scene.instances[j];
            if (!protoScenes[inst.mesh]) continue;
            RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(g, protoScenes[inst.mesh]);
            float xf[12];
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) xf[r * 4 + c] = float(inst.objectToWorld.m[r][c]);
            rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xf);
            rtcCommitGeometry(g);
            rtcAttachGeometryByID(top_, g, numMeshes_ + 1 + j);
            rtcReleaseGeometry(g);
        }
        rtcCommitScene(top_);
        if (!lastError_.empty()) throw std::runtime_error(lastError_);
        stats_.buildSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        stats_.memoryBytes = uint64_t(std::max<int64_t>(0, gEmbreeBytes.load() - bytesBefore));
        stats_.description = std::string("embree ") + (options.robust ? "robust " : "") +
                             (options.watertight ? "watertight " : "") +
                             toString(options.quality);
    }

    ~EmbreeAccelerator() override {
        for (RTCScene s : prototypes_) rtcReleaseScene(s);
        if (top_) rtcReleaseScene(top_);
        if (device_) rtcReleaseDevice(device_);
    }

    bool intersect(const Ray& ray, Hit& hit) const override {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRayHit rh;
        setRay(rh.ray, ray);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(top_, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
        fillHit(hit, rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID, rh.hit.geomID,
                rh.hit.instID[0]);
        return true;
    }

    bool occluded(const Ray& ray) const override {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRay r;
        setRay(r, ray);
        rtcOccluded1(top_, &ctx, &r);
        return r.tfar == -kInfinity;
    }

    // Batches go through 16-wide packets: coherent rays (camera tiles) share traversal work. With
    // watertight (user-geometry) triangles Embree calls kiln lane by lane anyway, and single rays
    // are faster.
    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const override {
        if (watertight_) return Accelerator::intersect(rays, hits);
        for (size_t base = 0; base < rays.size(); base += 16) {
            alignas(64) int valid[16];
            alignas(64) RTCRayHit16 rh;
            size_t n = fillPacket(rays, base, valid, rh.ray);
            for (size_t i = 0; i < 16; ++i) {
                rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
            }
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            rtcIntersect16(valid, top_, &ctx, &rh);
            for (size_t i = 0; i < n; ++i) {
                Hit& hit = hits[base + i];
                hit = Hit{};
                if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
                fillHit(hit, rh.ray.tfar[i], rh.hit.u[i], rh.hit.v[i], rh.hit.primID[i],
                        rh.hit.geomID[i], rh.hit.instID[0][i]);
            }
        }
    }

    void occluded(std::span<const Ray> rays, std::span<uint8_t> result) const override {
        if (watertight_) return Accelerator::occluded(rays, result);
        for (size_t base = 0; base < rays.size(); base += 16) {
            alignas(64) int valid[16];
            alignas(64) RTCRay16 r16;
            size_t n = fillPacket(rays, base, valid, r16);
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            rtcOccluded16(valid, top_, &ctx, &r16);
            for (size_t i = 0; i < n; ++i) result[base + i] = r16.tfar[i] == -kInfinity ? 1 : 0;
        }
    }

    const AcceleratorStats& stats() const override { return stats_; }

  private:
    // Embree's ids -> ours: meshes keep their index, spheres are one user geometry after them, and
    // instances follow (instance j has id numMeshes + 1 + j).
    void fillHit(Hit& hit, float t, float u, float v, unsigned prim, unsigned geom,
                 unsigned inst) const {
        hit.t = t, hit.u = u, hit.v = v, hit.prim = prim;
        if (inst != RTC_INVALID_GEOMETRY_ID) {
            hit.instance = inst - numMeshes_ - 1;
            hit.shape = scene_.instances[hit.instance].mesh;
        } else {
            hit.instance = kInvalidId;
            hit.shape = geom == numMeshes_ ? kSphereShape : geom;
        }
    }

    // Rays [base, base + 16) into a packet; lanes past the end repeat the last ray and are masked
    // off.
    size_t fillPacket(std::span<const Ray> rays, size_t base, int* valid, RTCRay16& r) const {
        size_t n = std::min<size_t>(16, rays.size() - base);
        for (size_t i = 0; i < 16; ++i) {
            valid[i] = i < n ? -1 : 0;
            setLane(r, i, rays[base + std::min(i, n - 1)]);
        }
        return n;
    }

    void setLane(RTCRay16& r, size_t i, const Ray& ray) const {
        r.org_x[i] = ray.origin.x, r.org_y[i] = ray.origin.y, r.org_z[i] = ray.origin.z;
        r.dir_x[i] = ray.dir.x, r.dir_y[i] = ray.dir.y, r.dir_z[i] = ray.dir.z;
        r.tnear[i] = ray.tMin, r.tfar[i] = ray.tMax;
        r.time[i] = 0, r.mask[i] = 0xffffffffu, r.flags[i] = 0;
        r.id[i] = hasAlpha_ ? raySeed(ray) : unsigned(i);
    }

    void setRay(RTCRay& r, const Ray& ray) const {
        r.org_x = ray.origin.x, r.org_y = ray.origin.y, r.org_z = ray.origin.z;
        r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z;
        r.tnear = ray.tMin;
        r.tfar = ray.tMax;
        r.time = 0;
        r.mask = 0xffffffffu;
        r.id = hasAlpha_ ? raySeed(ray) : 0;
        r.flags = 0;
    }

    RTCScene newScene(RTCSceneFlags flags, EmbreeOptions::Quality q) {
        RTCScene s = rtcNewScene(device_);
        rtcSetSceneFlags(s, flags);
        rtcSetSceneBuildQuality(s, toEmbree(q));
        return s;
    }

    RTCGeometry meshGeometry(const TriangleMesh& mesh, EmbreeOptions::Quality q) {
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                   mesh.positions.data(), 0, 3 * sizeof(float), mesh.vertexCount());
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                   mesh.indices.data(), 0, 3 * sizeof(uint32_t),
                                   mesh.triangleCount());
        rtcSetGeometryBuildQuality(g, toEmbree(q));
        rtcCommitGeometry(g);
        return g;
    }

    // Duplicates (world-space meshes) and alpha are decided in filter functions, installed only
    // where needed: each costs a callback per candidate hit.
    void installFilters(RTCGeometry g, uint32_t m, bool prototype) {
        bool duplicates = scene_.duplicateTriangles > 0 && !prototype;
        bool alpha = watertightData_[m].alpha;
        if (!duplicates && !alpha) return;
        rtcSetGeometryUserData(g, &watertightData_[m]);
        rtcSetGeometryIntersectFilterFunction(g, duplicates ? lowestIdWinsFilter : alphaFilter);
        if (alpha) rtcSetGeometryOccludedFilterFunction(g, alphaFilter);
        rtcCommitGeometry(g);
    }

    RTCGeometry watertightGeometry(uint32_t m, EmbreeOptions::Quality q) {
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, unsigned(scene_.meshes[m].triangleCount()));
        rtcSetGeometryUserData(g, &watertightData_[m]);
        rtcSetGeometryBoundsFunction(g, triangleBounds, nullptr);
        rtcSetGeometryIntersectFunction(g, watertightIntersect);
        rtcSetGeometryOccludedFunction(g, watertightOccluded);
        rtcSetGeometryBuildQuality(g, toEmbree(q));
        rtcCommitGeometry(g);
        return g;
    }

    const Scene& scene_;
    std::string lastError_;
    RTCDevice device_ = nullptr;
    RTCScene top_ = nullptr;
    std::vector<RTCScene> prototypes_;
    SphereData sphereData_{};
    std::vector<WatertightMeshData> watertightData_;
    uint32_t numMeshes_ = 0;
    bool watertight_ = false;
    bool hasAlpha_ = false;  // rays carry their alpha coin's seed in their id
    AcceleratorStats stats_;
};

}  // namespace

std::unique_ptr<Accelerator> makeEmbreeAccelerator(const Scene& scene,
                                                   const EmbreeOptions& options) {
    return std::make_unique<EmbreeAccelerator>(scene, options);
}

}  // namespace kiln
