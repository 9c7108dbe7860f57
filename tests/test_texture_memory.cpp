// A scene with far more texture data than --texture-cache-mb renders in fixed memory: the peak
// resident memory of the kiln process stays within the same scene's untextured peak plus the cache
// plus a stated margin, whether the textures are tiled and MIP-mapped (maketx's form) or plain PNGs
// that kiln converts into that form in its texture cache directory at load (docs/import.md has the
// figures).
// tools/texture_memory.py runs the same check on 2 GiB of textures.
#include <OpenImageIO/imageio.h>

#include <nlohmann/json.hpp>

#include "kiln_run.h"
#include "test_support.h"

namespace kiln {
namespace {

constexpr int kTextures = 10, kSide = 2048;  // 10 x 2048^2 RGB: 480 MiB as float texels
constexpr int kCacheMb = 64;
// What else may grow with textures: OIIO's per-file records and tile bookkeeping, the allocator's
// slack. Far below the 480 MiB (float) or 240 MiB (half, as stored) a cache ignoring its limit,
// or a reader holding whole images, would take.
constexpr double kMarginMb = 48;

// A tiled MIP-mapped half-float EXR (what maketx writes), each level drawn directly from a smooth
// pattern that differs per texture: no image is ever whole in this process.
void writeTexture(const std::string& path, int index) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(kSide, kSide, 3, OIIO::TypeDesc::HALF);
    spec.tile_width = spec.tile_height = 64;
    spec.attribute("compression", "none");
    spec.attribute("textureformat", "Plain Texture");  // the EXR is MIP-mapped, as maketx writes
    ASSERT_TRUE(out->supports("mipmap"));
    std::vector<float> texels;
    for (int side = kSide, level = 0; side >= 1; side /= 2, ++level) {
        spec.width = spec.height = spec.full_width = spec.full_height = side;
        ASSERT_TRUE(out->open(
            path, spec, level ? OIIO::ImageOutput::AppendMIPLevel : OIIO::ImageOutput::Create))
            << out->geterror();
        texels.resize(size_t(side) * side * 3);
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
                float* t = &texels[(size_t(y) * side + x) * 3];
                t[0] = float(x) / side, t[1] = float(y) / side, t[2] = float(index) / kTextures;
            }
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, texels.data()));
    }
    out->close();
}

// A plain 8-bit PNG with the same kind of pattern.
void writePng(const std::string& path, int index) {
    std::vector<uint8_t> texels(size_t(kSide) * kSide * 3);
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) {
            uint8_t* t = &texels[(size_t(y) * kSide + x) * 3];
            t[0] = uint8_t(x * 255 / kSide), t[1] = uint8_t(y * 255 / kSide);
            t[2] = uint8_t(index * 255 / kTextures);
        }
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(kSide, kSide, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("png:compressionLevel", 1);
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, texels.data()));
    out->close();
}

// kTextures unit quads side by side, each with its own material, textured (texI.EXTENSION) when
// `textured`.
std::string writeScene(const std::filesystem::path& dir, const std::string& name, bool textured,
                       const std::string& extension = "exr") {
    std::string mtl, obj = "mtllib " + name + ".mtl\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    for (int i = 0; i < kTextures; ++i) {
        std::string m = "m" + std::to_string(i), x0 = std::to_string(i * 1.1),
                    x1 = std::to_string(i * 1.1 + 1);
        mtl += "newmtl " + m + "\nKd 1 1 1\n" +
               (textured ? "map_Kd tex" + std::to_string(i) + "." + extension + "\n" : "");
        obj += "usemtl " + m + "\nv " + x0 + " 0 0\nv " + x1 + " 0 0\nv " + x1 + " 1 0\nv " + x0 +
               " 1 0\n";
        int v = 4 * i + 1;
        auto corner = [&](int k) { return std::to_string(v + k) + "/" + std::to_string(k + 1); };
        obj += "f " + corner(0) + " " + corner(1) + " " + corner(2) + "\nf " + corner(0) + " " +
               corner(2) + " " + corner(3) + "\n";
    }
    test::writeFile(dir / (name + ".mtl"), mtl);
    return test::writeFile(dir / (name + ".obj"), obj);
}

// With --heatmap every run loads the image module (OpenImageIO's libraries, about 110 MiB
// resident), an untextured one too: the difference between two runs is the textures' memory.
double peakMb(const std::string& scene, const std::filesystem::path& dir) {
    test::CliRun r = test::runKiln("render " + scene + " -o " + (dir / "out.exr").string() +
                                   " -r 320 48 -s 1 -q --json --heatmap --texture-cache-mb " +
                                   std::to_string(kCacheMb));
    EXPECT_EQ(r.code, 0) << r.err;
    if (r.code != 0) return 0;
    return nlohmann::json::parse(r.out)["peak_memory_bytes"].get<double>() / (1 << 20);
}

TEST(TextureMemory, TexturesBeyondTheCacheRenderInFixedMemory) {
    auto dir = test::scratchDir();
    for (int i = 0; i < kTextures; ++i)
        writeTexture((dir / ("tex" + std::to_string(i) + ".exr")).string(), i);
    double plain = peakMb(writeScene(dir, "plain", false), dir);
    double textured = peakMb(writeScene(dir, "textured", true), dir);
    RecordProperty("untextured_peak_mb", std::to_string(plain));
    RecordProperty("textured_peak_mb", std::to_string(textured));
    EXPECT_GT(plain, 0);
    EXPECT_LE(textured, plain + kCacheMb + kMarginMb)
        << "untextured " << plain << " MiB, cache " << kCacheMb << " MiB";
    // The bound is meaningful: the float texels alone are several times the allowance.
    double texelsMb = double(kTextures) * kSide * kSide * 3 * 4 / (1 << 20);
    EXPECT_GT(texelsMb, 4 * (kCacheMb + kMarginMb));
}

// Plain PNGs are converted once (one at a time) into tiled MIP files in the texture cache; the
// render that reads them, like the tiled case, stays within the cache plus the margin (read whole
// through automip they took 325 MiB against 149 MiB untextured).
TEST(TextureMemory, PlainPngsConvertedAtLoadRenderInFixedMemory) {
    auto dir = test::scratchDir();
    for (int i = 0; i < kTextures; ++i)
        writePng((dir / ("tex" + std::to_string(i) + ".png")).string(), i);
    test::ScopedEnv cache("KILN_TEXTURE_CACHE", (dir / "cache").string());
    double plain = peakMb(writeScene(dir, "plain", false), dir);
    std::string scene = writeScene(dir, "textured", true, "png");
    double converting = peakMb(scene, dir);
    double textured = peakMb(scene, dir);
    RecordProperty("untextured_peak_mb", std::to_string(plain));
    RecordProperty("converting_peak_mb", std::to_string(converting));
    RecordProperty("textured_peak_mb", std::to_string(textured));
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir / "cache"),
                            std::filesystem::directory_iterator()),
              kTextures);
    EXPECT_GT(plain, 0);
    EXPECT_LE(textured, plain + kCacheMb + kMarginMb)
        << "untextured " << plain << " MiB, cache " << kCacheMb << " MiB";
}

}  // namespace
}  // namespace kiln
