#include "scene/framing.h"

#include <cmath>

namespace kiln {

void applyCs184Framing(Scene& scene) {
    Bounds3 b = scene.storedBounds();
    if (b.empty()) return;
    Vec3 target = b.centroid();
    float distance = 1.5f * length(b.diagonal());
    Vec3 dir = scene.camera.cs184Direction;
    // The course nudges phi away from the poles so the up vector stays defined.
    if (std::abs(dir.y) > 0.9999f) dir = normalize(Vec3(dir.x, dir.y, dir.z + 1e-4f));
    scene.camera.position = target + dir * distance;
    scene.camera.forward = -dir;
    scene.camera.up = Vec3(0, 1, 0);  // the course's up vector (sin(phi) >= 0 always)
}

namespace {

// Sum over the lights of the cosine between the view direction (towards the camera) and the
// direction from which each light arrives; ambient and environment lights count for neither side.
float lightsFacing(const Scene& scene, Vec3 target, Vec3 dir) {
    float facing = 0;
    for (const Light& l : scene.lights) {
        Vec3 from(0.0f);
        if (l.kind == LightKind::Directional)
            from = -l.direction;
        else if (l.kind == LightKind::Point || l.kind == LightKind::Spot ||
                 l.kind == LightKind::Area)
            from = l.position - target;
        if (length(from) > 0) facing += dot(normalize(from), dir);
    }
    return facing;
}

}  // namespace

void applyDefaultFraming(Scene& scene) {
    Bounds3 b = scene.storedBounds();
    if (b.empty()) return;
    Camera& cam = scene.camera;
    cam.hFovDeg = 40.0f;
    cam.vFovDeg = 30.0f;
    Vec3 target = b.centroid();
    float radius = 0.5f * length(b.diagonal());
    Vec3 dir = normalize(Vec3(0.0f, 0.25f, 1.0f));
    // Lights behind the scene light only the side the front view cannot see (AC's
    // SphereWithLight renders black): look from the back when the lights are mostly there.
    if (lightsFacing(scene, target, dir) < 0) dir.z = -dir.z;
    // A flat scene seen (nearly) edge-on shows nothing: look along its normal axis instead.
    Vec3 size = b.diagonal();
    int thin = size.x <= size.y && size.x <= size.z ? 0 : (size.y <= size.z ? 1 : 2);
    if (size[thin] <= 1e-4f * maxComponent(size) && std::abs(dir[thin]) < 0.1f) {
        Vec3 normal(0.0f);
        normal[thin] = 1.0f;
        dir = normalize(normal + (thin == 1 ? Vec3(0.0f, 0.0f, 0.25f) : Vec3(0.0f, 0.25f, 0.0f)));
    }
    float halfFov = radians(0.5f * std::min(cam.hFovDeg, cam.vFovDeg));
    float distance = radius / std::sin(halfFov) * 1.05f;
    cam.position = target + dir * distance;
    cam.forward = -dir;
    cam.up = Vec3(0, 1, 0);
    cam.nearClip = distance * 1e-4f;
    cam.fromFile = false;
}

void fitOrthoToAspect(float& halfWidth, float& halfHeight, float aspect) {
    if (halfWidth < halfHeight * aspect)
        halfWidth = halfHeight * aspect;
    else if (halfWidth > halfHeight * aspect)
        halfHeight = halfWidth / aspect;
}

void fitFovToAspect(float& hFovDeg, float& vFovDeg, float aspect) {
    float fileAspect = std::tan(radians(hFovDeg) / 2) / std::tan(radians(vFovDeg) / 2);
    if (fileAspect < aspect)
        hFovDeg = 2 * degrees(std::atan(std::tan(radians(vFovDeg) / 2) * aspect));
    else if (fileAspect > aspect)
        vFovDeg = 2 * degrees(std::atan(std::tan(radians(hFovDeg) / 2) / aspect));
}

}  // namespace kiln
