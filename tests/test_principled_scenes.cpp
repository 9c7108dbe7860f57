// The principled material in scenes: glTF metallic-roughness imported and rendered (the metal /
// roughness sweep's highlights dim monotonically with roughness), emission added to a surface that
// still reflects, such an emitter found by light sampling and by BSDF-sampled rays alike, and the
// .kiln principled material with a base-colour texture.
#include <OpenImageIO/imageio.h>

#include "color/srgb_decode.h"
#include "integrators/bsdf.h"
#include "integrators/lights.h"
#include "integrators/path.h"
#include "integrators/render_plan.h"
#include "renderer/accel/accelerator.h"
#include "renderer/geometry/material_lookup.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

Vec3 layer(const Film& f, int x, int y, const std::string& name) {
    Vec3 v;
    for (int c = 0; c < 3; ++c) v[c] = f.aov(x, y, test::aovChannel(f, name + "." + "RGB"[c]));
    return v;
}

// scenes/metal_rough/grid.kiln: 2 rows x 5 spheres, roughness 0.3 .. 0.9 left to right, camera
// 6 units away with a 28 degree vertical field: at 200 x 100 pixels a unit spans 100 / (2 * 6 *
// tan 14) pixels and the sphere centres sit at x = (i - 2) units, y = +-0.55.
// A highlight's peak is the brightest 3x3 mean of the sphere's pixels at 64 spp. The closest
// neighbours differ by 8 % at 1024 spp (0.181 against 0.167, lower row, spheres 2 and 3), and the
// brightest single pixel at 16 spp is off by up to 37 % (the largest of ~700 noisy pixels): the
// 3x3 mean at 4x the samples has a sixth of a pixel's deviation.
float highlightPeak(const Film& f, int cx, int cy, int r) {
    float peak = 0;
    for (int y = cy - r + 1; y < cy + r; ++y)
        for (int x = cx - r + 1; x < cx + r; ++x) {
            float sum = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) sum += luminance(f.pixel(x + dx, y + dy));
            peak = std::max(peak, sum / 9);
        }
    return peak;
}

TEST(PrincipledScenes, MetalRoughSweepHighlightsDimWithRoughness) {
    Scene s = loadScene(test::repo("scenes/metal_rough/grid.kiln"));
    ASSERT_GE(test::countKind(s, MaterialKind::Principled), 10);  // and Assimp's default
    const Material* first = test::findMaterial(s, MaterialKind::Principled);
    EXPECT_FLOAT_EQ(first->metallic, 1.0f);
    EXPECT_FLOAT_EQ(first->roughness, 0.3f);
    auto accel = makeEmbreeAccelerator(s);
    RenderPlan plan = planFor(s, *accel, {});
    EXPECT_TRUE(plan.glossy);
    EXPECT_FALSE(plan.diffuseOnly);
    constexpr int kW = 200, kH = 100;
    Film f = test::renderJob(s, *accel, test::jobOptions(kW, kH, 64));
    const float unit = kH / (2 * 6 * std::tan(radians(14.0f)));
    for (float rowY : {0.55f, -0.55f}) {
        float previous = std::numeric_limits<float>::infinity();
        for (int i = 0; i < 5; ++i) {
            int cx = int(kW / 2 + (i - 2) * unit), cy = int(kH / 2 - rowY * unit);
            int r = int(0.45f * unit);
            const float peak = highlightPeak(f, cx, cy, r);
            EXPECT_LT(peak, previous) << "row " << rowY << " sphere " << i;
            EXPECT_GT(peak, 0.0f);
            previous = peak;
        }
    }
}

// A quad facing the camera: principled red base, blue emission, a point light at the camera.
Scene emissiveQuad(bool withLight) {
    Scene s = test::sceneWith(test::gridMesh(1, 1, 4.0f));
    Material& m = s.materials[0];
    m.kind = MaterialKind::Principled;
    m.albedo = Color(0.8f, 0.1f, 0.1f);
    m.roughness = 0.5f;
    m.emission = Color(0.0f, 0.0f, 0.5f);
    s.camera.position = Vec3(2, 2, 5);
    if (withLight) {
        Light l;
        l.kind = LightKind::Point;
        l.position = s.camera.position;
        l.radiance = Color(25.0f);  // irradiance 1 at the quad's centre
        s.lights.push_back(l);
    }
    addEmissiveMeshLights(s);
    return s;
}

