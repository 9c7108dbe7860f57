// Camera options of kiln render for batches: an override (position, look-at, up, fov) and the
// turntable (--turntable N --frame K about an axis and centre), applied after the scene is framed.
#pragma once

#include <optional>

#include "renderer/cli/cli_args.h"
#include "scene/scene.h"

namespace kiln {

struct CameraOptions {
    std::optional<Vec3> position, lookAt, up, orbitAxis, orbitCentre;  // world coordinates
    float fovDeg = -1;
    int turntable = 0, frame = -1;

    // --position --look-at --up --fov --turntable --frame --orbit-axis --orbit-centre
    void addOptions(ArgParser& parser);
    // What the options say alone (the turntable and its frame, distinct points); throws UsageError.
    void check() const;
    // The override, then the orbit; throws UsageError on an impossible camera.
    // storedBounds: the scene's (the orbit's and --position's default centre), found once per
    // load by a process that renders many frames of it.
    void apply(Scene& scene, const Bounds3& storedBounds) const;
};

}  // namespace kiln
