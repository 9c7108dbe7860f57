// The one way color/ writes an image through OpenImageIO: an AtomicFile (unique temporary,
// checked writes, fsync, rename). For image_output.cpp and exr_image.cpp.
#pragma once

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <string>

namespace kiln {

// spec's pixel type is what the file stores (dataType: all channels, when given). Throws
// std::runtime_error naming path and what.
void writeAtomically(const std::string& path, const std::string& format, OIIO::ImageSpec spec,
                     const OIIO::ImageBuf& buf, const char* what,
                     OIIO::TypeDesc dataType = OIIO::TypeDesc::UNKNOWN);

}  // namespace kiln
