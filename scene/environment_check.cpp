// Reads an environment map at load time, so a bad --env fails before any rendering starts and the
// light-transport layer never opens a file.
#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace kiln {

std::shared_ptr<const RgbImage> loadEnvironmentMap(const std::string& path,
                                                   std::vector<std::string>& warnings) {
    ImageHeader header;
    try {
        header = readImageHeader(path);
    } catch (const ImageReadError& e) {
        throw SceneError(path, "cannot read environment map: " + e.reason);
    }
    if (header.channels < 3)
        throw SceneError(
            path, "environment map needs RGB channels, has " + std::to_string(header.channels));
    if (header.width != 2 * header.height)
        warnings.push_back(path + " is " + std::to_string(header.width) + "x" +
                           std::to_string(header.height) +
                           ", not the 2:1 of a lat-long map; it is used as lat-long anyway");
    try {
        RgbImage image = readWorkingSpaceImage(path);
        // Filtered lookups blend neighbours: a NaN, infinite or negative texel would spread.
        for (Color& c : image.pixels) c = isFinite(c) ? max(c, Color(0.0f)) : Color(0.0f);
        return std::make_shared<const RgbImage>(std::move(image));
    } catch (const ImageReadError& e) {
        throw SceneError(path, "cannot read environment map: " + e.reason);
    }
}

}  // namespace kiln
