#include "color/texture.h"

#include "color/texture_system.h"

namespace kiln {

// The OpenImageIO side's textures (texture_system.h).
struct TextureSet::Impl {
    OiioTextures* textures;
    ~Impl() { destroyTextures(textures); }
};

TextureSet::TextureSet(float cacheMb)
    : impl_(new Impl{createTextures(cacheMb)}), cacheMb_(cacheMb) {}

TextureSet::~TextureSet() = default;

int TextureSet::add(const TextureSource& source, std::string* note) {
    // Stored first: the cache reads through the stored copy; taken back if it cannot be read.
    sources_.push_back(std::make_unique<TextureSource>(source));
    try {
        return addTexture(*impl_->textures, *sources_.back(), sources_.size(), note);
    } catch (...) {
        sources_.pop_back();
        throw;
    }
}

Color TextureSet::lookup(int id, float s, float t, float width, WrapModes wrap) const {
    return lookupTexture(*impl_->textures, id, s, t, width, wrap);
}

float TextureSet::lookupChannel(int id, int channel, float s, float t, float width,
                                WrapModes wrap) const {
    return lookupTextureChannel(*impl_->textures, id, channel, s, t, width, wrap);
}

}  // namespace kiln
