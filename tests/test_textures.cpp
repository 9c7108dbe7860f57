// Base-colour textures through OIIO's TextureSystem, on files the tests write: texels land where
// their UVs say, decoded from sRGB; a minified checker filters to its linear mean; embedded glTF
// textures render; what the importer cannot use is a warning.
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <functional>

#include "color/image_input.h"
#include "integrators/path.h"
#include "renderer/accel/accelerator.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace kiln {
namespace {

using TexelFn = std::function<uint8_t(int x, int y, int c)>;

void writePng(const std::filesystem::path& path, int w, int h, const TexelFn& texel) {
    std::vector<uint8_t> pixels(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) pixels[(size_t(y) * w + x) * 3 + c] = texel(x, y, c);
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    out->close();
}

// A 4 x 4 quad in z = 0 with UVs (x/4, y/4), its material textured with `texture` (an OBJ with
// an MTL, so Assimp reads it); extraMtl adds lines to the material.
std::string writeTexturedQuad(const std::filesystem::path& dir, const std::string& texture,
                              const std::string& extraMtl = "") {
    test::writeFile(dir / "quad.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd " + texture + "\n" + extraMtl);
    return test::writeFile(dir / "quad.obj",
                           "mtllib quad.mtl\nusemtl tex\n"
                           "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\n"
                           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                           "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
}

Vec3 layer(const Film& f, int x, int y, const std::string& name, const char* xyz) {
    Vec3 v;
    for (int c = 0; c < 3; ++c) v[c] = f.aov(x, y, test::aovChannel(f, name + "." + xyz[c]));
    return v;
}

Film renderAlbedo(const Scene& s, int w, int h, int spp) {
    AovRequest aovs;
    aovs.add(AovKind::Albedo);
    aovs.add(AovKind::Position);
    auto accel = makeEmbreeAccelerator(s);
    return test::renderJob(s, *accel, test::jobOptions(w, h, spp, PathOptions{}, aovs));
}

// The quad's UV at the mean surface point of a pixel; false when the point is off the quad.
bool quadUv(const Film& f, int x, int y, float& u, float& v) {
    Vec3 p = layer(f, x, y, "P", "XYZ");
    u = p.x / 4, v = p.y / 4;
    return std::abs(p.z) < 1e-3f && u > 0.01f && u < 0.99f && v > 0.01f && v < 0.99f;
}

// Pixels wholly on the quad (so are their neighbours: a pixel the quad's edge crosses has one
// wholly off it, whose mean P is the background's 0), with their UV.
void forEachQuadPixel(const Film& f, const std::function<void(int, int, float, float)>& visit) {
    for (int y = 1; y + 1 < f.height(); ++y)
        for (int x = 1; x + 1 < f.width(); ++x) {
            float u, v, nu, nv;
            bool inside = quadUv(f, x, y, u, v);
            for (int dy = -1; dy <= 1 && inside; ++dy)
                for (int dx = -1; dx <= 1 && inside; ++dx)
                    inside = quadUv(f, x + dx, y + dy, nu, nv);
            if (inside) visit(x, y, u, v);
        }
}

const Material& materialNamed(const Scene& s, const std::string& name) {
    for (const Material& m : s.materials)
        if (m.name == name) return m;
    ADD_FAILURE() << "no material " << name;
    return s.materials.at(0);
}

// 8 x 8 cells of 16 x 16 texels, two colours: a pixel well inside a cell sees that cell's colour,
// decoded from sRGB, whatever MIP level its footprint picks.
TEST(Textures, TexelColourLandsWhereItsUvSays) {
    auto dir = test::scratchDir();
    const uint8_t colours[2][3] = {{200, 50, 30}, {20, 110, 230}};
    writePng(dir / "cells.png", 128, 128,
             [&](int x, int y, int c) { return colours[((x / 16) + (y / 16)) % 2][c]; });
    Scene s = loadScene(writeTexturedQuad(dir, "cells.png"));
    Film f = renderAlbedo(s, 64, 64, 4);
    int checked = 0;
    forEachQuadPixel(f, [&](int x, int y, float u, float v) {
        // Image rows run down, v up; cell coordinates in [0, 8).
        float cu = u * 8, cv = (1 - v) * 8;
        float fromEdge = std::min(
            {cu - std::floor(cu), std::ceil(cu) - cu, cv - std::floor(cv), std::ceil(cv) - cv});
        if (fromEdge < 0.3f) return;  // the pixel, its jitter and the filter stay in the cell
        const uint8_t* c = colours[(int(cu) + int(cv)) % 2];
        Vec3 want(srgbToLinear(c[0] / 255.0f), srgbToLinear(c[1] / 255.0f),
                  srgbToLinear(c[2] / 255.0f));
        Vec3 got = layer(f, x, y, "albedo", "RGB");
        EXPECT_LE(maxComponent(abs(got - want)), 2e-3f) << "pixel " << x << "," << y;
        ++checked;
    });
    // The quad covers about 30 x 30 pixels, 4 per cell; 0.4 of each cell's width is checked.
    EXPECT_GT(checked, 100);
}

// A one-texel black/white checker seen from far (16+ texels per pixel): MIP filtering in linear
// space gives 0.5 everywhere. Point sampling would give 0 or 1 (aliasing), filtering the sRGB
// codes and decoding after would give 0.21.
TEST(Textures, MinifiedCheckerFiltersToItsLinearMean) {
    auto dir = test::scratchDir();
    writePng(dir / "checker.png", 256, 256,
             [](int x, int y, int) { return uint8_t((x + y) % 2 ? 255 : 0); });
    Scene s = loadScene(writeTexturedQuad(dir, "checker.png"));
    Film f = renderAlbedo(s, 16, 16, 4);
    int checked = 0;
    forEachQuadPixel(f, [&](int x, int y, float, float) {
        Vec3 got = layer(f, x, y, "albedo", "RGB");
        EXPECT_NEAR(got.x, 0.5f, 0.03f) << "pixel " << x << "," << y;
        EXPECT_NEAR(got.y, 0.5f, 0.03f);
        ++checked;
    });
    EXPECT_GE(checked, 16);
}

// The same checker converted ahead (maketx's job, here OIIO's make_texture to a tiled MIP-mapped
// float file): used as stored, it filters to the same mean, and no note says it was 8-bit.
TEST(Textures, MipMappedFilesAreUsedAsStored) {
    auto dir = test::scratchDir();
    std::vector<float> texels(256 * 256 * 3);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            for (int c = 0; c < 3; ++c) texels[(size_t(y) * 256 + x) * 3 + c] = float((x + y) % 2);
    OIIO::ImageBuf src(OIIO::ImageSpec(256, 256, 3, OIIO::TypeDesc::FLOAT), texels.data());
    OIIO::ImageSpec config;
    config.tile_width = config.tile_height = 64;
    ASSERT_TRUE(OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, src,
                                                 (dir / "checker.tx").string(), config));
    Scene s = loadScene(writeTexturedQuad(dir, "checker.tx"));
    ASSERT_EQ(s.textureSources.size(), 1u);
    EXPECT_EQ(test::warningsNaming(s, "texture"), 0);
    Film f = renderAlbedo(s, 16, 16, 4);
    int checked = 0;
    forEachQuadPixel(f, [&](int x, int y, float, float) {
        EXPECT_NEAR(layer(f, x, y, "albedo", "RGB").x, 0.5f, 0.03f) << "pixel " << x << "," << y;
        ++checked;
    });
    EXPECT_GE(checked, 16);
    // An 8-bit one is used as stored too, and the note says its codes are taken as linear.
    OIIO::ImageBuf codes(OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::UINT8));
    OIIO::ImageBufAlgo::fill(codes, {0.5f, 0.5f, 0.5f});
    ASSERT_TRUE(OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, codes,
                                                 (dir / "codes.tx").string(), config));
    Scene eight = loadScene(writeTexturedQuad(dir, "codes.tx"));
    EXPECT_EQ(test::warningsNaming(eight, "8-bit MIP-mapped texture used as stored"), 1);
}

