// Reads an environment map at load time, so a bad --env fails before any rendering starts and the
// light-transport layer never opens a file.
#include <fmt/format.h>

#include <filesystem>
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

// Filtered lookups blend neighbours: a NaN, infinite or negative texel would spread. Each one
// set to 0 is counted in a warning: a map of NaNs must not render black without a word.
std::shared_ptr<const RgbImage> sanitised(const std::string& path, RgbImage image,
                                          std::vector<std::string>& warnings) {
    size_t nonFinite = 0, negative = 0;
    for (Color& c : image.pixels) {
        if (!isFinite(c)) {
            ++nonFinite, c = Color(0.0f);
        } else if (c.x < 0 || c.y < 0 || c.z < 0) {
            ++negative, c = max(c, Color(0.0f));
        }
    }
    if (nonFinite + negative > 0)
        warnings.push_back(
            fmt::format("{}: {} of {} texels NaN or infinite (set to 0), {} with a "
                        "negative channel (clamped to 0)",
                        path, nonFinite, image.pixels.size(), negative));
    return std::make_shared<const RgbImage>(std::move(image));
}

}  // namespace

std::shared_ptr<const RgbImage> loadEnvironmentMap(const std::string& path,
                                                   std::vector<std::string>& warnings) {
    // Before any open: opening a FIFO blocks until a writer comes, signals and all.
    std::error_code ec;
    if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
        throw SceneError(path,
                         "is not a regular file (a directory, FIFO, socket or device), not "
                         "an environment map");
    // A plain RGB EXR (the usual map) without the image module; anything else through it.
    if (std::optional<RgbImage> exr = readExrRgb(path)) {
        warnIfNotLatLong(path, exr->width, exr->height, warnings);
        return sanitised(path, std::move(*exr), warnings);
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
        return sanitised(path, readWorkingSpaceImage(path), warnings);
    } catch (const ImageReadError& e) {
        throw SceneError(path, "cannot read environment map: " + e.reason);
    }
}

}  // namespace kiln
