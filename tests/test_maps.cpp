// Normal maps, alpha (cutout and blend coverage), texture transforms, material overrides and the
// .kiln camera's fov axis, on the scenes tools/make_maps_scenes.py writes under scenes/assets/.
// Every scene is lit by one directional light from straight above and seen from straight above
// (-m 1: direct light only), so a Lambert surface's pixel is albedo * E * cos / pi exactly, and
// the expected values below are that formula, not measured numbers.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "renderer/accel/accelerator.h"
#include "renderer/geometry/camera.h"
#include "renderer/validation/crosscheck.h"
#include "scene/scene_loader.h"
#include "tests/kiln_run.h"
#include "tests/test_support.h"

namespace kiln {
namespace {

constexpr int kSize = 64;
constexpr float kIrradiance = 3.0f;  // the .kiln light's radiance

std::string asset(const std::string& name) { return test::repo("scenes/assets/" + name); }

Film render(const Scene& s, int spp = 4, bool transparent = false, int threads = 0, int tile = 32) {
    auto accel = makeEmbreeAccelerator(s);
    PathOptions path;
    path.maxDepth = 1;
    AovRequest aovs;
    aovs.transparent = transparent;
    RenderJobOptions o = test::jobOptions(kSize, kSize, spp, path, aovs);
    o.settings.threads = threads, o.settings.tileSize = tile;
    return test::renderJob(s, *accel, o);
}

float lambert(float albedo, float cosine = 1.0f) { return albedo * kIrradiance * cosine / kPi; }

// The quad's middle of its left (x = -0.5) and right (x = +0.5) halves: camera 4 above y = 0,
// 60 degrees: x = +-0.5 lands 0.5 / (4 tan 30) of the half-width from the centre.
constexpr int kLeftHalf = 25, kRightHalf = 38, kMiddleRow = 32;

TEST(NormalMap, TiltedMapDarkensByTheCosineOfItsTilt) {
    Scene none = loadScene(asset("maps_normal_none.kiln"));
    Scene mapped = loadScene(asset("maps_normal.kiln"));
    ASSERT_GE(mapped.materials[0].maps.normalTexture, 0);
    ASSERT_FALSE(mapped.meshes[0].tangents.empty());
    Film a = render(none), b = render(mapped);
    for (int x : {kLeftHalf, kRightHalf}) {
        EXPECT_NEAR(a.pixel(x, kMiddleRow).x, lambert(0.8f), 1e-5f);
        // The map tilts the normal 45 degrees (towards +x on the left, -x on the right).
        EXPECT_NEAR(b.pixel(x, kMiddleRow).x, lambert(0.8f, std::sqrt(0.5f)), 1e-4f) << x;
    }
}

TEST(NormalMap, TangentAndBitangentPointAlongIncreasingUAndV) {
    // Light from the -x side at 45 degrees: the left half's normal (tilted to +x, away from it)
    // is edge-on, the right half's (tilted to -x) faces it; unmapped, cos 45.
    Film side = render(loadScene(asset("maps_normal_side.kiln")));
    EXPECT_NEAR(side.pixel(kLeftHalf, kMiddleRow).x, 0.0f, 1e-4f);
    EXPECT_NEAR(side.pixel(kRightHalf, kMiddleRow).x, lambert(0.8f), 1e-4f);
    // +y in the map is the bitangent: glTF's v decreasing (up the image), the quad's -z side here,
    // where the light comes from.
    Film up = render(loadScene(asset("maps_normal_up.kiln")));
    EXPECT_NEAR(up.pixel(32, 32).x, lambert(0.8f), 1e-4f);
}

// Scenes rendered one after another in one process (kiln batch, the test binary) each see their
// own textures: OIIO's per-thread micro-cache once handed a later scene an earlier one's tiles.
TEST(NormalMap, ALaterSceneReadsItsOwnTextures) {
    Film first = render(loadScene(asset("maps_normal_up.kiln")));
    for (const char* other : {"textured.gltf", "maps_normal_side.kiln", "maps_alpha_mask.kiln"})
        render(loadScene(asset(other)));
    Film again = render(loadScene(asset("maps_normal_up.kiln")));
    for (int y = 0; y < first.height(); ++y)
        for (int x = 0; x < first.width(); ++x)
            ASSERT_EQ(first.pixel(x, y), again.pixel(x, y)) << x << " " << y;
}

TEST(NormalMap, GltfScaleShortensTheTilt) {
    Scene s = loadScene(asset("maps_normal_scale.kiln"));
    EXPECT_EQ(s.materials[0].maps.normalScale, 0.5f);
    // The 45-degree texel (t, 0, t), t = sqrt(1/2), with x halved: cos = t / |(t/2, 0, t)|.
    float t = std::sqrt(0.5f), cosine = t / std::sqrt(0.25f * t * t + t * t);
    EXPECT_NEAR(render(s).pixel(kLeftHalf, kMiddleRow).x, lambert(0.8f, cosine), 1e-4f);
}

TEST(Alpha, ObjDissolveAndMapDAreCoverage) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "veil.mtl",
                    "newmtl veil\nKd 1 1 1\nd 0.4\nnewmtl cut\nKd 1 1 1\n"
                    "map_d " +
                        asset("maps_card_rgba.png") + "\n");
    std::string obj =
        test::writeFile(dir / "veil.obj",
                        "mtllib veil.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                        "usemtl veil\nf 1/1 2/2 3/3\nusemtl cut\nf 1/1 3/3 2/2\n");
    Scene s = loadScene(obj);
    int blends = 0;
    for (const Material& m : s.materials) {
        if (m.name == "veil") {
            EXPECT_EQ(m.maps.alphaMode, AlphaMode::Blend);
            EXPECT_NEAR(m.maps.opacity, 0.4f, 1e-6f);
            ++blends;
        }
        if (m.name == "cut") {
            EXPECT_EQ(m.maps.alphaMode, AlphaMode::Blend);
            EXPECT_GE(m.maps.opacityTexture, 0);
            EXPECT_EQ(m.maps.opacityChannel, 0);
            ++blends;
        }
    }
    EXPECT_EQ(blends, 2);
}

TEST(NormalMap, FileTangentsAndComputedTangentsAgree) {
    Scene computed = loadScene(asset("maps_normal.kiln"));
    Scene file = loadScene(asset("maps_normal_tangents.kiln"));
    Film a = render(computed), b = render(file);
    for (int x : {kLeftHalf, kRightHalf})
        EXPECT_NEAR(a.pixel(x, kMiddleRow).x, b.pixel(x, kMiddleRow).x, 1e-5f);
}

TEST(NormalMap, FlatMapIsBitIdenticalToNone) {
    Film a = render(loadScene(asset("maps_normal_none.kiln")));
    Film b = render(loadScene(asset("maps_normal_flat.kiln")));
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) ASSERT_EQ(a.pixel(x, y), b.pixel(x, y)) << x << " " << y;
}

