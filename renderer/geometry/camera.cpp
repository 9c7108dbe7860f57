#include "renderer/geometry/camera.h"

#include <cmath>

#include "renderer/core/warp.h"
#include "scene/framing.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace kiln {

CameraModel::CameraModel(const Camera& camera, int width, int height)
    : cam_(camera), width_(width), height_(height), hFov_(camera.hFovDeg), vFov_(camera.vFovDeg) {
    // A camera that did not come through loadScene is checked here: no invalid ray reaches Embree.
    validateCamera("camera", camera);
    if (width <= 0 || height <= 0)
        throw SceneError("camera", "image size must be positive, not " + std::to_string(width) +
                                       " x " + std::to_string(height));
    if (camera.orthographic()) {
        tanX_ = camera.orthoHalfWidth, tanY_ = camera.orthoHalfHeight;
        fitOrthoToAspect(tanX_, tanY_, float(width) / float(height));
    } else {
        fitFov(camera.fovAxis, float(width), float(height));
        tanX_ = std::tan(radians(hFov_) / 2);
        tanY_ = std::tan(radians(vFov_) / 2);
    }
    xScale_ = 2.0f / float(width), yScale_ = 2.0f / float(height);
    forward_ = normalize(camera.forward);
    right_ = cross(forward_, camera.up);
    if (dot(right_, right_) < 1e-12f) {  // up parallel to forward: pick any perpendicular
        Vec3 t;
        orthonormalBasis(forward_, right_, t);
    }
    right_ = normalize(right_);
    up_ = cross(right_, forward_);
}

void CameraModel::fitFov(Camera::FovAxis axis, float width, float height) {
    float aspect = width / height;
    // One stated angle (in hFovDeg) spans the named axis; the other follows from the aspect.
    float tanStated = std::tan(radians(hFov_) / 2), tanX = 0, tanY = 0;
    switch (axis) {
        case Camera::FovAxis::Fit:
            fitFovToAspect(hFov_, vFov_, aspect);
            return;
        case Camera::FovAxis::Horizontal:
            tanX = tanStated, tanY = tanStated / aspect;
            break;
        case Camera::FovAxis::Vertical:
            tanY = tanStated, tanX = tanStated * aspect;
            break;
        case Camera::FovAxis::Diagonal: {
            float diagonal = std::hypot(width, height);
            tanX = tanStated * width / diagonal, tanY = tanStated * height / diagonal;
            break;
        }
    }
    hFov_ = 2 * degrees(std::atan(tanX));
    vFov_ = 2 * degrees(std::atan(tanY));
}

Ray CameraModel::generateRay(float px, float py, float lensU, float lensV) const {
    float x = (px * xScale_ - 1.0f) * tanX_;
    float y = (1.0f - py * yScale_) * tanY_;
    if (cam_.orthographic())  // parallel rays; clip planes are distances from the camera plane
        return Ray{cam_.position + right_ * x + up_ * y, cam_.nearClip, forward_, cam_.farClip};
    const Vec3 towards = right_ * x + up_ * y + forward_;
    const float len = length(towards);
    Vec3 dir = towards / len;
    Ray ray{cam_.position, 0.0f, dir, kInfinity};
    // Clip planes are distances along the view axis, as in the course program: 1 / cos of the
    // ray's angle to it is len up to rounding, since towards is 1 along the unit forward_ (right_
    // and up_ are perpendicular to it). That saves a division after the square root; the clip
    // distances move by ulps (at the default near plane, 1e-3, by about 1e-10).
    ray.tMin = cam_.nearClip * len;
    ray.tMax = cam_.farClip * len;
    if (cam_.apertureRadius > 0) {
        // Thin lens: concentric disk sample, aim at the point on the plane of focus.
        float dx, dy;
        concentricDisk(lensU, lensV, dx, dy);
        Vec3 lens = (right_ * dx + up_ * dy) * cam_.apertureRadius;
        const float invCos = 1.0f / dot(dir, forward_);  // as before: thin-lens images unchanged
        Vec3 focus = cam_.position + dir * (cam_.focalDistance * invCos);
        ray.origin = cam_.position + lens;
        Vec3 d = normalize(focus - ray.origin);
        float c = dot(d, forward_);
        ray.dir = d;
        ray.tMin = cam_.nearClip / c;
        ray.tMax = cam_.farClip / c;
    }
    return ray;
}

}  // namespace kiln
