// Files that rendered all black in the Assimp corpus (docs/robustness.md): each is either read
// right now or loaded with a warning that says why its image is black.
#include <filesystem>
#include <iostream>
#include <sstream>

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

// A point light of intensity 1 at 1000 units from a unit quad gives it 1e-6: too dim to see. The
// same light 2 units away is not.
TEST(ImportBlack, LightsTooFarForTheirIntensityWarn) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    auto scene = [&](const std::string& position) {
        return loadScene(test::writeFile(dir / "s.kiln",
                                         R"(<?xml version="1.0"?><kiln-scene><mesh file="quad.obj"/>
<light kind="point" radiance="1 1 1" position=")" +
                                             position + R"("/></kiln-scene>)"));
    };
    EXPECT_TRUE(test::hasWarning(scene("0.5 0.5 1000"), "irradiance of at most 1e-06"));
    EXPECT_FALSE(test::hasWarning(scene("0.5 0.5 2"), "irradiance of at most"));
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
