// The kiln executable's side of the image module (image_module.h): each image function loads
// kiln_image.so on its first call and forwards to the module's own. The module sits beside the
// binary in the build tree and in KILN_IMAGE_MODULE_FROM_BINARY once installed.
#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>

#include "color/image_module.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

const ImageModule& loadModule() {
    fs::path dir = fs::read_symlink("/proc/self/exe").parent_path();
    std::string errors;
    for (const fs::path& path :
         {dir / "kiln_image.so", (dir / KILN_IMAGE_MODULE_FROM_BINARY).lexically_normal()}) {
        void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            errors += std::string(errors.empty() ? "" : "; ") + ::dlerror();
            continue;
        }
        auto entry =
            reinterpret_cast<decltype(&kiln_image_module)>(::dlsym(handle, kImageModuleEntry));
        if (entry) return *entry();
        errors += "; " + path.string() + ": no " + kImageModuleEntry;
    }
    // A binary copied elsewhere needs its kiln_image.so beside it (cp build/kiln
    // build/kiln_image.so).
    throw std::runtime_error(
        "cannot load kiln_image.so, kiln's image module (reading or writing an "
        "image needs it; a copied kiln binary needs it beside it): " +
        errors);
}

const ImageModule& module() {
    static const ImageModule& loaded = loadModule();
    return loaded;
}

}  // namespace

void requireImageModule() { module(); }

ImageHeader readImageHeader(const std::string& path) { return module().readImageHeader(path); }
RgbImage readWorkingSpaceImage(const std::string& path) {
    return module().readWorkingSpaceImage(path);
}
bool readChannelImage(const std::string& path, ChannelImage& image) {
    return module().readChannelImage(path, image);
}
void writeSampleHeatMap(const std::string& path, const Film& film) {
    module().writeSampleHeatMap(path, film);
}
void writeDisplayImage(const std::string& path, int w, int h, const std::vector<uint8_t>& rgba) {
    module().writeDisplayImage(path, w, h, rgba);
}
OiioTextures* createTextures(float cacheMb) { return module().createTextures(cacheMb); }
void destroyTextures(OiioTextures* textures) { module().destroyTextures(textures); }
int addTexture(OiioTextures& textures, const TextureSource& stored, size_t number,
               std::string* note) {
    return module().addTexture(textures, stored, number, note);
}
Color lookupTexture(const OiioTextures& textures, int id, float s, float t, float width,
                    const WrapModes& wrap) {
    return module().lookupTexture(textures, id, s, t, width, wrap);
}
float lookupTextureChannel(const OiioTextures& textures, int id, int channel, float s, float t,
                           float width, const WrapModes& wrap) {
    return module().lookupTextureChannel(textures, id, channel, s, t, width, wrap);
}

void readExrImage(const std::string& path, ExrImage& image) { module().readExrImage(path, image); }
void writeExrImage(const std::string& path, const ExrImage& image) {
    module().writeExrImage(path, image);
}

}  // namespace kiln