TEST(NormalMap, StrengthScaleZeroIsFlat) {
    Scene s = loadScene(asset("maps_normal.kiln"));
    s.materials[0].maps.normalScale = 0.0f;  // x and y scaled away: (0, 0, z)
    Film f = render(s);
    EXPECT_NEAR(f.pixel(kLeftHalf, kMiddleRow).x, lambert(0.8f), 1e-5f);
}

// Alpha scene: a card at y = 0.5 over [-1, 1]^2, cut (alpha 0) on its -z half (the image's top);
// a green floor at y = 0 under its left half only.
constexpr int kCutOverFloorX = 24, kCutOverNothingX = 40, kCutRow = 24, kOpaqueRow = 40;

TEST(Alpha, MaskShowsTheFloorThroughTheCutAndItsLightPassesToo) {
    Scene s = loadScene(asset("maps_alpha_mask.kiln"));
    ASSERT_EQ(s.materials[1].maps.alphaMode, AlphaMode::Mask);
    Film f = render(s, 4, true);
    // The floor, fully lit: the shadow ray passes through the same cut.
    EXPECT_NEAR(f.pixel(kCutOverFloorX, kCutRow).y, lambert(0.7f), 1e-5f);
    EXPECT_EQ(f.alpha(kCutOverFloorX, kCutRow), 1.0f);
    // Nothing behind the cut: background, transparent.
    EXPECT_EQ(f.alpha(kCutOverNothingX, kCutRow), 0.0f);
    EXPECT_EQ(f.pixel(kCutOverNothingX, kCutRow).x, 0.0f);
    // The opaque half: the card's red texel.
    EXPECT_NEAR(f.pixel(kCutOverNothingX, kOpaqueRow).x, lambert(1.0f), 1e-5f);
    EXPECT_EQ(f.alpha(kCutOverNothingX, kOpaqueRow), 1.0f);
}

TEST(Alpha, MaskOffRendersTheCardWhole) {
    Scene s = loadScene(asset("maps_alpha_mask.kiln"));
    s.materials[1].maps.alphaMode = AlphaMode::Opaque;
    Film f = render(s, 4, true);
    EXPECT_EQ(f.alpha(kCutOverNothingX, kCutRow), 1.0f);
    EXPECT_NEAR(f.pixel(kCutOverNothingX, kCutRow).x, lambert(1.0f), 1e-5f);
}

