// Camera framing and field of view as the CS184 program does them.
#include <cmath>

#include "renderer/geometry/camera.h"
#include "scene/framing.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

TEST(Framing, FovWidenedToTheImageAspect) {
    // CS184 Cornell camera: xfov 49.13434, aspect_ratio 1.777778 -> vfov 28.84; at 800x600 the
    // vertical angle widens to 2*atan(tan(hfov/2) / (4/3)) = 37.85 degrees and the horizontal
    // stays.
    float h = 49.13434f, v = degrees(2 * std::atan(std::tan(radians(h / 2)) / 1.777778f));
    fitFovToAspect(h, v, 800.0f / 600.0f);
    EXPECT_NEAR(h, 49.13434f, 1e-4f);
    EXPECT_NEAR(v, 37.849f, 1e-3f);
    // A taller image widens the vertical angle, a wider one the horizontal.
    float h2 = 40, v2 = 40;
    fitFovToAspect(h2, v2, 2.0f);
    EXPECT_NEAR(std::tan(radians(h2 / 2)) / std::tan(radians(v2 / 2)), 2.0f, 1e-5f);
    EXPECT_FLOAT_EQ(v2, 40.0f);
}

TEST(Framing, CourseRulePlacesTheCameraOnTheFileDirection) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    Bounds3 b = s.storedBounds();
    Vec3 expected = b.centroid() + Vec3(0, 0, 1) * (1.5f * length(b.diagonal()));
    EXPECT_NEAR(s.camera.position.x, expected.x, 1e-5f);
    EXPECT_NEAR(s.camera.position.y, expected.y, 1e-5f);
    EXPECT_NEAR(s.camera.position.z, expected.z, 1e-5f);
    EXPECT_NEAR(s.camera.forward.z, -1.0f, 1e-6f);
    // CBbunny's camera matrix points the other way: the course places it at -z.
    Scene bunny = loadScene(test::cs184("sky/CBbunny.dae"));
    EXPECT_LT(bunny.camera.position.z, -4.0f);
    EXPECT_NEAR(bunny.camera.forward.z, 1.0f, 1e-6f);
}

TEST(Framing, FileCameraOnRequest) {
    LoadOptions o;
    o.cameraRule = LoadOptions::CameraRule::File;
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"), o);
    // Node matrix -1 0 0 0 / 0 0 1 3 / 0 1 0 0 in Z-up: position (0,3,0) -> Y-up (0,0,3).
    EXPECT_NEAR(s.camera.position.z, 3.0f, 1e-5f);
    EXPECT_NEAR(s.camera.position.y, 0.0f, 1e-5f);
    EXPECT_FALSE(s.framedByCourseRule);
}

TEST(Framing, CentreRayHitsTheTargetAndCornersSpanTheFov) {
    Camera cam;
    cam.position = Vec3(0, 0, 5);
    cam.forward = Vec3(0, 0, -1);
    cam.hFovDeg = 90;
    cam.vFovDeg = 90;
    CameraModel model(cam, 200, 100);  // 2:1 widens the horizontal angle
    Ray centre = model.generateRay(100, 50);
    EXPECT_NEAR(centre.dir.z, -1.0f, 1e-6f);
    Ray topLeft = model.generateRay(0, 0);
    EXPECT_NEAR(topLeft.dir.y / -topLeft.dir.z, 1.0f, 1e-5f);   // tan(45 deg)
    EXPECT_NEAR(topLeft.dir.x / -topLeft.dir.z, -2.0f, 1e-5f);  // widened to aspect 2
}

TEST(ThinLens, RaysThroughOnePixelMeetOnThePlaneOfFocus) {
    Camera cam;
    cam.position = Vec3(0, 0, 0);
    cam.forward = Vec3(0, 0, -1);
    cam.apertureRadius = 0.2f;
    cam.focalDistance = 7.0f;
    CameraModel model(cam, 64, 48);
    Vec3 meet;
    float spread = 0, spreadNear = 0;
    for (int i = 0; i < 16; ++i) {
        float u = (i % 4 + 0.5f) / 4, v = (i / 4 + 0.5f) / 4;
        Ray r = model.generateRay(40.3f, 11.7f, u, v);
        Vec3 atFocus = r.origin + r.dir * ((-7.0f - r.origin.z) / r.dir.z);  // the plane z = -7
        Vec3 atNear = r.origin + r.dir * ((-2.0f - r.origin.z) / r.dir.z);
        if (i == 0) meet = atFocus;
        spread = std::max(spread, length(atFocus - meet));
        spreadNear = std::max(spreadNear, length(atNear - meet * (2.0f / 7.0f)));
        EXPECT_LE(length(r.origin - cam.position), 0.2f + 1e-6f);  // starts on the lens
    }
    EXPECT_LT(spread, 1e-5f);      // sharp on the plane of focus
    EXPECT_GT(spreadNear, 0.05f);  // blurred in front of it
}

}  // namespace
}  // namespace kiln
