// Textures through OpenImageIO's TextureSystem: one per scene, its tile cache bounded in memory,
// MIP-mapped filtered lookups. Plain images (JPEG, PNG, EXR, embedded glTF bytes) are decoded to
// the working space and converted into tiled MIP-mapped files in the texture cache directory
// (texture_convert.h; OIIO's automip when that directory is unusable); tiled MIP-mapped files
// (maketx output) are read as they are stored.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "color/image_input.h"
#include "renderer/core/math.h"

namespace kiln {

// Colour maps are decoded to the working space (sRGB-encoded texels to linear); data maps are raw.
enum class TextureEncoding { Color, Data };

// Where a texture's bytes come from: a file, or bytes held in memory (an embedded glTF image) with
// the image format's usual extension as a hint ("png", "jpg").
struct TextureSource {
    std::string name;  // the path, or a label for embedded bytes (messages name it)
    std::shared_ptr<const std::vector<unsigned char>> bytes;  // null: read the file `name`
    std::string formatHint;
    TextureEncoding encoding = TextureEncoding::Color;
};

// How a lookup reads (s, t) outside [0, 1] on each axis (glTF sampler wrapS/wrapT: REPEAT,
// CLAMP_TO_EDGE, MIRRORED_REPEAT; Assimp's decal mode: nothing, black, outside).
enum class TextureWrap { Repeat, Clamp, Mirror, Black };
struct WrapModes {
    TextureWrap s = TextureWrap::Repeat, t = TextureWrap::Repeat;
};

class TextureSet {
  public:
    static constexpr float kDefaultCacheMb = 256.0f;
    explicit TextureSet(float cacheMb = kDefaultCacheMb);
    ~TextureSet();
    TextureSet(const TextureSet&) = delete;
    TextureSet& operator=(const TextureSet&) = delete;

    // Opens the image (header only) and returns its id; throws ImageReadError when it cannot be
    // read. A tiled MIP-mapped 8-bit colour file is used as stored: `note` then says so.
    int add(const TextureSource& source, std::string* note = nullptr);
    size_t size() const { return sources_.size(); }
    float cacheMb() const { return cacheMb_; }

    // The filtered RGB at (s, t) (s right, t down, 1 = the image width/height, outside [0, 1] as
    // `wrap` says), over a square footprint `width` wide in the same units (0: the finest level,
    // bilinear).
    Color lookup(int id, float s, float t, float width, WrapModes wrap = {}) const;
    // One channel, filtered the same way (alpha: channel 3); a channel the image lacks reads as 1
    // (an RGB texture is opaque).
    float lookupChannel(int id, int channel, float s, float t, float width,
                        WrapModes wrap = {}) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::vector<std::unique_ptr<TextureSource>> sources_;  // stable: the cache reads through them
    float cacheMb_;
};

}  // namespace kiln
