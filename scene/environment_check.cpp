// Reads an environment map at load time, so a bad --env fails before any rendering starts and the
// light-transport layer never opens a file.
#include <optional>

#include "color/exr_rgb_input.h"
#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace kiln {

namespace {

void warnIfNotLatLong(const std::string& path, int width, int height,
                      std::vector<std::string>& warnings) {
    if (width != 2 * height)
        warnings.push_back(path + " is " + std::to_string(width) + "x" + std::to_string(height) +
                           ", not the 2:1 of a lat-long map; it is used as lat-long anyway");
}

// Filtered lookups blend neighbours: a NaN, infinite or negative texel would spread.
std::shared_ptr<const RgbImage> sanitised(RgbImage image) {
    for (Color& c : image.pixels) c = isFinite(c) ? max(c, Color(0.0f)) : Color(0.0f);
    return std::make_shared<const RgbImage>(std::move(image));
}

}  // namespace

std::shared_ptr<const RgbImage> loadEnvironmentMap(const std::string& path,
                                                   std::vector<std::string>& warnings) {
    // A plain RGB EXR (the usual map) without the image module; anything else through it.
    if (std::optional<RgbImage> exr = readExrRgb(path)) {
        warnIfNotLatLong(path, exr->width, exr->height, warnings);
        return sanitised(std::move(*exr));
    }
    ImageHeader header;
    try {
        header = readImageHeader(path);
    } catch (const ImageReadError& e) {
        throw SceneError(path, "cannot read environment map: " + e.reason);
    }
    if (header.channels < 3)
        throw SceneError(
            path, "environment map needs RGB channels, has " + std::to_string(header.channels));
    warnIfNotLatLong(path, header.width, header.height, warnings);
    try {
        return sanitised(readWorkingSpaceImage(path));
    } catch (const ImageReadError& e) {
        throw SceneError(path, "cannot read environment map: " + e.reason);
    }
}

}  // namespace kiln
