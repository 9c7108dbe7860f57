// Camera placement for batches: a look-at camera and the turntable orbit about an axis.
#pragma once

#include "scene/scene.h"

namespace kiln {

// Points the camera from `position` at `target` with `up` as the roll reference. Throws
// std::invalid_argument when the position equals the target or up is parallel to the view.
void pointCamera(Camera& camera, Vec3 position, Vec3 target, Vec3 up);

// The camera turned about the line through `centre` along `axis` by frame/frames of a full turn
// (right-handed about the axis): position, forward and up rotate together, so frame 0 is the
// camera itself and every frame keeps its distance to the axis and its framing.
Camera orbitCamera(const Camera& camera, Vec3 centre, Vec3 axis, int frames, int frame);

}  // namespace kiln
