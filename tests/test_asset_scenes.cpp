// kiln's own scene set (scenes/assets, written by tools/make_asset_scenes.py): each scene's pixels
// against what its generator says it holds; a converted file light's radiance; import warnings
// carried into the EXR header and the --json result.
#include <OpenImageIO/imageio.h>

#include <nlohmann/json.hpp>

#include "color/image_input.h"
#include "kiln_run.h"
#include "renderer/accel/accelerator.h"
#include "test_support.h"

namespace kiln {
namespace {

constexpr int kSize = 64;  // the scenes' camera sees x, y in [-1, 1]: 32 pixels a unit

Vec3 albedoAt(const Film& f, int x, int y) {
    return {f.aov(x, y, test::aovChannel(f, "albedo.R")),
            f.aov(x, y, test::aovChannel(f, "albedo.G")),
            f.aov(x, y, test::aovChannel(f, "albedo.B"))};
}

Film renderWithAlbedo(const Scene& s, int spp) {
    AovRequest aovs;
    aovs.add(AovKind::Albedo);
    auto accel = makeEmbreeAccelerator(s);
    return test::renderJob(s, *accel, test::jobOptions(kSize, kSize, spp, PathOptions{}, aovs));
}

// The linear colour of texel (x, y) of an 8-bit sRGB image.
Vec3 linearTexel(const std::string& path, int x, int y) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path;
    std::vector<uint8_t> px(size_t(in->spec().width) * in->spec().height * 3);
    EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
    const uint8_t* t = &px[(size_t(y) * in->spec().width + x) * 3];
    return {srgbToLinear(t[0] / 255.0f), srgbToLinear(t[1] / 255.0f), srgbToLinear(t[2] / 255.0f)};
}

std::string assetScene(const std::string& name) { return test::repo("scenes/assets/" + name); }

// The checker quad: its camera sees the middle 8 x 8 cells (16 texels each, from texel 16), so
// image pixels [8k, 8k + 8) lie in texture cell k + 1. A pixel's albedo is its cell's texel,
// decoded from sRGB; the image's mean is the mean of the two cells' linear colours.
TEST(AssetScenes, TexturedCheckerTexelsAndMean) {
    Scene s = loadScene(assetScene("textured.gltf"));
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    Film f = renderWithAlbedo(s, 4);
    std::string png = assetScene("checker.png");
    Vec3 a = linearTexel(png, 24, 24), b = linearTexel(png, 40, 24);
    EXPECT_GT(maxComponent(abs(a - b)), 0.2f);  // two different colours
    for (int cy = 0; cy < 8; ++cy)
        for (int cx = 0; cx < 8; ++cx) {
            // The centre pixels of each cell: their footprint stays inside the cell.
            Vec3 want = (cx + cy) % 2 ? b : a;
            for (int p : {3, 4})
                EXPECT_LE(maxComponent(abs(albedoAt(f, 8 * cx + p, 8 * cy + p) - want)), 2e-3f)
                    << "cell " << cx << "," << cy;
        }
    Vec3 mean(0.0f);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) mean += albedoAt(f, x, y) / float(kSize * kSize);
    EXPECT_LE(maxComponent(abs(mean - (a + b) * 0.5f)), 2e-3f);
}

// The lit render of the same quad: one directional light (KHR_lights_punctual, intensity 3 lux,
// tilted 30 degrees) on the plane rendered Lambertian (--material-override diffuse), nothing else
// to bounce off, so every pixel is albedo * E cos(30) / pi exactly: the light is converted with its
// intensity as irradiance.
TEST(AssetScenes, GltfDirectionalLightIrradianceIsItsLux) {
    LoadOptions diffuse;  // the glTF material is principled; its Lambert look is exact
    diffuse.materialOverride = kDiffuseOverride;
    Scene s = loadScene(assetScene("textured.gltf"), diffuse);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].kind, LightKind::Directional);
    Film f = renderWithAlbedo(s, 4);
    const float scale = 3.0f * std::cos(30.0f * kPi / 180.0f) / kPi;
    for (int y = 3; y < kSize; y += 8)
        for (int x = 3; x < kSize; x += 8) {
            Color c = f.pixel(x, y);
            Vec3 want = albedoAt(f, x, y) * scale;
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], want[k], 1e-3f) << x << "," << y;
        }
}