TEST(Alpha, BlendCoverageIsAlphaWithinItsBinomialError) {
    Scene s = loadScene(asset("maps_alpha_blend.kiln"));
    ASSERT_EQ(s.materials[1].maps.alphaMode, AlphaMode::Blend);
    const float alpha = s.materials[1].maps.opacity;
    ASSERT_NEAR(alpha, 0.3f, 1e-6f);
    const int spp = 64;
    Film f = render(s, spp, true);
    // The veil over nothing (x > 0): each camera sample is covered with probability alpha.
    double covered = 0;
    int pixels = 0;
    for (int y = 20; y <= 44; ++y)
        for (int x = 36; x <= 44; ++x, ++pixels) covered += f.alpha(x, y);
    double n = double(pixels) * spp, mean = covered / pixels;
    double sigma = std::sqrt(alpha * (1 - alpha) / n);
    EXPECT_NEAR(mean, alpha, 5 * sigma) << "sigma " << sigma;
}

TEST(Alpha, BlendImagesAreBitIdenticalForAnyThreadsAndTiles) {
    Scene s = loadScene(asset("maps_alpha_blend.kiln"));
    Film a = render(s, 8, true, 1, 8), b = render(s, 8, true, 0, 32);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            ASSERT_EQ(a.pixel(x, y), b.pixel(x, y)) << x << " " << y;
            ASSERT_EQ(a.alpha(x, y), b.alpha(x, y));
        }
}

class AlphaCrosscheck : public ::testing::TestWithParam<const char*> {};

TEST_P(AlphaCrosscheck, EmbreeAgreesWithTheReferenceBvh) {
    Scene s = loadScene(asset(GetParam()));
    auto embree = makeEmbreeAccelerator(s);
    auto reference = makeReferenceAccelerator(s);
    CrosscheckReport report = crosscheck(s, *embree, *reference, 5000, 1);
    for (const CrosscheckCategory& c : report.categories)
        EXPECT_EQ(c.genuine, 0u) << toString(c.kind);
    // The cut is seen: straight down through the card's cut half over nothing is a miss for both.
    Ray down{Vec3(0.5f, 2.0f, -0.5f), 0.0f, Vec3(0, -1, 0), kInfinity};
    Hit a, b;
    bool blocked = std::string(GetParam()) == "maps_alpha_blend.kiln";
    if (!blocked) {
        EXPECT_FALSE(embree->intersect(down, a));
        EXPECT_FALSE(reference->intersect(down, b));
        EXPECT_FALSE(embree->occluded(down));
        EXPECT_FALSE(reference->occluded(down));
        // The opaque half blocks both kinds of query in both.
        Ray opaque{Vec3(0.5f, 2.0f, 0.5f), 0.0f, Vec3(0, -1, 0), kInfinity};
        EXPECT_TRUE(embree->occluded(opaque));
        EXPECT_TRUE(reference->occluded(opaque));
        ASSERT_TRUE(embree->intersect(opaque, a));
        ASSERT_TRUE(reference->intersect(opaque, b));
        EXPECT_EQ(a.shape, b.shape);
        EXPECT_NEAR(a.t, 1.5f, 1e-5f);
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, AlphaCrosscheck,
                         ::testing::Values("maps_alpha_mask.kiln", "maps_alpha_blend.kiln"));

TEST(Alpha, WatertightEmbreeCutsOutToo) {
    Scene s = loadScene(asset("maps_alpha_mask.kiln"));
    EmbreeOptions o;
    o.watertight = true;
    auto embree = makeEmbreeAccelerator(s, o);
    Hit h;
    EXPECT_FALSE(embree->intersect({Vec3(0.5f, 2.0f, -0.5f), 0.0f, Vec3(0, -1, 0), kInfinity}, h));
    EXPECT_TRUE(embree->intersect({Vec3(0.5f, 2.0f, 0.5f), 0.0f, Vec3(0, -1, 0), kInfinity}, h));
}

// KHR_texture_transform on a texture whose left half is black and right half white.
float quadAt(const std::string& file, int x, int y) {
    return render(loadScene(asset(file))).pixel(x, y).x;
}

TEST(TextureTransform, ScaleOffsetAndRotationMoveTheLookup) {
    // Scale 0.5: the quad's right half reads the texture's u in [0.25, 0.5]: black.
    EXPECT_NEAR(quadAt("maps_transform_scale.kiln", kRightHalf, kMiddleRow), 0.0f, 1e-6f);
    // Offset 0.5 as well: u in [0.75, 1]: white.
    EXPECT_NEAR(quadAt("maps_transform_offset.kiln", kRightHalf, kMiddleRow), lambert(1.0f), 1e-5f);
    // Rotation 90 degrees: s = v (glTF's v, 0 at the image's top row, the quad's -z edge), so the
    // quad's -z half reads s in (0, 0.5): black; its +z half white.
    EXPECT_NEAR(quadAt("maps_transform_rotate.kiln", 32, 24), 0.0f, 1e-6f);
    EXPECT_NEAR(quadAt("maps_transform_rotate.kiln", 32, 40), lambert(1.0f), 1e-5f);
}

// The pixel's (R, A) in an EXR kiln wrote.
std::pair<float, float> exrPixel(const std::string& path, int x, int y) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return {-1.0f, -1.0f};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data());
    size_t at = (size_t(y) * spec.width + x) * spec.nchannels;
    return {px[at + spec.channelindex("R")], px[at + spec.channelindex("A")]};
}

