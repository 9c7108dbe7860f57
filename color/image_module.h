// The image module: every call of OpenImageIO in kiln (image_input, image_output, exr_image,
// oiio_textures, texture_convert, atomic_file_proxy) is built into kiln_image.so, which the kiln
// executable loads with dlopen() at its first image call (image_stubs.cpp). OpenImageIO links about
// 250 libraries whose relocation was all of kiln's start-up (docs/performance.md "Start-up"): kiln
// --version, kiln info and kiln render of a scene that reads no image (the film's EXR and the PNG
// preview are written without OpenImageIO: film_exr.cpp, preview.cpp) and the batch and farm
// parents never load them.
// The tests and the Python module link the same code directly, without the module.
#pragma once

#include "color/exr_image.h"
#include "color/image_input.h"
#include "color/image_output.h"
#include "color/texture_system.h"

namespace kiln {

// The module's functions, by the names the headers above declare.
struct ImageModule {
    decltype(&kiln::readImageHeader) readImageHeader;
    decltype(&kiln::readWorkingSpaceImage) readWorkingSpaceImage;
    decltype(&kiln::readChannelImage) readChannelImage;
    decltype(&kiln::writeSampleHeatMap) writeSampleHeatMap;
    decltype(&kiln::writeDisplayImage) writeDisplayImage;
    decltype(&kiln::createTextures) createTextures;
    decltype(&kiln::destroyTextures) destroyTextures;
    decltype(&kiln::addTexture) addTexture;
    decltype(&kiln::lookupTexture) lookupTexture;
    decltype(&kiln::lookupTextureChannel) lookupTextureChannel;
    decltype(&kiln::readExrImage) readExrImage;
    decltype(&kiln::writeExrImage) writeExrImage;
};

// Loads the module now in the kiln executable (a no-op where the image code is linked in): kiln
// render calls it before the scene loads when its outputs need it (a heat map, a preview in another
// format than PNG), so a missing module is an error before any work. A scene's textures and maps
// load it as they are read (its loading then counts in the render's load time). Throws
// std::runtime_error when it cannot be loaded.
void requireImageModule();

// The module's one exported symbol, looked up by name after dlopen().
constexpr const char* kImageModuleEntry = "kiln_image_module";

}  // namespace kiln

extern "C" const kiln::ImageModule* kiln_image_module();
