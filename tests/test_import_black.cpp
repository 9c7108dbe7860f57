// Files that rendered all black in the Assimp corpus (docs/robustness.md): each is either read
// right now or loaded with a warning that says why its image is black.
#include <algorithm>
#include <filesystem>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "kiln_run.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

std::string corpus(const std::string& rel) {
    std::string path = "/usr/share/assimp/models/" + rel;
    EXPECT_TRUE(std::filesystem::exists(path)) << "assimp-testmodels (tools/setup.sh) missing";
    return path;
}

// An OBJ quad whose material states Kd 0 0 0: black as written, and said so.
TEST(ImportBlack, BlackMaterialsAreNamedInAWarning) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "black.mtl", "newmtl black\nKd 0 0 0\n");
    Scene s = loadScene(test::writeFile(
        dir / "black.obj",
        "mtllib black.mtl\nusemtl black\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"));
    EXPECT_TRUE(test::hasWarning(s, "diffuse colour is black"));
    test::writeFile(dir / "grey.mtl", "newmtl grey\nKd 0.5 0.5 0.5\n");
    Scene grey = loadScene(test::writeFile(
        dir / "grey.obj",
        "mtllib grey.mtl\nusemtl grey\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"));
    EXPECT_FALSE(test::hasWarning(grey, "diffuse colour is black"));
}

// The black-image warning comes from what the camera sees (kiln render probes the frame), so it
// cannot be dodged: a point light of intensity 1 at 1000 units from a unit quad gives it 1e-6; a
// light inside the scene's bounds that grazes the quad (it dodged the old bound on light power,
// as Collada/cube_tristrips.dae's light inside its cube did) gives it nothing. The same light 2
// units away lights it, and says nothing.
TEST(ImportBlack, WhatTheCameraSeesDecidesTheBlackImageWarning) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    auto render = [&](const std::string& lights) {
        std::string scene = test::writeFile(
            dir / "s.kiln", R"(<?xml version="1.0"?><kiln-scene><mesh file="quad.obj"/>)" + lights +
                                "</kiln-scene>");
        test::CliRun r =
            test::runKiln("render " + scene + " -r 32 24 -s 1 --json --progress none -o " +
                          (dir / "out").string());
        EXPECT_EQ(r.code, 0) << r.err;
        return nlohmann::json::parse(r.out)["warnings"].dump();
    };
    auto point = [](const char* position) {
        return std::string(R"(<light kind="point" radiance="1 1 1" position=")") + position +
               R"("/>)";
    };
    std::string far = render(point("0.5 0.5 1000"));
    EXPECT_NE(far.find("the image will look black"), std::string::npos) << far;
    EXPECT_NE(far.find("mean luminance of"), std::string::npos) << far;
    std::string grazing = render(point("0.5 0.5 1000") + point("0.5 0.5 0"));
    EXPECT_NE(grazing.find("the image will look black"), std::string::npos) << grazing;
    std::string near = render(point("0.5 0.5 2"));
    EXPECT_EQ(near.find("look black"), std::string::npos) << near;
}

// AC's SphereWithLight has no camera and its light behind the sphere as the default front view
// sees it: the default framing looks from the light's side.
TEST(ImportBlack, DefaultFramingLooksFromTheLightsSide) {
    Scene s = loadScene(corpus("AC/SphereWithLight.ac"));
    ASSERT_FALSE(s.hasFileCamera);
    const Light* light = test::findLight(s, LightKind::Point);
    ASSERT_NE(light, nullptr);
    Vec3 centre = s.storedBounds().centroid();
    EXPECT_GT(dot(s.camera.position - centre, light->position - centre), 0.0f);
}

// Assimp 5.2 reports a SIB light's target point as its direction: heffalump's sun shone upwards.
TEST(ImportBlack, SibLightsPointAtTheirTargets) {
    Scene s = loadScene(corpus("SIB/heffalump.sib"));
    const Light* sun = test::findLight(s, LightKind::Directional);
    ASSERT_NE(sun, nullptr);
    EXPECT_LT(sun->direction.y, -0.5f);  // from (-1.34, 5.60, 0) towards (0, 3.60, 0)
}

// FBX states its lamp's falloff (linear: Assimp's factor 0.000667); as 1 / d^2 the lamp gave the
// model 2.7e-6 at 600 units. Lights that state none keep exactly 1 / d^2.
TEST(ImportBlack, FbxLightsFallOffAsTheFileStates) {
    Scene s = loadScene(corpus("FBX/huesitos.fbx"));
    const Light* lamp = test::findLight(s, LightKind::Point);
    ASSERT_NE(lamp, nullptr);
    EXPECT_TRUE(lamp->attenuationStated);
    EXPECT_NEAR(lamp->attenuationLinear, 0.000666667f, 1e-8f);
    EXPECT_NEAR(lamp->falloffDenominator(600.0f * 600.0f), 0.4f, 1e-5f);
    EXPECT_FALSE(test::hasWarning(s, "irradiance of at most"));
    Light physical;
    EXPECT_EQ(physical.falloffDenominator(2.5f), 2.5f);
}

// MDL without skins: Assimp's colour (0, 0, 0, 0) is not the file's; Quick3D: Assimp's camera at
// the origin and black light are not the file's; AMF: constellations and extra volumes are lost.
TEST(ImportBlack, AssimpReaderLimitsAreWarnings) {
    Scene mdl = loadScene(corpus("MDL/MDL5 (3DGS A5)/PhosphoricAcid_MDl5.mdl"));
    EXPECT_EQ(mdl.materials[0].albedo, Material{}.albedo);
    EXPECT_TRUE(test::hasWarning(mdl, "has no skin"));
    Scene q3d = loadScene(corpus("Q3D/WusonOrange.q3s"));
    EXPECT_FALSE(q3d.hasFileCamera);
    EXPECT_TRUE(test::hasWarning(q3d, "Quick3D"));
    EXPECT_NE(test::findLight(q3d, LightKind::Directional), nullptr);  // the default rig
    Scene amf = loadScene(corpus("AMF/test8.amf"));
    EXPECT_TRUE(test::hasWarning(amf, "constellation"));
    EXPECT_TRUE(test::hasWarning(amf, "first <volume>"));
    Scene zeros = loadScene(corpus("AMF/test1.amf"));  // no colours in the file: Assimp's zeros
    EXPECT_TRUE(zeros.meshes[0].colors.empty());
    EXPECT_TRUE(test::hasWarning(zeros, "(0, 0, 0, 0)"));
    Scene blend = loadScene(corpus("BLEND/BlenderDefault_250.blend"));  // Assimp: (-1, -1, -1, -1)
    EXPECT_TRUE(blend.meshes[0].colors.empty());
}

// OpenGEX's parser prints "nullptr returned by creating DDLNode." to std::cerr: kiln's error must
// stay the only line.
TEST(ImportBlack, AssimpPrintsNothingBesideKilnsError) {
    std::ostringstream printed;
    std::streambuf* old = std::cerr.rdbuf(printed.rdbuf());
    EXPECT_THROW(loadScene(corpus("OpenGEX/empty_camera.ogex")), SceneError);
    std::cerr.rdbuf(old);
    EXPECT_EQ(printed.str(), "");
}

}  // namespace
}  // namespace kiln
