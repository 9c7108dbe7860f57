#include "color/texture_convert.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "color/atomic_file.h"
#include "color/image_input.h"
#include "color/working_space.h"
#include "renderer/core/sampler.h"

namespace kiln {
namespace {

// Bumped whenever what a converted file holds changes (format, filter, decoding).
constexpr uint64_t kConversionVersion = 1;

uint64_t hashBytes(const std::string& bytes) {
    uint64_t h = 0x84222325cbf29ce4ull;  // FNV-1a, then mixed
    for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
    return mix64(h);
}

}  // namespace

std::string textureCacheDir() {
    if (const char* dir = std::getenv("KILN_TEXTURE_CACHE"); dir && *dir) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
        return (std::filesystem::path(xdg) / "kiln" / "textures").string();
    const char* home = std::getenv("HOME");
    return (std::filesystem::path(home && *home ? home : "/tmp") / ".cache" / "kiln" / "textures")
        .string();
}

std::string convertedTextureName(const std::string& identity, const TexelConversion& conversion) {
    const bool decodeSrgb = conversion.decodeSrgb;
    uint64_t h = mix64(hashBytes(identity) ^ (decodeSrgb ? 1 : 2) ^ (kConversionVersion << 8));
    // Decoded sRGB lands in scene_linear: another working space is another file.
    if (const WorkingSpace& space = workingSpace(); decodeSrgb && !space.rec709)
        h = mix64(h ^ hashBytes(space.name));
    // A matrix (another working space, stated chromaticities): its values name the result.
    if (conversion.matrix)
        h = mix64(h ^ hashBytes(std::string(reinterpret_cast<const char*>(&conversion.toWorking),
                                            sizeof conversion.toWorking)));
    return fmt::format("{:016x}.tx", h);
}

void convertToTiledMip(OIIO::ImageInput& in, const TexelConversion& conversion,
                       const std::string& target) {
    OIIO::ImageSpec spec = in.spec();
    const int nch = spec.nchannels;
    const size_t texels = size_t(spec.width) * size_t(spec.height);
    std::vector<float> pixels(texels * size_t(nch));
    if (conversion.decodeSrgb &&
        spec.format == OIIO::TypeDesc::UINT8) {  // 8-bit: through the code table
        std::vector<uint8_t> codes(pixels.size());
        if (!in.read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, codes.data()))
            throw std::runtime_error(target + ": cannot read the source image: " + in.geterror());
        decodeSrgb8Texels(codes.data(), pixels.data(), texels, nch);
    } else {
        if (!in.read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, pixels.data()))
            throw std::runtime_error(target + ": cannot read the source image: " + in.geterror());
        conversion.apply(pixels.data(), texels, nch);
    }
    spec.set_format(OIIO::TypeDesc::FLOAT);
    spec.tile_width = spec.tile_height = spec.tile_depth = 0;
    OIIO::ImageBuf image(spec, pixels.data());

    OIIO::ImageSpec config;
    config.tile_width = config.tile_height = 64;
    config.tile_depth = 1;
    config.set_format(OIIO::TypeDesc::FLOAT);
    config.attribute("maketx:fileformatname", "tiff");
    config.attribute("maketx:hash", 0);
    // A unique temporary beside the target (AtomicFile), which make_texture then writes by name.
    AtomicFile file(target);
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, image, file.tempPath(),
                                          config))
        throw std::runtime_error(target +
                                 ": cannot write the converted texture: " + OIIO::geterror());
    file.commit();
}

}  // namespace kiln
