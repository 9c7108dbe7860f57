// Camera rays: pinhole (sensor at z = -1 in camera space, as CS184), thin lens, or orthographic
// (parallel rays from a rectangle of the camera's half width and height).
#pragma once

#include "renderer/core/ray.h"
#include "scene/scene.h"

namespace kiln {

class CameraModel {
  public:
    // Fits the field of view (or the orthographic rectangle) to the image aspect by widening one
    // side (the course's rule).
    CameraModel(const Camera& camera, int width, int height);
    // (px, py): continuous raster position, y down; lens: two uniform numbers for thin-lens
    // sampling.
    Ray generateRay(float px, float py, float lensU = 0.5f, float lensV = 0.5f) const;
    float hFovDeg() const { return hFov_; }
    float vFovDeg() const { return vFov_; }
    bool orthographic() const { return cam_.orthographic(); }
    // A thin lens (generateRay reads its lens sample); a pinhole ignores it.
    bool hasLens() const { return cam_.apertureRadius > 0 && !cam_.orthographic(); }
    // Orthographic: half the view's width and height after the aspect fit, in scene units.
    float orthoHalfWidth() const { return tanX_; }
    float orthoHalfHeight() const { return tanY_; }

  private:
    // The field of view for this image size: the file's two angles fitted (Camera::FovAxis::Fit),
    // or the one stated angle on its axis.
    void fitFov(Camera::FovAxis axis, float width, float height);
    Camera cam_;
    int width_, height_;
    float hFov_, vFov_;
    float tanX_, tanY_;  // the sensor's half extent at distance 1 (orthographic: in scene units)
    float xScale_, yScale_;  // raster to [-1, 1]: 2 / width, 2 / height
    Vec3 right_, up_, forward_;
};

}  // namespace kiln