TEST(PrincipledScenes, EmissionIsAddedToTheLitSurface) {
    AovRequest aovs;
    aovs.add(AovKind::Emission);
    aovs.add(AovKind::Direct);
    for (bool withLight : {false, true}) {
        Scene s = emissiveQuad(withLight);
        ASSERT_TRUE(test::findLight(s, LightKind::MeshEmitter));
        auto accel = makeEmbreeAccelerator(s);
        constexpr int kSpp = 64;
        Film f = test::renderJob(s, *accel, test::jobOptions(33, 33, kSpp, PathOptions{}, aovs));
        // One light sample per vertex, chosen by power: the point light with probability p, its
        // estimate then divided by p, so a pixel's relative standard deviation is
        // sqrt((1 - p) / (p spp)).
        float p = withLight ? LightSet(s).selectPmf(0) : 1.0f;
        float rel = 5 * std::sqrt((1 - p) / (p * kSpp)) + 0.005f;  // 5 sigma, footprint 0.5 %
        Color emitted = layer(f, 16, 16, "emission"), direct = layer(f, 16, 16, "direct");
        EXPECT_NEAR(emitted.z, 0.5f, 1e-5f);
        EXPECT_NEAR(emitted.x, 0.0f, 1e-6f);
        // What the light adds: f(n, n) cos * irradiance, as the BSDF evaluates it (the pixel's
        // footprint moves the light's distance and angle by well under 1 %).
        Color lit =
            withLight ? Bsdf(s.materials[0]).eval(Vec3(0, 0, 1), Vec3(0, 0, 1)) : Color(0.0f);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(direct[c], lit[c], rel * lit[c] + 1e-6f);
        Color beauty = f.pixel(16, 16);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(beauty[c], emitted[c] + lit[c], rel * lit[c] + 1e-5f);
        if (withLight) {
            EXPECT_GT(lit.x, 0.1f);  // the red base colour, lit
        }
    }
}

// A principled emitter lighting a Lambert floor: light sampling alone and MIS with BSDF sampling
// agree (the emitter is a light NEE samples and a surface bounce rays find, weighted consistently).
TEST(PrincipledScenes, EmittingSurfaceIsALightForNeeAndMis) {
    Scene s = test::sceneWith(test::gridMesh(1, 1, 4.0f));  // floor at z = 0, 0..4
    TriangleMesh lamp = test::gridMesh(1, 1, 1.0f);
    for (size_t v = 0; v < lamp.vertexCount(); ++v) {  // a 1 x 1 lamp at z = 1.5 above the centre
        lamp.positions[3 * v] += 1.5f, lamp.positions[3 * v + 1] += 1.5f;
        lamp.positions[3 * v + 2] = 1.5f;
    }
    lamp.materialIds = {1};
    s.meshes.push_back(lamp);
    Material emitter;
    emitter.kind = MaterialKind::Principled;
    emitter.albedo = Color(0.5f);
    emitter.roughness = 0.4f;
    emitter.emission = Color(4.0f);
    s.materials.push_back(emitter);
    s.camera.position = Vec3(2, -3, 4);
    s.camera.forward = normalize(Vec3(2, 2, 0) - s.camera.position);
    s.camera.up = Vec3(0, 0, 1);
    addEmissiveMeshLights(s);
    ASSERT_EQ(s.lights.size(), 1u);
    auto accel = makeEmbreeAccelerator(s);
    RenderPlan plan = planFor(s, *accel, {});
    EXPECT_TRUE(plan.emitters);
    EXPECT_TRUE(plan.areaLights);
    auto render = [&](DirectSampling sampling) {
        PathOptions o;
        o.sampling = sampling;
        o.maxDepth = 1;
        return test::renderJob(s, *accel, test::jobOptions(32, 24, 32, o));
    };
    Film mis = render(DirectSampling::Mis), light = render(DirectSampling::Light);
    // Paired pixel differences: their mean is 0 when both estimate the same image; its standard
    // error comes from their spread.
    double sum = 0, sum2 = 0, lit = 0;
    int n = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) {
            double d = luminance(mis.pixel(x, y)) - luminance(light.pixel(x, y));
            sum += d, sum2 += d * d, lit += luminance(light.pixel(x, y)), ++n;
        }
    double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
    EXPECT_GT(lit / n, 0.05) << "the emitter lights the floor";
    EXPECT_NEAR(mean, 0.0, 5 * se + 1e-6);
}