// Fraction of pixels whose albedo is dominated by channel c (the Cesium logo: blue sky, green
// hills).
float dominatedBy(const Film& f, int c) {
    int n = 0;
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x) {
            Vec3 a = layer(f, x, y, "albedo", "RGB");
            n += a[c] > 0.05f && a[c] > 1.5f * a[(c + 1) % 3] && a[c] > 1.5f * a[(c + 2) % 3];
        }
    return float(n) / float(f.width() * f.height());
}

// Assimp's BoxTextured: the .glb buffer and the .gltf data URI carry the same embedded PNG.
TEST(Textures, EmbeddedGltfTexturesRender) {
    const std::string dir = "/usr/share/assimp/models/glTF2/";
    Scene glb = loadScene(dir + "BoxTextured-glTF-Binary/BoxTextured.glb");
    Scene embedded = loadScene(dir + "BoxTextured-glTF-Embedded/BoxTextured.gltf");
    ASSERT_EQ(glb.textureSources.size(), 1u);
    ASSERT_TRUE(glb.textureSources[0].bytes);
    Film a = renderAlbedo(glb, 48, 48, 2), b = renderAlbedo(embedded, 48, 48, 2);
    EXPECT_GT(dominatedBy(a, 2), 0.05f);  // blue
    EXPECT_GT(dominatedBy(a, 1), 0.02f);  // green
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x)
            ASSERT_EQ(layer(a, x, y, "albedo", "RGB"), layer(b, x, y, "albedo", "RGB"));
}

