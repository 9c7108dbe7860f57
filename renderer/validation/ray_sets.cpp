#include "renderer/validation/ray_sets.h"

#include <cmath>

#include "renderer/core/sampler.h"
#include "renderer/core/warp.h"
#include "renderer/geometry/camera.h"
#include "renderer/geometry/interaction.h"

namespace kiln {
namespace {

// A point on some light, or a random point in the bounds when the light has no position.
Vec3 lightPoint(const Scene& scene, Sampler& s, const Bounds3& b) {
    if (!scene.lights.empty()) {
        const Light& l = scene.lights[std::min(scene.lights.size() - 1,
                                               size_t(s.next1D() * scene.lights.size()))];
        float u = s.next1D() - 0.5f, v = s.next1D() - 0.5f;
        if (l.kind == LightKind::Area) return l.position + l.dimX * u + l.dimY * v;
        if (l.kind == LightKind::Point || l.kind == LightKind::Spot) return l.position;
        if (l.kind == LightKind::MeshEmitter) {
            const TriangleMesh& m = scene.meshes[l.mesh];
            size_t tri = std::min(m.triangleCount() - 1, size_t(s.next1D() * m.triangleCount()));
            float a = s.next1D(), c = s.next1D();
            if (a + c > 1) a = 1 - a, c = 1 - c;
            const uint32_t* idx = &m.indices[3 * tri];
            return m.vertex(idx[0]) * (1 - a - c) + m.vertex(idx[1]) * a + m.vertex(idx[2]) * c;
        }
    }
    Vec3 d = b.diagonal();
    return b.lo + Vec3(d.x * s.next1D(), d.y * s.next1D(), d.z * s.next1D());
}

}  // namespace

const char* toString(RaySetKind kind) {
    switch (kind) {
        case RaySetKind::Camera:
            return "camera";
        case RaySetKind::Random:
            return "random";
        case RaySetKind::Secondary:
            return "secondary";
        case RaySetKind::Shadow:
            return "shadow";
    }
    return "?";
}

std::vector<Ray> makeCoherentCameraRays(const Scene& scene, int width, int height, size_t count) {
    CameraModel camera(scene.camera, width, height);
    int blocksX = (width + 3) / 4, blocksY = (height + 3) / 4;
    size_t blocks = size_t(blocksX) * size_t(blocksY);
    // Spread the blocks evenly over the whole image whatever the count, so empty rows do not skew
    // rates.
    size_t wanted = std::max<size_t>(1, (count + 15) / 16);
    double stride = double(blocks) / double(wanted);
    std::vector<Ray> rays;
    rays.reserve(count);
    for (size_t k = 0; rays.size() < count; ++k) {
        size_t block = size_t(double(k % wanted) * stride) % blocks;
        int bx = int(block % size_t(blocksX)) * 4, by = int(block / size_t(blocksX)) * 4;
        for (int y = by; y < std::min(by + 4, height); ++y)
            for (int x = bx; x < std::min(bx + 4, width); ++x)
                rays.push_back(camera.generateRay(float(x) + 0.5f, float(y) + 0.5f));
    }
    rays.resize(count);
    return rays;
}

std::vector<Ray> makeRaySet(RaySetKind kind, const Scene& scene, const Accelerator& finder,
                            size_t count, uint64_t seed) {
    std::vector<Ray> rays;
    rays.reserve(count);
    Bounds3 b = scene.storedBounds();
    Vec3 pad = b.diagonal() * 0.05f;
    Bounds3 big{b.lo - pad, b.hi + pad};
    CameraModel camera(scene.camera, 800, 600);
    uint64_t attempt = 0;
    // Secondary/shadow rays need a surface point: retry camera rays that miss, with a cap.
    while (rays.size() < count && attempt < count * 20 + 1000) {
        Sampler s(seed, uint64_t(kind), attempt++);
        if (kind == RaySetKind::Camera) {
            rays.push_back(camera.generateRay(s.next1D() * 800, s.next1D() * 600));
            continue;
        }
        if (kind == RaySetKind::Random) {
            Vec3 d = big.diagonal();
            Vec3 o = big.lo + Vec3(d.x * s.next1D(), d.y * s.next1D(), d.z * s.next1D());
            rays.push_back(Ray{o, 0.0f, uniformSphere(s.next1D(), s.next1D()), kInfinity});
            continue;
        }
        // Start from a visible surface point, then bounce once more half of the time so the set
        // also holds points the camera cannot see (the distribution a path tracer makes).
        Ray primary = camera.generateRay(s.next1D() * 800, s.next1D() * 600);
        Hit hit;
        if (!finder.intersect(primary, hit)) continue;
        SurfaceInteraction si = makeInteraction(scene, primary, hit);
        if (s.next1D() < 0.5f) {
            Vec3 dir = uniformSphere(s.next1D(), s.next1D());
            if (dot(dir, si.ng) < 0) dir = -dir;
            Ray bounce = spawnRay(si, dir);
            Hit h2;
            if (finder.intersect(bounce, h2)) si = makeInteraction(scene, bounce, h2);
        }
        if (kind == RaySetKind::Secondary) {
            Vec3 dir = uniformSphere(s.next1D(), s.next1D());
            if (dot(dir, si.ng) < 0 && s.next1D() < 0.8f)
                dir = -dir;  // mostly reflection, some transmission
            rays.push_back(spawnRay(si, dir));
        } else {
            rays.push_back(spawnRayTo(si, lightPoint(scene, s, b)));
        }
    }
    return rays;
}

}  // namespace kiln