// A unit quad with UVs (quad.obj) and an image named `texture` beside it, in dir.
void texturedQuad(const std::filesystem::path& dir, const std::string& texture) {
    test::writeFile(dir / "quad.obj",
                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
    std::filesystem::copy_file("/usr/share/assimp/models/LWO/LWO2/boxuv.png", dir / texture);
}

// .kiln: kind="principled" with its parameters and a base-colour texture beside the file.
TEST(PrincipledScenes, KilnPrincipledMaterialWithTexture) {
    auto dir = test::scratchDir();
    texturedQuad(dir, "base.png");
    test::writeFile(dir / "t.kiln",
                    "<kiln-scene>\n"
                    "  <material name=\"p\" kind=\"principled\" base-color=\"0.9 0.5 0.1\" "
                    "metallic=\"0.25\" roughness=\"0.7\" specular=\"0.5\" clearcoat=\"1\" "
                    "clearcoat-roughness=\"0.1\" emission=\"0 0.2 0\" "
                    "base-color-texture=\"base.png\"/>\n"
                    "  <mesh file=\"quad.obj\" material=\"p\"/>\n"
                    "</kiln-scene>\n");
    // The texture path is resolved beside the .kiln file; a missing one is an error.
    test::writeFile(dir / "missing.kiln",
                    "<kiln-scene><material name=\"p\" kind=\"principled\" "
                    "base-color-texture=\"nope.png\"/></kiln-scene>\n");
    test::expectError((dir / "missing.kiln").string(), "nope.png not found");
    test::writeFile(dir / "range.kiln",
                    "<kiln-scene><material name=\"p\" kind=\"principled\" metallic=\"2\"/>"
                    "</kiln-scene>\n");
    test::expectError((dir / "range.kiln").string(), "metallic must be in [0, 1]");
    Scene s = loadScene((dir / "t.kiln").string());
    for (const std::string& w : s.warnings) EXPECT_EQ(w.find("base.png"), std::string::npos) << w;
    const Material* m = test::findMaterial(s, MaterialKind::Principled);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->albedo, Color(0.9f, 0.5f, 0.1f));
    EXPECT_FLOAT_EQ(m->metallic, 0.25f);
    EXPECT_FLOAT_EQ(m->roughness, 0.7f);
    EXPECT_FLOAT_EQ(m->specular, 0.5f);
    EXPECT_FLOAT_EQ(m->clearcoat, 1.0f);
    EXPECT_FLOAT_EQ(m->clearcoatRoughness, 0.1f);
    EXPECT_EQ(m->emission, Color(0.0f, 0.2f, 0.0f));
    ASSERT_GE(m->albedoTexture, 0);
    EXPECT_EQ(s.textureSources[size_t(m->albedoTexture)].name, (dir / "base.png").string());
}

// .kiln: the transmission, volume, sheen and specular-colour attributes and the clearcoat texture;
// the render plan names rough transmission and sheen; values out of range are errors.
TEST(PrincipledScenes, KilnTransmissionSheenAndPlan) {
    auto dir = test::scratchDir();
    texturedQuad(dir, "coat.png");
    test::writeFile(dir / "t.kiln",
                    "<kiln-scene>\n"
                    "  <material name=\"p\" kind=\"principled\" transmission=\"0.8\" "
                    "thickness=\"0.5\" attenuation-color=\"0.9 0.5 0.2\" "
                    "attenuation-distance=\"2\" sheen=\"0.7\" sheen-color=\"1 0.5 0.25\" "
                    "sheen-roughness=\"0.4\" specular-color=\"1 0.9 0.8\" clearcoat=\"1\" "
                    "clearcoat-texture=\"coat.png\"/>\n"
                    "  <mesh file=\"quad.obj\" material=\"p\"/>\n"
                    "</kiln-scene>\n");
    test::writeFile(dir / "range.kiln",
                    "<kiln-scene><material name=\"p\" kind=\"principled\" transmission=\"1.5\"/>"
                    "</kiln-scene>\n");
    test::expectError((dir / "range.kiln").string(), "transmission must be in [0, 1]");
    Scene s = loadScene((dir / "t.kiln").string());
    const Material* m = test::findMaterial(s, MaterialKind::Principled);
    ASSERT_TRUE(m);
    EXPECT_FLOAT_EQ(m->transmission, 0.8f);
    EXPECT_FLOAT_EQ(m->thickness, 0.5f);
    EXPECT_EQ(m->attenuationColor, Color(0.9f, 0.5f, 0.2f));
    EXPECT_FLOAT_EQ(m->attenuationDistance, 2.0f);
    EXPECT_FLOAT_EQ(m->sheen, 0.7f);
    EXPECT_EQ(m->sheenColor, Color(1.0f, 0.5f, 0.25f));
    EXPECT_FLOAT_EQ(m->sheenRoughness, 0.4f);
    EXPECT_EQ(m->specularColor, Color(1.0f, 0.9f, 0.8f));
    ASSERT_GE(m->maps.clearcoatTexture, 0);
    EXPECT_EQ(m->maps.clearcoatChannel, 0);
    auto accel = makeEmbreeAccelerator(s);
    std::string plan = planFor(s, *accel, AovRequest{}).compact();
    EXPECT_NE(plan.find("rough-transmission"), std::string::npos) << plan;
    EXPECT_NE(plan.find("sheen"), std::string::npos) << plan;
    // Without the lobes the plan names neither.
    Scene plain = loadScene(test::repo("scenes/metal_rough/grid.kiln"));
    auto plainAccel = makeEmbreeAccelerator(plain);
    std::string plainPlan = planFor(plain, *plainAccel, AovRequest{}).compact();
    EXPECT_EQ(plainPlan.find("transmission"), std::string::npos) << plainPlan;
    EXPECT_EQ(plainPlan.find("sheen"), std::string::npos) << plainPlan;
}

