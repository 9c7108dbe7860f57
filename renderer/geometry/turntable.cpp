#include "renderer/geometry/turntable.h"

#include <cmath>
#include <stdexcept>

namespace kiln {
namespace {

// Rodrigues' rotation of v about the unit axis k by angle (radians); in double so 1,000 frames
// of a large scene do not drift.
Vec3 rotateAbout(Vec3 v, Vec3 k, double angle) {
    Vec3d vd(v), kd(k);
    double c = std::cos(angle), s = std::sin(angle);
    Vec3d r = vd * c + cross(kd, vd) * s + kd * (dot(kd, vd) * (1.0 - c));
    return Vec3(r);
}

}  // namespace

void pointCamera(Camera& camera, Vec3 position, Vec3 target, Vec3 up) {
    Vec3 view = target - position;
    if (!(length(view) > 0)) throw std::invalid_argument("the camera position equals its target");
    Vec3 forward = normalize(view);
    if (!(length(up) > 0) || !(length(cross(forward, normalize(up))) > 1e-6f))
        throw std::invalid_argument("the up vector is zero or parallel to the view direction");
    camera.position = position;
    camera.forward = forward;
    camera.up = normalize(up);
}

Camera orbitCamera(const Camera& camera, Vec3 centre, Vec3 axis, int frames, int frame) {
    if (frames < 1 || frame < 0 || frame >= frames)
        throw std::invalid_argument("turntable frame " + std::to_string(frame) + " is not in 0.." +
                                    std::to_string(frames - 1));
    if (!(length(axis) > 0)) throw std::invalid_argument("the turntable axis is zero");
    if (frame == 0) return camera;  // exactly the framed camera, no rounding through the rotation
    Vec3 k = normalize(axis);
    double angle = 2.0 * 3.14159265358979323846 * frame / frames;
    Camera turned = camera;
    turned.position = centre + rotateAbout(camera.position - centre, k, angle);
    turned.forward = normalize(rotateAbout(camera.forward, k, angle));
    turned.up = normalize(rotateAbout(camera.up, k, angle));
    return turned;
}

}  // namespace kiln
