#include "renderer/cli/camera_options.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "renderer/geometry/turntable.h"
#include "scene/scene_loader.h"

namespace kiln {
namespace {

// Three coordinates, each finite once stored as a float (1e39 is not). A point lies within the
// span kiln traces (kMaxSceneExtent: beyond it float distances overflow, and Embree asserts on
// the rays); a direction (nonZero) must not be (0, 0, 0), and is scaled to its largest component
// (a length of (1e30, 0, 0) would overflow).
ArgParser::Handler vec3Into(std::optional<Vec3>& target, std::string name, bool nonZero = false) {
    return [&target, name, nonZero](const std::vector<std::string>& v) {
        float xyz[3];
        for (int k = 0; k < 3; ++k) {
            xyz[k] = float(ArgParser::toDouble(name, v[size_t(k)]));
            if (!std::isfinite(xyz[k]))
                throw UsageError(name + " takes finite coordinates (at most 3.4e38), got '" +
                                 v[size_t(k)] + "'");
            if (!nonZero && std::abs(xyz[k]) > kMaxSceneExtent)
                throw UsageError(
                    fmt::format("{} takes coordinates within +-{:.0e} (the span "
                                "kiln traces), got '{}'",
                                name, double(kMaxSceneExtent), v[size_t(k)]));
        }
        if (!nonZero) {
            target = Vec3(xyz[0], xyz[1], xyz[2]);
            return;
        }
        const float largest = std::max({std::abs(xyz[0]), std::abs(xyz[1]), std::abs(xyz[2])});
        if (largest == 0) throw UsageError(name + " takes a direction, got (0, 0, 0)");
        target = Vec3(xyz[0] / largest, xyz[1] / largest, xyz[2] / largest);
    };
}

// World coordinates to the scene's stored (recentred) ones.
Vec3 stored(const Scene& scene, Vec3 world) { return Vec3(Vec3d(world) - scene.origin); }

}  // namespace

void CameraOptions::addOptions(ArgParser& parser) {
    OptionGroup group(parser, "Camera");
    parser.option("position", "", 3, "X Y Z", "camera position (world coordinates)",
                  vec3Into(position, "--position"));
    parser.option("look-at", "", 3, "X Y Z", "point the camera looks at (default: bbox centre)",
                  vec3Into(lookAt, "--look-at"));
    parser.option("up", "", 3, "X Y Z", "camera up vector (default: the scene camera's)",
                  vec3Into(up, "--up", true));
    parser.option("fov", "", 1, "DEG", "field of view of the image's shorter side in degrees",
                  [this](const std::vector<std::string>& v) {
                      fovDeg = float(ArgParser::toDouble("--fov", v[0]));
                      if (!(fovDeg > 0 && fovDeg < 180))
                          throw UsageError("--fov must be between 0 and 180 degrees");
                  });
    parser.intOption("turntable", "", "N cameras orbiting the scene (pick one with --frame)",
                     turntable, 1, 1 << 20);
    parser.intOption("frame", "", "the turntable frame to render, 0..N-1", frame, 0, 1 << 20);
    parser.option("orbit-axis", "", 3, "X Y Z", "turntable axis (default: the camera's up)",
                  vec3Into(orbitAxis, "--orbit-axis", true));
    parser.option("orbit-centre", "", 3, "X Y Z",
                  "a point on the turntable axis (default: bbox centre)",
                  vec3Into(orbitCentre, "--orbit-centre"));
}

void CameraOptions::check() const {
    if ((turntable > 0) != (frame >= 0)) throw UsageError("--turntable and --frame go together");
    if (turntable > 0 && frame >= turntable)
        throw UsageError("--frame " + std::to_string(frame) + " is not below --turntable " +
                         std::to_string(turntable));
    if (position && lookAt && *position == *lookAt)
        throw UsageError("--position and --look-at are the same point");
    // All three given, the view needs nothing of the scene: an up along it is refused before the
    // load, with the words it would get after.
    if (position && lookAt && up) try {
            Camera scratch;
            pointCamera(scratch, *position, *lookAt, *up);
        } catch (const std::invalid_argument& e) {
            throw UsageError(e.what());
        }
}

void CameraOptions::apply(Scene& scene, const Bounds3& storedBounds) const {
    check();
    Camera& cam = scene.camera;
    Vec3 centre = storedBounds.centroid();
    try {
        if (position || lookAt || up)
            pointCamera(cam, position ? stored(scene, *position) : cam.position,
                        lookAt ? stored(scene, *lookAt) : centre, up ? *up : cam.up);
        if (fovDeg > 0) {  // a perspective view on the shorter side, whatever the file's was
            cam.hFovDeg = cam.vFovDeg = fovDeg;
            cam.fovAxis = Camera::FovAxis::Fit;
            cam.orthoHalfWidth = cam.orthoHalfHeight = 0;
        }
        if (turntable > 0)
            cam = orbitCamera(cam, orbitCentre ? stored(scene, *orbitCentre) : centre,
                              orbitAxis ? *orbitAxis : cam.up, turntable, frame);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    // The camera moved: within the span kiln traces with the scene, as a file's camera must be.
    if (position || lookAt || up || fovDeg > 0 || turntable > 0) validateView(scene, storedBounds);
}

}  // namespace kiln