// The transmission weight and sheen read their textures where the mesh has UVs: transmission times
// R, sheen colour times the (sRGB-decoded) colour, sheen roughness times A. One texel, so that the
// texture system's filter returns it wherever it looks.
TEST(PrincipledScenes, TransmissionAndSheenTexturesScaleTheirFactors) {
    auto dir = test::scratchDir();
    texturedQuad(dir, "unused.png");
    const uint8_t texel[4] = {102, 64, 128, 51};
    auto out = OIIO::ImageOutput::create((dir / "layers.png").string());
    OIIO::ImageSpec spec(1, 1, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // as given: straight, as glTF's PNGs are
    ASSERT_TRUE(out && out->open((dir / "layers.png").string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, texel) && out->close());
    test::writeFile(dir / "t.kiln",
                    "<kiln-scene>\n"
                    "  <material name=\"p\" kind=\"principled\" transmission=\"0.8\" sheen=\"1\" "
                    "sheen-color=\"1 0.5 0.25\" sheen-roughness=\"0.5\" "
                    "transmission-texture=\"layers.png\" sheen-color-texture=\"layers.png\" "
                    "sheen-roughness-texture=\"layers.png\" clearcoat=\"1\" "
                    "clearcoat-roughness=\"0.5\" clearcoat-roughness-texture=\"layers.png\"/>\n"
                    "  <mesh file=\"quad.obj\" material=\"p\"/>\n"
                    "</kiln-scene>\n");
    Scene s = loadScene((dir / "t.kiln").string());
    ASSERT_TRUE(hasSurfaceColourVariation(s));
    const Material* m = test::findMaterial(s, MaterialKind::Principled);
    ASSERT_TRUE(m);
    Hit hit;
    hit.shape = 0, hit.prim = 0, hit.u = 0.3f, hit.v = 0.2f;
    const Layers layers = layersAt(s, *m, hit, 0.0f);
    EXPECT_NEAR(layers.transmission, 0.8f * 102 / 255, 1e-5f);
    EXPECT_NEAR(layers.sheenRoughness, 0.5f * 51 / 255, 1e-5f);
    EXPECT_NEAR(layers.sheenColour.x, 1.0f * srgbToLinear(102 / 255.0f), 1e-5f);
    EXPECT_NEAR(layers.sheenColour.y, 0.5f * srgbToLinear(64 / 255.0f), 1e-5f);
    EXPECT_NEAR(layers.sheenColour.z, 0.25f * srgbToLinear(128 / 255.0f), 1e-5f);
    EXPECT_NEAR(coatAt(s, *m, hit, 0.0f).roughness, 0.5f * 64 / 255, 1e-5f);  // G
    // Without the textures: the factors.
    const Layers plain = Layers::of(*m);
    EXPECT_FLOAT_EQ(plain.transmission, 0.8f);
    EXPECT_EQ(plain.sheenColour, Color(1.0f, 0.5f, 0.25f));
}

// glTF's material extensions as Assimp 5.2 hands them over (transmission, volume, sheen, ior,
// clearcoat with its textures) and as kiln reads them from the JSON (KHR_materials_specular);
// the extensions neither reads are named in one warning, and the maps kiln does not apply each in
// their own.
TEST(PrincipledImport, GltfMaterialExtensions) {
    auto dir = test::scratchDir();
    std::filesystem::copy_file("/usr/share/assimp/models/LWO/LWO2/boxuv.png", dir / "t.png");
    test::writeFile(dir / "m.gltf",
                    R"({"asset":{"version":"2.0"},
"extensionsUsed":["KHR_materials_transmission","KHR_materials_volume","KHR_materials_sheen",
  "KHR_materials_specular","KHR_materials_ior","KHR_materials_clearcoat",
  "KHR_materials_iridescence","KHR_materials_anisotropy"],
"buffers":[{"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA","byteLength":36}],
"bufferViews":[{"buffer":0,"byteLength":36}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
"images":[{"uri":"t.png"}],"textures":[{"source":0}],
"materials":[{"name":"m","pbrMetallicRoughness":{"baseColorFactor":[0.5,0.6,0.7,1],"metallicFactor":0.1,"roughnessFactor":0.3},
"extensions":{"KHR_materials_transmission":{"transmissionFactor":0.9,"transmissionTexture":{"index":0}},
"KHR_materials_volume":{"thicknessFactor":0.5,"attenuationDistance":2.0,"attenuationColor":[0.9,0.5,0.3],
  "thicknessTexture":{"index":0}},
"KHR_materials_sheen":{"sheenColorFactor":[0.2,0.3,0.4],"sheenRoughnessFactor":0.7,
  "sheenColorTexture":{"index":0},"sheenRoughnessTexture":{"index":0}},
"KHR_materials_specular":{"specularFactor":0.8,"specularColorFactor":[1,0.5,0.25]},
"KHR_materials_ior":{"ior":1.33},
"KHR_materials_clearcoat":{"clearcoatFactor":0.6,"clearcoatRoughnessFactor":0.2,
  "clearcoatTexture":{"index":0},"clearcoatRoughnessTexture":{"index":0}}}}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0})");
    Scene s = loadScene((dir / "m.gltf").string());
    const Material* m = test::findMaterial(s, MaterialKind::Principled);
    ASSERT_TRUE(m);
    EXPECT_FLOAT_EQ(m->transmission, 0.9f);
    EXPECT_FLOAT_EQ(m->thickness, 0.5f);
    EXPECT_FLOAT_EQ(m->attenuationDistance, 2.0f);
    EXPECT_EQ(m->attenuationColor, Color(0.9f, 0.5f, 0.3f));
    EXPECT_FLOAT_EQ(m->sheen, 1.0f);
    EXPECT_EQ(m->sheenColor, Color(0.2f, 0.3f, 0.4f));
    EXPECT_FLOAT_EQ(m->sheenRoughness, 0.7f);
    EXPECT_FLOAT_EQ(m->specular, 0.8f);
    EXPECT_EQ(m->specularColor, Color(1.0f, 0.5f, 0.25f));
    EXPECT_FLOAT_EQ(m->ior, 1.33f);
    EXPECT_FLOAT_EQ(m->clearcoat, 0.6f);
    EXPECT_FLOAT_EQ(m->clearcoatRoughness, 0.2f);
    EXPECT_GE(m->maps.clearcoatTexture, 0);
    EXPECT_GE(m->maps.clearcoatRoughnessTexture, 0);
    EXPECT_EQ(test::warningsNaming(s, "glTF extensions not read"), 1);
    EXPECT_TRUE(test::hasWarning(s, "KHR_materials_iridescence, KHR_materials_anisotropy"));
    EXPECT_GE(m->maps.transmissionTexture, 0);
    EXPECT_GE(m->maps.sheenColorTexture, 0);
    EXPECT_GE(m->maps.sheenRoughnessTexture, 0);
    EXPECT_EQ(test::warningsNaming(s, "transmission map"), 0);
    EXPECT_EQ(test::warningsNaming(s, "sheen map"), 0);
    EXPECT_EQ(test::warningsNaming(s, "thicknessTexture"), 1);  // thin or not: the factor alone
    EXPECT_EQ(test::warningsNaming(s, "clearcoat"), 0);
    EXPECT_EQ(test::warningsNaming(s, "KHR_materials_sheen"), 0);
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

// Assimp's samples: glTF metallic-roughness becomes the principled material; an FBX emissive
// colour is added to a surface that keeps its diffuse colour (it used to replace it).
TEST(PrincipledImport, GltfMetallicRoughnessAndFbxEmission) {
    Scene box = loadScene("/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");
    const Material* textured = test::findMaterial(box, MaterialKind::Principled);
    ASSERT_TRUE(textured);
    EXPECT_FLOAT_EQ(textured->metallic, 0.0f);  // the file's metallicFactor 0
    EXPECT_FLOAT_EQ(textured->roughness, 1.0f);
    EXPECT_GE(textured->albedoTexture, 0);

    Scene cube = loadScene("/usr/share/assimp/models/FBX/phong_cube.fbx");
    const Material* phong = test::findMaterial(cube, MaterialKind::Principled);  // its specular
    ASSERT_TRUE(phong);
    EXPECT_EQ(test::countKind(cube, MaterialKind::Emission), 0);
    EXPECT_EQ(phong->albedo, Color(0.5f, 0.25f, 0.25f));
    EXPECT_EQ(phong->emission, Color(0.25f, 0.125f, 0.25f));
    EXPECT_TRUE(test::findLight(cube, LightKind::MeshEmitter));

    Scene pbr = loadScene("/usr/share/assimp/models/FBX/maxPbrMaterial_metalRough.fbx");
    EXPECT_EQ(test::countKind(pbr, MaterialKind::Emission), 0);
}

// OBJ and FBX Phong materials keep their highlight as Blender's importers make it (Cycles shows
// it): a principled dielectric whose F0 is 0.08 Ks per channel, with Blender's roughness from the
// shininess. Without a specular colour the material stays Lambert.
TEST(PrincipledImport, ObjAndFbxSpecularColourAsBlenderImportsIt) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "m.mtl",
                    "newmtl shiny\nKd 0.2 0.4 0.6\nKs 0.5 0.4 0.3\nNs 250\n"
                    "newmtl matte\nKd 0.7 0.7 0.7\nKs 0 0 0\nNs 10\n");
    test::writeFile(dir / "m.obj",
                    "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                    "usemtl shiny\nf 1 2 3\nusemtl matte\nf 2 4 3\n");
    Scene s = loadScene((dir / "m.obj").string());
    const Material* shiny = test::findMaterial(s, MaterialKind::Principled);
    ASSERT_TRUE(shiny);
    EXPECT_EQ(shiny->albedo, Color(0.2f, 0.4f, 0.6f));
    EXPECT_FLOAT_EQ(shiny->metallic, 0.0f);
    EXPECT_NEAR(shiny->roughness, 0.5f, 1e-6f);  // 1 - sqrt(250 / 1000)
    // F0 per channel = 0.04 specular specularColor = 0.08 Ks.
    const Color f0 = shiny->specularColor * (0.04f * shiny->specular);
    EXPECT_NEAR(f0.x, 0.08f * 0.5f, 1e-6f);
    EXPECT_NEAR(f0.y, 0.08f * 0.4f, 1e-6f);
    EXPECT_NEAR(f0.z, 0.08f * 0.3f, 1e-6f);
    bool matteIsLambert = false;  // Ks 0
    for (const Material& m : s.materials)
        matteIsLambert |= m.name == "matte" && m.kind == MaterialKind::Lambertian;
    EXPECT_TRUE(matteIsLambert);
    EXPECT_EQ(test::warningsNaming(s, "specular"), 0);

    // FBX: Blender's Specular is 2 SpecularFactor, roughness 1 - sqrt(Shininess) / 10.
    Scene cube = loadScene("/usr/share/assimp/models/FBX/phong_cube.fbx");
    const Material* phong = test::findMaterial(cube, MaterialKind::Principled);
    ASSERT_TRUE(phong);
    EXPECT_GT(phong->specular, 0.0f);
    EXPECT_EQ(test::warningsNaming(cube, "specular"), 0);
}

// COLLADA keeps the course's rules: an emissive material is a light and nothing else.
TEST(PrincipledImport, ColladaEmittersStayEmission) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    EXPECT_EQ(test::countKind(s, MaterialKind::Principled), 0);
    EXPECT_GE(test::countKind(s, MaterialKind::Emission), 1);
}

}  // namespace
}  // namespace kiln