TEST(Alpha, KilnRenderTransparentWritesAlphaZeroThroughTheCut) {
    auto dir = test::scratchDir();
    std::string out = (dir / "cut").string();
    test::CliRun r = test::runKiln("render " + asset("maps_alpha_mask.kiln") +
                                   " -r 64 64 -s 2 -m 1 -q --transparent --output " + out);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(exrPixel(out + ".exr", kCutOverNothingX, kCutRow).second, 0.0f);
    EXPECT_EQ(exrPixel(out + ".exr", kCutOverFloorX, kCutRow).second, 1.0f);
    // The override makes the card opaque clay: covered, grey.
    r = test::runKiln("render " + asset("maps_alpha_mask.kiln") +
                      " -r 64 64 -s 2 -m 1 -q --transparent --material-override clay --output " +
                      out);
    ASSERT_EQ(r.code, 0) << r.err;
    auto [red, alpha] = exrPixel(out + ".exr", kCutOverNothingX, kCutRow);
    EXPECT_EQ(alpha, 1.0f);
    EXPECT_NEAR(red, lambert(0.5f), 1e-5f);
    test::CliRun bad =
        test::runKiln("render " + asset("maps_alpha_mask.kiln") + " --material-override x:y");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("not a material override"), std::string::npos) << bad.err;
}

TEST(TextureTransform, GltfMatchesTheExtensionsFormula) {
    // uv' = T R S uv, R = [cos sin; -sin cos] (checked against Khronos' TextureTransformTest
    // asset, whose markers show which direction is right): 90 degrees sends (x, y) to (y, -x).
    UvTransform x = UvTransform::gltf(0.1f, 0.2f, kPi / 2, 2.0f, 3.0f);
    float u = 0.3f, vUp = 0.4f, g = 1 - vUp;  // kiln's v is up, glTF's down
    EXPECT_NEAR(x.s(u, vUp), 0.1f + 3.0f * g, 1e-6f);
    EXPECT_NEAR(x.t(u, vUp), 0.2f - 2.0f * u, 1e-6f);
    UvTransform id;
    EXPECT_EQ(id.s(u, vUp), u);
    EXPECT_EQ(id.t(u, vUp), 1 - vUp);
}

TEST(MaterialOverride, ClayReplacesEveryMaterialButEmitters) {
    LoadOptions o;
    o.materialOverride = "clay";
    Scene s = loadScene(asset("maps_alpha_mask.kiln"), o);
    for (const Material& m : s.materials) {
        EXPECT_EQ(m.name, "clay");
        EXPECT_EQ(m.albedo, Color(0.5f));
        EXPECT_FALSE(m.maps.hasAlpha());
    }
    // Cornell's light is an emitter and keeps lighting the clay.
    Scene box = loadScene(test::repo("scenes/cornell.dae"), o);
    for (const Material& m : box.materials) {
        if (m.kind != MaterialKind::Emission && !(maxComponent(m.emission) > 0)) {
            EXPECT_EQ(m.name, "clay");
        }
    }
    EXPECT_FALSE(box.lights.empty());
}

TEST(MaterialOverride, SpecsAndFiles) {
    EXPECT_EQ(parseMaterialOverride("lambertian:0.25").albedo, Color(0.25f));
    EXPECT_EQ(parseMaterialOverride("lambertian:0.1,0.2,0.3").albedo, Color(0.1f, 0.2f, 0.3f));
    std::string file = test::writeFile(test::scratchDir() / "override.kiln",
                                       "<kiln-scene><material name=\"a\" albedo=\"0.1 0.1 0.1\"/>"
                                       "<material name=\"chrome\" kind=\"mirror\"/></kiln-scene>");
    EXPECT_EQ(parseMaterialOverride(file).name, "a");
    EXPECT_EQ(parseMaterialOverride(file + ":chrome").kind, MaterialKind::Mirror);
    for (const char* bad : {"lambertian:2", "lambertian:0.1,0.2", "lambertian:x", "nosuchfile",
                            "override.kiln:nosuchname"})
        EXPECT_THROW(parseMaterialOverride(
                         std::string(bad).find("override.kiln") == 0 ? file + ":nosuchname" : bad),
                     SceneError)
            << bad;
}