TEST(Textures, MissingTextureFileIsAWarningAndThePlainColour) {
    auto dir = test::scratchDir();
    Scene s = loadScene(writeTexturedQuad(dir, "no_such.png"));
    bool warned = false;
    for (const std::string& w : s.warnings) warned |= w.find("no_such.png") != std::string::npos;
    EXPECT_TRUE(warned);
    EXPECT_EQ(materialNamed(s, "tex").albedoTexture, -1);
    EXPECT_EQ(materialNamed(s, "tex").albedo, Color(1.0f));
}

TEST(Textures, UnreadableTextureFileIsAWarning) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "broken.png", "not an image");
    Scene s = loadScene(writeTexturedQuad(dir, "broken.png"));
    bool warned = false;
    for (const std::string& w : s.warnings)
        warned |=
            w.find("broken.png") != std::string::npos && w.find("cannot read") != std::string::npos;
    EXPECT_TRUE(warned);
    EXPECT_EQ(materialNamed(s, "tex").albedoTexture, -1);
}

TEST(Textures, SlotsKilnIgnoresAreWarnings) {
    auto dir = test::scratchDir();
    writePng(dir / "t.png", 4, 4, [](int, int, int) { return uint8_t(128); });
    Scene s = loadScene(writeTexturedQuad(dir, "t.png", "map_bump bumps.png\nmap_d alpha.png\n"));
    int ignored = 0, dropped = 0;
    for (const std::string& w : s.warnings) {
        ignored +=
            w.find("ignored") != std::string::npos && w.find("bumps.png") != std::string::npos;
        // map_d is read (coverage, test_maps.cpp); this one names a missing file.
        dropped +=
            w.find("dropped") != std::string::npos && w.find("alpha.png") != std::string::npos;
    }
    EXPECT_EQ(ignored, 1);
    EXPECT_EQ(dropped, 1);
    EXPECT_GE(materialNamed(s, "tex").albedoTexture, 0);
}

}  // namespace
}  // namespace kiln

namespace kiln {
namespace {

// Assimp's phong_cube.fbx: an emissive, half-transparent Phong material with a specular colour;
// kiln renders its opacity as coverage (as OBJ's d) and its highlight as Blender's importer does
// (readPhongSpecular: no warning). Its
// emission is added to the diffuse surface (no warning); BoxTextured's glTF metallic-roughness is
// the principled material (no warning either).
TEST(MaterialWarnings, FeaturesKilnDropsAreNamed) {
    Scene s = loadScene("/usr/share/assimp/models/FBX/phong_cube.fbx");
    EXPECT_EQ(test::warningsNaming(s, "opacity"), 0);
    ASSERT_FALSE(s.materials.empty());
    EXPECT_EQ(s.materials[0].maps.alphaMode, AlphaMode::Blend);
    EXPECT_NEAR(s.materials[0].maps.opacity, 0.5f, 1e-6f);
    EXPECT_EQ(test::warningsNaming(s, "specular colour dropped"), 0);
    EXPECT_EQ(test::warningsNaming(s, "emissive"), 0);
    Scene box = loadScene("/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");
    // Its material states metallic 0; the metallic 1 of the default material Assimp's glTF
    // reader adds and no mesh uses is no one's to warn about.
    EXPECT_EQ(test::warningsNaming(box, "metallic"), 0);
}

// The CS184 files follow the CGL rules: no material warnings there.
TEST(MaterialWarnings, Cs184ScenesGetNone) {
    Scene s = loadScene(test::cs184("sky/CBspheres_lambertian.dae"));
    EXPECT_EQ(test::warningsNaming(s, "material"), 0);
}

}  // namespace
}  // namespace kiln
