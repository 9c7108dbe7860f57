#include "color/image_module.h"

// Linked in (the tests, the Python module, or inside the module itself): nothing to load.
void kiln::requireImageModule() {}

extern "C" __attribute__((visibility("default"))) const kiln::ImageModule* kiln_image_module() {
    using namespace kiln;
    static const ImageModule module{
        &readImageHeader,   &readWorkingSpaceImage, &readChannelImage, &writeSampleHeatMap,
        &writeDisplayImage, &createTextures,        &destroyTextures,  &addTexture,
        &lookupTexture,     &lookupTextureChannel,  &readExrImage,     &writeExrImage};
    return &module;
}