TEST(MaterialOverride, KilnOverrideElementReplacesAnIncludedAssetsMaterials) {
    auto dir = test::scratchDir();
    std::string scene =
        test::writeFile(dir / "override_element.kiln",
                        "<kiln-scene><material name=\"grey\" albedo=\"0.3 0.3 0.3\"/>"
                        "<include file=\"" +
                            asset("maps_alpha_mask.gltf") +
                            "\"><override material=\"grey\"/></include>"
                            "<include file=\"" +
                            asset("maps_normal.gltf") +
                            "\"><override spec=\"clay\"/></include>"
                            "</kiln-scene>");
    Scene s = loadScene(scene);
    std::set<std::string> names;
    for (const TriangleMesh& m : s.meshes)
        for (uint32_t id : m.materialIds) names.insert(s.materials[id].name);
    EXPECT_EQ(names, (std::set<std::string>{"grey", "clay"}));
    // A spec's file is relative to the .kiln that names it.
    test::writeFile(dir / "override_mats.kiln",
                    "<kiln-scene><material name=\"chrome\" kind=\"mirror\"/></kiln-scene>");
    std::string relative = test::writeFile(
        dir / "override_relative.kiln",
        "<kiln-scene><include file=\"" + asset("maps_normal.gltf") +
            "\"><override spec=\"override_mats.kiln:chrome\"/></include></kiln-scene>");
    Scene chrome = loadScene(relative);
    EXPECT_EQ(chrome.materials[chrome.meshes[0].materialOf(0)].kind, MaterialKind::Mirror);
    std::string bad = test::writeFile(
        dir / "override_bad.kiln", "<kiln-scene><include file=\"" + asset("maps_normal.gltf") +
                                       "\"><override material=\"nope\"/></include></kiln-scene>");
    test::expectError(bad, "unknown material 'nope'");
}

TEST(FovAxis, EachAxisSpansTheStatedAngle) {
    auto dir = test::scratchDir();
    auto fovOf = [&](const std::string& axis, int w, int h) {
        std::string attr = axis.empty() ? "" : " fov_axis=\"" + axis + "\"";
        std::string file = test::writeFile(
            dir / ("fov_" + axis + ".kiln"),
            "<kiln-scene><include file=\"" + asset("maps_normal_none.gltf") +
                "\"/><camera position=\"0 4 0\" look-at=\"0 0 0\" up=\"0 0 -1\" fov=\"40\"" + attr +
                "/></kiln-scene>");
        Scene s = loadScene(file);
        CameraModel c(s.camera, w, h);
        return std::pair<float, float>(c.hFovDeg(), c.vFovDeg());
    };
    auto tanHalf = [](float deg) { return std::tan(deg * kPi / 360.0f); };
    for (auto [w, h] : {std::pair{800, 400}, std::pair{300, 600}}) {
        auto [h0, v0] = fovOf("", w, h);  // default: the narrow axis, as before
        EXPECT_FLOAT_EQ(std::min(h0, v0), 40.0f);
        EXPECT_EQ(fovOf("narrow", w, h), fovOf("", w, h));
        EXPECT_FLOAT_EQ(fovOf("horizontal", w, h).first, 40.0f);
        EXPECT_FLOAT_EQ(fovOf("vertical", w, h).second, 40.0f);
        auto [hd, vd] = fovOf("diagonal", w, h);
        EXPECT_NEAR(std::hypot(tanHalf(hd), tanHalf(vd)), tanHalf(40.0f), 1e-5f);
        EXPECT_NEAR(tanHalf(hd) / tanHalf(vd), float(w) / float(h), 1e-5f);
    }
    std::string bad = test::writeFile(
        dir / "fov_bad.kiln", "<kiln-scene><include file=\"" + asset("maps_normal_none.gltf") +
                                  "\"/><camera position=\"0 4 0\" look-at=\"0 0 0\" up=\"0 0 -1\" "
                                  "fov=\"40\" fov_axis=\"sideways\"/></kiln-scene>");
    test::expectError(bad, "fov_axis must be");
}

}  // namespace
}  // namespace kiln
