// Plain images become tiled MIP-mapped files in the texture cache directory once: decoded to the
// working space, reused by a later load, converted again when the source changes, and read whole
// (with a note) when the directory cannot take them.
#include <OpenImageIO/imageio.h>

#include <chrono>
#include <cstdlib>
#include <fstream>

#include "color/image_input.h"
#include "color/texture.h"
#include "color/texture_convert.h"
#include "kiln_run.h"
#include "test_support.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

// Every test process (and the kiln it starts) converts into a scratch directory, never $HOME.
const bool kTextureCacheSet = [] {
    fs::path dir = fs::temp_directory_path() / "kiln-tests" / "texture-cache";
    return ::setenv("KILN_TEXTURE_CACHE", dir.c_str(), 1) == 0;
}();

using test::ScopedEnv;

// A w x h 8-bit sRGB PNG whose texel (x, y) holds (x * 16, y * 16, 200).
std::string writeGradientPng(const fs::path& path, int w, int h) {
    std::vector<uint8_t> px;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) px.insert(px.end(), {uint8_t(x * 16), uint8_t(y * 16), 200});
    auto out = OIIO::ImageOutput::create(path.string());
    EXPECT_TRUE(out && out->open(path.string(), OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8)));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    return path.string();
}

std::vector<fs::path> convertedFiles(const fs::path& dir) {
    std::vector<fs::path> files;
    if (fs::exists(dir))
        for (const auto& e : fs::directory_iterator(dir))
            if (e.path().extension() == ".tx") files.push_back(e.path());
    return files;
}

TEST(TextureConvert, CacheDirectoryFollowsTheEnvironment) {
    ASSERT_TRUE(kTextureCacheSet);
    {
        ScopedEnv kiln("KILN_TEXTURE_CACHE", "/somewhere/tx");
        EXPECT_EQ(textureCacheDir(), "/somewhere/tx");
    }
    ScopedEnv kiln("KILN_TEXTURE_CACHE", nullptr);
    {
        ScopedEnv xdg("XDG_CACHE_HOME", "/xdg");
        EXPECT_EQ(textureCacheDir(), "/xdg/kiln/textures");
    }
    ScopedEnv xdg("XDG_CACHE_HOME", nullptr);
    ScopedEnv home("HOME", "/home/someone");
    EXPECT_EQ(textureCacheDir(), "/home/someone/.cache/kiln/textures");
}

TEST(TextureConvert, PngBecomesATiledMipFileDecodedToLinear) {
    fs::path dir = test::scratchDir(), cache = dir / "cache";
    ScopedEnv env("KILN_TEXTURE_CACHE", cache.string());
    std::string png = writeGradientPng(dir / "gradient.png", 16, 8);
    TextureSet set(16.0f);
    std::string note;
    int id = set.add(TextureSource{png, nullptr, "", TextureEncoding::Color}, &note);
    EXPECT_EQ(note, "");
    std::vector<fs::path> files = convertedFiles(cache);
    ASSERT_EQ(files.size(), 1u);
    auto in = OIIO::ImageInput::open(files[0].string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().tile_width, 64);
    OIIO::ImageSpec level1;
    EXPECT_TRUE(in->seek_subimage(0, 1, level1)) << "no MIP level 1";
    // The same texels as the image read whole in memory (decoded to linear there): lookups of
    // the finest level agree to float rounding, inside texels, between them and across the wrap.
    fs::path blocked = fs::path(test::writeFile(dir / "a-file", "")) / "cache";
    ScopedEnv whole("KILN_TEXTURE_CACHE", blocked.string());
    TextureSet reference(16.0f);
    int ref = reference.add(TextureSource{png, nullptr, "", TextureEncoding::Color});
    for (auto [s, t] : {std::pair{3.5f / 16, 2.5f / 8}, {0.61f, 0.33f}, {0.999f, 0.97f}}) {
        Color c = set.lookup(id, s, t, 0.0f), r = reference.lookup(ref, s, t, 0.0f);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], r[k], 1e-6f) << s << " " << t;
    }
    EXPECT_GT(set.lookup(id, 15.5f / 16, 0.5f / 8, 0.0f).x, 0.5f);  // decoded: 240 -> 0.87
}

TEST(TextureConvert, ReusedUntilTheSourceChanges) {
    fs::path dir = test::scratchDir(), cache = dir / "cache";
    ScopedEnv env("KILN_TEXTURE_CACHE", cache.string());
    std::string png = writeGradientPng(dir / "gradient.png", 16, 8);
    TextureSource source{png, nullptr, "", TextureEncoding::Color};
    TextureSet{16.0f}.add(source);
    std::vector<fs::path> first = convertedFiles(cache);
    ASSERT_EQ(first.size(), 1u);
    auto written = fs::last_write_time(first[0]);
    TextureSet{16.0f}.add(source);
    ASSERT_EQ(convertedFiles(cache).size(), 1u);
    EXPECT_EQ(fs::last_write_time(first[0]), written) << "reconverted an unchanged source";
    // The same file read as data (no sRGB decoding) is another conversion.
    TextureSet{16.0f}.add(TextureSource{png, nullptr, "", TextureEncoding::Data});
    EXPECT_EQ(convertedFiles(cache).size(), 2u);
    fs::last_write_time(png, fs::last_write_time(png) + std::chrono::seconds(5));
    TextureSet{16.0f}.add(source);
    EXPECT_EQ(convertedFiles(cache).size(), 3u) << "an edited source must convert again";
}

TEST(TextureConvert, EmbeddedBytesAreKeyedByTheirContent) {
    fs::path dir = test::scratchDir(), cache = dir / "cache";
    ScopedEnv env("KILN_TEXTURE_CACHE", cache.string());
    std::ifstream file(writeGradientPng(dir / "gradient.png", 16, 8), std::ios::binary);
    auto bytes = std::make_shared<const std::vector<unsigned char>>(
        std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    TextureSet set(16.0f);
    set.add(TextureSource{"*0", bytes, "png", TextureEncoding::Color});
    set.add(TextureSource{"*1", bytes, "png", TextureEncoding::Color});
    EXPECT_EQ(convertedFiles(cache).size(), 1u);
}

TEST(TextureConvert, AnUnusableDirectoryFallsBackWithANote) {
    fs::path dir = test::scratchDir();
    std::string blocker = test::writeFile(dir / "a-file", "not a directory");
    ScopedEnv env("KILN_TEXTURE_CACHE", (fs::path(blocker) / "cache").string());
    std::string png = writeGradientPng(dir / "gradient.png", 16, 8);
    TextureSet set(16.0f);
    std::string note;
    int id = set.add(TextureSource{png, nullptr, "", TextureEncoding::Color}, &note);
    EXPECT_NE(note.find("not converted to a tiled MIP-mapped file"), std::string::npos) << note;
    EXPECT_GT(set.lookup(id, 15.5f / 16, 0.5f / 8, 0.0f).x, 0.5f);  // read and decoded
}

}  // namespace
}  // namespace kiln
