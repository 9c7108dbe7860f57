#include "color/image_module.h"

#include <OpenEXR/ImfThreading.h>
#include <OpenImageIO/imageio.h>

// Linked in (the tests, the Python module, or inside the module itself): nothing to load.
void kiln::requireImageModule() {}

extern "C" __attribute__((visibility("default"))) const kiln::ImageModule* kiln_image_module() {
    using namespace kiln;
    // OpenImageIO sets OpenEXR's pool to every core when it first opens an EXR (a texture): it
    // keeps the count kiln chose instead (a render's -t, set before the scene loads).
    static const bool exrThreadsKept = [] {
        if (int n = Imf::globalThreadCount(); n > 0) OIIO::attribute("exr_threads", n);
        return true;
    }();
    (void)exrThreadsKept;
    static const ImageModule module{
        &readImageHeader,   &readWorkingSpaceImage, &readChannelImage, &writeSampleHeatMap,
        &writeDisplayImage, &createTextures,        &destroyTextures,  &addTexture,
        &lookupTexture,     &lookupTextureChannel,  &readExrImage,     &writeExrImage};
    return &module;
}
