// Checks an environment map at load time, so a bad --env fails before any rendering starts.
#include <OpenImageIO/imageio.h>

#include "scene/scene_error.h"
#include "scene/scene_loader.h"

namespace kiln {

void checkEnvironmentMap(const std::string& path, std::vector<std::string>& warnings) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw SceneError(path, "cannot read environment map: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.nchannels < 3)
        throw SceneError(
            path, "environment map needs RGB channels, has " + std::to_string(spec.nchannels));
    if (spec.width != 2 * spec.height)
        warnings.push_back(path + " is " + std::to_string(spec.width) + "x" +
                           std::to_string(spec.height) +
                           ", not the 2:1 of a lat-long map; it is used as lat-long anyway");
}

}  // namespace kiln