// Blender's FBX lamps (energy 1, distance 30 m in a centimetre file): Assimp states the falloff
// as 1 / (q d^2) with q = 2 / DecayStart^2 for quadratic decay, so the intensity is 1 / q (the lamp
// is as bright at 2121 cm as a unit intensity at 1); linear decay is matched at the scene's centre
// and named. Before, both were unit intensities some 700 cm away: black images.
TEST(AssetScenes, FbxLampsKeepTheirFalloff) {
    // spider.fbx: quadratic decay from 3000 (cm): 1 / (2 / 3000^2 d^2), exactly as stated.
    Scene spider = loadScene("/usr/share/assimp/models/FBX/spider.fbx");
    const Light* lamp = test::findLight(spider, LightKind::Point);
    ASSERT_TRUE(lamp);
    EXPECT_TRUE(lamp->attenuationStated);
    const float d2 = 700.0f * 700.0f;
    EXPECT_NEAR(lamp->falloffDenominator(d2), 2.0 / (3000.0 * 3000.0) * d2, 1e-5);
    // huesitos.fbx: linear decay, 1 / (2 / 3000 d).
    Scene bones = loadScene("/usr/share/assimp/models/FBX/huesitos.fbx");
    lamp = test::findLight(bones, LightKind::Point);
    ASSERT_TRUE(lamp);
    EXPECT_NEAR(lamp->falloffDenominator(d2), 2.0 / 3000.0 * 700.0, 1e-5);
    for (Scene* s : {&spider, &bones}) {
        auto accel = makeEmbreeAccelerator(*s);
        Film f = test::renderJob(*s, *accel, test::jobOptions(32, 24, 4));
        float brightest = 0;
        for (int y = 0; y < f.height(); ++y)
            for (int x = 0; x < f.width(); ++x) brightest = std::max(brightest, f.pixel(x, y).y);
        EXPECT_GT(brightest, 0.05f) << s->sourcePath;
    }
}

// Four quadrants, one glTF COLOR_0 value each (linear), on a white material.
TEST(AssetScenes, VertexColouredQuadrants) {
    Scene s = loadScene(assetScene("vertex_colored.gltf"));
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    Film f = renderWithAlbedo(s, 4);
    const Vec3 colours[4] = {
        {0.8f, 0.1f, 0.1f}, {0.1f, 0.7f, 0.2f}, {0.15f, 0.2f, 0.9f}, {0.9f, 0.75f, 0.1f}};
    for (int q = 0; q < 4; ++q)
        for (int p : {4, 16, 27}) {
            int x = (q % 2) * 32 + p, y = (q / 2) * 32 + p;
            EXPECT_LE(maxComponent(abs(albedoAt(f, x, y) - colours[q])), 1e-4f)
                << "quadrant " << q << " pixel " << x << "," << y;
            EXPECT_GT(f.pixel(x, y).y, 0.0f);  // lit
        }
}

// Every import warning (kiln info's and stderr's list) is in the EXR header, one per line with
// their count, and in the --json result.
TEST(AssetWarnings, InTheExrHeaderAndTheJsonResult) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "quad.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd no_such_texture.png\n");
    std::string obj = test::writeFile(dir / "quad.obj",
                                      "mtllib quad.mtl\nusemtl tex\n"
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                      "vt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
    Scene s = loadScene(obj);
    ASSERT_FALSE(s.warnings.empty());
    std::string exr = (dir / "out.exr").string();
    test::CliRun r = test::runKiln("render " + obj + " -o " + exr + " -r 8 8 -s 1 -q --json");
    ASSERT_EQ(r.code, 0) << r.err;
    auto in = OIIO::ImageInput::open(exr);
    ASSERT_TRUE(in);
    std::string joined;
    for (const std::string& w : s.warnings) {
        joined += (joined.empty() ? "" : "\n") + w;
        EXPECT_NE(r.err.find(w), std::string::npos) << w;
    }
    EXPECT_NE(joined.find("no_such_texture.png"), std::string::npos);
    EXPECT_EQ(in->spec().get_string_attribute("kiln:warnings"), joined);
    EXPECT_EQ(in->spec().get_int_attribute("kiln:warning_count", -1), int(s.warnings.size()));
    EXPECT_EQ(nlohmann::json::parse(r.out)["warnings"], nlohmann::json(s.warnings));
}

// A scene without warnings says so: a count of 0 and no text.
TEST(AssetWarnings, NoneIsACountOfZero) {
    auto dir = test::scratchDir();
    std::string exr = (dir / "out.exr").string();
    test::CliRun r = test::runKiln("render " + assetScene("vertex_colored.gltf") + " -o " + exr +
                                   " -r 8 8 -s 1 -q");
    ASSERT_EQ(r.code, 0) << r.err;
    auto in = OIIO::ImageInput::open(exr);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_int_attribute("kiln:warning_count", -1), 0);
    EXPECT_EQ(in->spec().get_string_attribute("kiln:warnings", "absent"), "absent");
}

// An extension neither Assimp nor kiln reads is named (KHR_technique_webgl: the textured box
// rendered plain white without a word); the ones read or warned about elsewhere are not.
TEST(AssetWarnings, UnreadGltfExtensionsAreNamed) {
    const std::string dir = "/usr/share/assimp/models/glTF2/";
    Scene webgl = loadScene(dir + "BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf");
    EXPECT_EQ(test::warningsNaming(webgl, "glTF extensions not read"), 1);
    EXPECT_EQ(test::warningsNaming(webgl, "KHR_technique_webgl"), 1);
    for (const char* read : {"BoxTextured-glTF-Binary/BoxTextured.glb",
                             "BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf",
                             "ClearCoat-glTF/ClearCoatTest.gltf"})
        EXPECT_EQ(test::warningsNaming(loadScene(dir + read), "glTF extension"), 0) << read;
}

}  // namespace
}  // namespace kiln
