// The display-referred preview (image_output.h: writePreview, displayTransform): OpenColorIO's
// display/view transform applied here, a PNG written with libpng. Only another format (a .jpg
// preview) goes through the image module's OpenImageIO writer (writeDisplayImage).
#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "color/color_config.h"
#include "color/image_output.h"
#include "color/ocio_configs.h"
#include "color/png_write.h"

namespace OCIO = OCIO_NAMESPACE;

namespace kiln {
namespace {

// scene_linear -> display/view (through the look when given), as OpenImageIO's ociodisplay builds
// it: a display-view transform in OCIO's legacy viewing pipeline, the looks as its override.
OCIO::ConstCPUProcessorRcPtr makeDisplayProcessor(const ColorSetup& setup) {
    try {
        OCIO::ConstConfigRcPtr config = sharedOcioConfig(setup.configPath);
        OCIO::DisplayViewTransformRcPtr transform = OCIO::DisplayViewTransform::Create();
        transform->setSrc(setup.sceneLinear.c_str());
        transform->setDisplay(setup.display.c_str());
        transform->setView(setup.view.c_str());
        OCIO::LegacyViewingPipelineRcPtr pipeline = OCIO::LegacyViewingPipeline::Create();
        pipeline->setDisplayViewTransform(transform);
        if (!setup.look.empty()) {
            pipeline->setLooksOverride(setup.look.c_str());
            pipeline->setLooksOverrideEnabled(true);
        }
        return pipeline->getProcessor(config, config->getCurrentContext())
            ->getDefaultCPUProcessor();
    } catch (const OCIO::Exception& e) {
        throw std::runtime_error(std::string("colour transform failed: ") + e.what());
    }
}

// Made once per config, display, view and look in a process (every frame of a batch writes a
// preview).
OCIO::ConstCPUProcessorRcPtr displayProcessor(const std::string& display, const std::string& view,
                                              const std::string& look) {
    const ColorSetup setup = checkColorConfig(display, view, look);
    static MadeFromConfig<OCIO::ConstCPUProcessorRcPtr> made;
    return made.get(setup.configStamp, setup.display, setup.view, setup.look,
                    [&] { return makeDisplayProcessor(setup); });
}

// A display value as an 8-bit code: scaled, rounded half away from zero, clamped, NaN to 0
// (OpenImageIO's float to uint8 conversion, so the preview's codes are those it wrote).
uint8_t toCode(float v) {
    const float s = std::round(v * 255.0f);
    if (!(s > 0)) return 0;
    return uint8_t(std::min(s, 255.0f));
}

// The preview's RGBA codes: the beauty (or the denoised one) scaled by 2^exposureStops, opaque
// (the premultiplied beauty over black, as rendered), through the display transform.
std::vector<uint8_t> previewCodes(const Film& film, const std::string& display,
                                  const std::string& view, float exposureStops,
                                  const std::string& look, const std::vector<Color>* denoised) {
    const size_t w = size_t(film.width()), h = size_t(film.height());
    const float scale = std::exp2(exposureStops);
    std::vector<float> rgba(w * h * 4);
    for (size_t y = 0; y < h; ++y)
        for (size_t x = 0; x < w; ++x) {
            Color c = denoised ? (*denoised)[y * w + x] : film.pixel(int(x), int(y));
            if (exposureStops != 0) c = c * scale;
            float* px = &rgba[(y * w + x) * 4];
            px[0] = c.x, px[1] = c.y, px[2] = c.z, px[3] = 1.0f;
        }
    OCIO::PackedImageDesc image(rgba.data(), long(w), long(h), 4);
    displayProcessor(display, view, look)->apply(image);
    std::vector<uint8_t> codes(rgba.size());
    std::transform(rgba.begin(), rgba.end(), codes.begin(), toCode);
    return codes;
}

}  // namespace

bool writesPngPreview(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext.empty() || ext == ".png";
}

void writePreview(const std::string& path, const Film& film, const std::string& display,
                  const std::string& view, float exposureStops, const std::string& look,
                  const std::vector<Color>* denoised) {
    const std::vector<uint8_t> codes =
        previewCodes(film, display, view, exposureStops, look, denoised);
    if (writesPngPreview(path))
        writePng(path, film.width(), film.height(), 4, codes.data(), "preview");
    else
        writeDisplayImage(path, film.width(), film.height(), codes);
}

float displayTransform(float linear, const std::string& display, const std::string& view) {
    float rgb[3] = {linear, linear, linear};
    displayProcessor(display, view, "")->applyRGB(rgb);
    return rgb[0];
}

}  // namespace kiln
