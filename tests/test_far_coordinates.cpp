// Scenes far from the world origin (survey data lives at ~1e6): positions are parsed and composed
// in double and stored in float only relative to the scene's origin, so a translated scene renders
// like the original.
#include <fstream>
#include <sstream>

#include "renderer/accel/accelerator.h"
#include "scene/scene_info.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

constexpr double kShift = 1e7;

// The CS184 file with its whole visual scene wrapped in one node translated by kShift.
std::string translatedCopy(const std::string& path, const std::filesystem::path& dir) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    const std::string open = "<visual_scene id=\"Scene\" name=\"Scene\">";
    size_t at = s.find(open);
    EXPECT_NE(at, std::string::npos);
    s.insert(at + open.size(), "<node id=\"far\"><translate>1e7 1e7 1e7</translate>");
    s.insert(s.find("</visual_scene>"), "</node>");
    return test::writeFile(dir / "far.dae", s);
}

Scene loadWithFileCamera(const std::string& path) {
    LoadOptions o;
    o.cameraRule = LoadOptions::CameraRule::File;  // the course rule's direction sees the shift
    return loadScene(path, o);
}

// Mean luminance of each b x b block of two renders differs by at most 5 standard deviations of
// the difference (each block's variance from the films' per-pixel estimator variances).
int blocksBeyondNoise(const Film& a, const Film& b, int w, int h, int block) {
    int beyond = 0;
    for (int y0 = 0; y0 < h; y0 += block)
        for (int x0 = 0; x0 < w; x0 += block) {
            double diff = 0, var = 0;
            for (int y = y0; y < y0 + block; ++y)
                for (int x = x0; x < x0 + block; ++x) {
                    diff += luminance(a.pixel(x, y)) - luminance(b.pixel(x, y));
                    var += a.luminanceVariance(x, y) + b.luminanceVariance(x, y);
                }
            beyond += std::abs(diff) > 5 * std::sqrt(var) + 1e-9;
        }
    return beyond;
}

TEST(FarCoordinates, Cs184SceneTranslatedBy1e7KeepsItsGeometry) {
    auto dir = test::scratchDir();
    std::string original = test::cs184("sky/CBspheres_lambertian.dae");
    Scene a = loadWithFileCamera(original), b = loadWithFileCamera(translatedCopy(original, dir));
    ASSERT_EQ(a.spheres.size(), b.spheres.size());
    for (size_t i = 0; i < a.spheres.size(); ++i) {
        Vec3d pa = a.world(a.spheres[i].center), pb = b.world(b.spheres[i].center);
        // Z-up file: its (x, y, z) shift lands on (-x, z, y) after the course's axis fix.
        Vec3d shift(-kShift, kShift, kShift);
        EXPECT_LT(length(pb - pa - shift), 1e-6) << "sphere " << i;
        EXPECT_NEAR(a.spheres[i].radius, b.spheres[i].radius, 1e-6f);
    }
    const Light* la = test::findLight(a, LightKind::Area);
    const Light* lb = test::findLight(b, LightKind::Area);
    ASSERT_TRUE(la && lb);
    EXPECT_NEAR(a.world(la->position).y + kShift, b.world(lb->position).y, 1e-6);
    Bounds3T<double> ba = worldBoundsExact(a), bb = worldBoundsExact(b);
    EXPECT_NEAR(bb.hi.y - bb.lo.y, ba.hi.y - ba.lo.y, 1e-6);
}

TEST(FarCoordinates, Cs184SceneTranslatedBy1e7RendersLikeTheOriginal) {
    auto dir = test::scratchDir();
    std::string original = test::cs184("sky/CBspheres_lambertian.dae");
    Scene a = loadWithFileCamera(original), b = loadWithFileCamera(translatedCopy(original, dir));
    constexpr int w = 48, h = 36, spp = 32;
    auto render = [&](const Scene& s) {
        auto accel = makeEmbreeAccelerator(s);
        return test::renderJob(s, *accel, test::jobOptions(w, h, spp));
    };
    Film fa = render(a), fb = render(b);
    EXPECT_EQ(blocksBeyondNoise(fa, fb, w, h, 4), 0);
    EXPECT_EQ(blocksBeyondNoise(fa, fb, w, h, 12), 0);
}

// Text readers parse positions in double: a vertex at 1e7 + 0.125 keeps its eighth.
TEST(FarCoordinates, PlyObjAndKilnKeepFarDigits) {
    auto dir = test::scratchDir();
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
        "property double z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "10000000.125 0 0\n10000001.125 0 0\n10000000.125 1.0625 0\n10000000.125 0 1\n"
        "3 0 1 2\n3 0 1 3\n";
    std::string obj =
        "v 10000000.125 0 0\nv 10000001.125 0 0\nv 10000000.125 1.0625 0\nv 10000000.125 0 1\n"
        "f 1 2 3\nf 1 2 4\n";
    std::string kiln = test::writeFile(
        dir / "far.kiln",
        R"(<kiln-scene><mesh file="near.obj" translate="10000000.125 0 0"/></kiln-scene>)");
    test::writeFile(dir / "near.obj",
                    "v 0 0 0\nv 1 0 0\nv 0 1.0625 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n");
    for (const std::string& path :
         {test::writeFile(dir / "far.ply", ply), test::writeFile(dir / "far.obj", obj), kiln}) {
        Scene s = loadScene(path);
        Bounds3T<double> b = worldBoundsExact(s);
        EXPECT_EQ(b.lo.x, 10000000.125) << path;
        EXPECT_EQ(b.hi.x, 10000001.125) << path;
        EXPECT_EQ(b.hi.y, 1.0625) << path;
    }
}

}  // namespace
}  // namespace kiln
