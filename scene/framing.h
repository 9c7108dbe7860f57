// Camera placement rules: the CS184 course framing and a default framing for files without a
// camera.
#pragma once

#include "scene/scene.h"

namespace kiln {

// The course rule: camera at bbox centroid + direction * 1.5 * |bbox diagonal|, looking at the
// centroid.
void applyCs184Framing(Scene& scene);

// Files with no camera: look at the bounding sphere from the front (+Z), slightly above, and fit
// it.
void applyDefaultFraming(Scene& scene);

// Widens one field of view so that tan(h/2)/tan(v/2) equals the image aspect (the course's rule).
void fitFovToAspect(float& hFovDeg, float& vFovDeg, float aspect);
// The same rule for an orthographic camera's half width and height.
void fitOrthoToAspect(float& halfWidth, float& halfHeight, float aspect);

}  // namespace kiln
