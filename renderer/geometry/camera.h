// Camera rays: pinhole (sensor at z = -1 in camera space, as CS184) or thin lens.
#pragma once

#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

class CameraModel {
  public:
    // Fits the field of view to the image aspect by widening one angle (the course's rule).
    CameraModel(const Camera& camera, int width, int height);
    // (px, py): continuous raster position, y down; lens: two uniform numbers for thin-lens
    // sampling.
    Ray generateRay(float px, float py, float lensU = 0.5f, float lensV = 0.5f) const;
    float hFovDeg() const { return hFov_; }
    float vFovDeg() const { return vFov_; }

  private:
    // The field of view for this image size: the file's two angles fitted (Camera::FovAxis::Fit),
    // or the one stated angle on its axis.
    void fitFov(Camera::FovAxis axis, float width, float height);
    Camera cam_;
    int width_, height_;
    float hFov_, vFov_, tanX_, tanY_;
    float xScale_, yScale_;  // raster to [-1, 1]: 2 / width, 2 / height
    Vec3 right_, up_, forward_;
};

}  // namespace kiln
