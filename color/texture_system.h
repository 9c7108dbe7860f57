// TextureSet's OpenImageIO side: one TextureSystem per scene, its files and handles, defined in
// oiio_textures.cpp. It lives in the image module kiln loads on first use (color/image_module.h),
// so a process that reads no texture never loads OpenImageIO. This header is all that texture.cpp
// and the module share (oiio_textures.cpp reads texture.h's types; texture.cpp only these calls).
#pragma once

#include <cstddef>
#include <string>

#include "renderer/core/math.h"

namespace kiln {

struct TextureSource;
struct WrapModes;
struct OiioTextures;

OiioTextures* createTextures(float cacheMb);
void destroyTextures(OiioTextures* textures);
// Opens `stored` (which must outlive the textures: the cache reads through it), the number-th
// source of the set; returns its id. Throws ImageReadError.
int addTexture(OiioTextures& textures, const TextureSource& stored, size_t number,
               std::string* note);
Color lookupTexture(const OiioTextures& textures, int id, float s, float t, float width,
                    const WrapModes& wrap);
float lookupTextureChannel(const OiioTextures& textures, int id, int channel, float s, float t,
                           float width, const WrapModes& wrap);

}  // namespace kiln
