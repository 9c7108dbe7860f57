// Plain images (PNG, JPEG, scanline EXR, embedded glTF bytes) converted once into tiled, MIP-mapped
// files in a texture cache directory, as Arnold's auto-tx and Cycles' use_auto_tx do: the
// TextureSystem then reads tiles on demand and a render stays within --texture-cache-mb, where
// OIIO's automip would hold every untiled image whole.
#pragma once

#include <OpenImageIO/imageio.h>

#include <string>

#include "color/texel_conversion.h"

namespace kiln {

// $KILN_TEXTURE_CACHE, else $XDG_CACHE_HOME/kiln/textures, else $HOME/.cache/kiln/textures.
std::string textureCacheDir();

// The cached file's name for an image: a hash of what identifies its content (a file's absolute
// path, size and modification time, or embedded bytes themselves), how it is decoded and the
// conversion's version, so an edited source or a new kiln converts again.
std::string convertedTextureName(const std::string& identity, const TexelConversion& conversion);

// Reads the image from `in` as float, takes its colour channels to the working space by
// `conversion` (alpha stays straight), and writes it as a tiled MIP-mapped float TIFF at `target`
// through a unique temporary name and a rename, so concurrent renders and a kill never leave a
// partial file. Throws std::runtime_error naming target and the reason.
void convertToTiledMip(OIIO::ImageInput& in, const TexelConversion& conversion,
                       const std::string& target);

}  // namespace kiln
