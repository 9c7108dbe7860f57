#include "color/srgb_decode.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include "color/color_config.h"
#include "color/ocio_configs.h"
#include "renderer/core/log.h"

namespace kiln {
namespace {

namespace OCIO = OCIO_NAMESPACE;

// The names configs give the sRGB texture encoding: kiln's and most configs' "sRGB", ACES 1.x's
// and the OCIO 2 reference configs' texture spaces.
constexpr const char* kSrgbNames[] = {"sRGB", "sRGB - Texture", "Utility - sRGB - Texture",
                                      "srgb_tx", "srgb_texture"};

// The roles a config may point at its texture encoding, consulted in this order. Only a space
// that is sRGB-encoded is taken: ACES 1.x configs point texture_paint at ACEScc, Blender's at
// linear, and decoding 8-bit colour through those would be wrong.
const char* const kTextureRoles[] = {OCIO::ROLE_TEXTURE_PAINT, OCIO::ROLE_MATTE_PAINT,
                                     OCIO::ROLE_COLOR_PICKING};

bool looksSrgbEncoded(const OCIO::ConstColorSpaceRcPtr& space) {
    std::string name = space->getName(), encoding = space->getEncoding();
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return !space->isData() && (encoding == "sdr-video" || name.find("srgb") != std::string::npos);
}

// The config's sRGB texture space: a known name, else a texture role naming an sRGB-encoded
// space; empty when it has neither.
std::string srgbTextureSpace(const OCIO::ConstConfigRcPtr& config) {
    for (const char* name : kSrgbNames)
        if (config->getColorSpace(name)) return name;
    for (const char* role : kTextureRoles)
        if (config->hasRole(role))
            if (OCIO::ConstColorSpaceRcPtr space = config->getColorSpace(role);
                space && looksSrgbEncoded(space))
                return space->getName();
    return "";
}

// The IEC 61966-2-1 curve: the fallback when the config has no sRGB texture space.
float srgbCurve(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

// Null when falling back to srgbCurve.
OCIO::ConstCPUProcessorRcPtr makeDecoder(const std::string& path) {
    try {
        OCIO::ConstConfigRcPtr config = sharedOcioConfig(path);
        if (std::string name = srgbTextureSpace(config); !name.empty())
            return config->getProcessor(name.c_str(), OCIO::ROLE_SCENE_LINEAR)
                ->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32,
                                           OCIO::OPTIMIZATION_LOSSLESS);
        logWarning(
            "{}: no sRGB texture colour space; sRGB-encoded colour decoded with the sRGB curve",
            path);
    } catch (const OCIO::Exception& e) {
        logWarning("{}: {}; sRGB-encoded colour decoded with the sRGB curve", path, e.what());
    }
    return nullptr;
}

// The processor of the config kiln follows now, made once per read of it: $OCIO may change
// between scenes of one process, and a long session may edit the config (ocioConfigStamp).
OCIO::ConstCPUProcessorRcPtr decoder() {
    static std::mutex mutex;
    static std::string madeFor;
    static OCIO::ConstCPUProcessorRcPtr processor;
    const std::string path = colorConfigPath(), stamp = ocioConfigStamp(path);
    std::lock_guard lock(mutex);
    if (stamp != madeFor) processor = makeDecoder(path), madeFor = stamp;
    return processor;
}

}  // namespace

void decodeSrgbTexels(float* texels, size_t count, int channels) {
    const OCIO::ConstCPUProcessorRcPtr cpu = decoder();
    const size_t stride = size_t(channels);
    if (!cpu) {
        for (size_t i = 0; i < count; ++i)
            for (int c = 0; c < std::min(channels, 3); ++c)
                texels[i * stride + size_t(c)] = srgbCurve(texels[i * stride + size_t(c)]);
    } else if (channels >= 3) {  // in place, alpha and other channels skipped by the strides
        const ptrdiff_t texelBytes = ptrdiff_t(stride * sizeof(float));
        OCIO::PackedImageDesc image(texels, long(count), 1, OCIO::CHANNEL_ORDERING_RGB,
                                    OCIO::BIT_DEPTH_F32, sizeof(float), texelBytes,
                                    texelBytes * ptrdiff_t(count));
        cpu->apply(image);
    } else {  // grey (and alpha): as RGB greys, a run at a time
        constexpr size_t kRun = 4096;
        std::vector<float> rgb(3 * std::min(count, kRun));
        for (size_t start = 0; start < count; start += kRun) {
            size_t n = std::min(kRun, count - start);
            for (size_t i = 0; i < n; ++i)
                rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = texels[(start + i) * stride];
            OCIO::PackedImageDesc image(rgb.data(), long(n), 1, 3);
            cpu->apply(image);
            for (size_t i = 0; i < n; ++i) texels[(start + i) * stride] = rgb[3 * i];
        }
    }
}

float srgbToLinear(float encoded) {
    float grey = encoded;
    decodeSrgbTexels(&grey, 1, 1);
    return grey;
}

std::array<float, 256> srgb8Table() {
    std::array<float, 256> table{};
    for (size_t code = 0; code < table.size(); ++code) table[code] = float(code) / 255.0f;
    decodeSrgbTexels(table.data(), table.size(), 1);
    return table;
}

void decodeSrgb8Texels(const uint8_t* codes, float* out, size_t count, int channels) {
    const std::array<float, 256> table = srgb8Table();
    const int colour = std::min(channels, 3);
    for (size_t i = 0; i < count * size_t(channels); i += size_t(channels))
        for (int c = 0; c < channels; ++c)
            out[i + size_t(c)] =
                c < colour ? table[codes[i + size_t(c)]] : float(codes[i + size_t(c)]) / 255.0f;
}

}  // namespace kiln
