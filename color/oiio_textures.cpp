#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <chrono>
#include <cstring>
#include <filesystem>

#include "color/color_config.h"
#include "color/image_input.h"
#include "color/texture.h"
#include "color/texture_convert.h"
#include "color/texture_system.h"
#include "renderer/core/log.h"

namespace kiln {
namespace {

// The config attribute through which the cache hands a source to the input that decodes it.
constexpr const char* kSourceAttribute = "kiln:source";

// Opens the file, or the bytes in memory through a proxy that must outlive the input.
// Colour stays unassociated (straight) as PNG and glTF store it: OIIO would otherwise premultiply
// by alpha, and a cut-out texel's colour (or a half-transparent one's) would darken.
std::unique_ptr<OIIO::ImageInput> openTextureSource(
    const TextureSource& source, std::unique_ptr<OIIO::Filesystem::IOMemReader>& proxy) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    if (!source.bytes) return OIIO::ImageInput::open(source.name, &config);
    proxy =
        std::make_unique<OIIO::Filesystem::IOMemReader>(source.bytes->data(), source.bytes->size());
    // With a config, OIIO 2.4 takes the proxy from it, not from the argument.
    OIIO::Filesystem::IOProxy* io = proxy.get();
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &io);
    return OIIO::ImageInput::open("embedded." + source.formatHint, &config, io);
}

// What a texture's texels need to reach the working space: nothing for data (normals, roughness).
TexelConversion conversionOf(const TextureSource& source, const OIIO::ImageSpec& spec) {
    return source.encoding == TextureEncoding::Color ? colourConversion(spec) : TexelConversion{};
}

// Presents an image (a file or bytes in memory) to the ImageCache as float scanlines in the
// working space, so automip filters linear values: filtering sRGB-encoded texels and decoding
// afterwards would darken every minified texture (a black/white checker's mean is 0.5, not 0.21).
class WorkingSpaceInput final : public OIIO::ImageInput {
  public:
    const char* format_name() const override { return "kiln-working-space"; }
    bool open(const std::string& name, OIIO::ImageSpec& spec) override {
        return open(name, spec, OIIO::ImageSpec());
    }
    bool open(const std::string&, OIIO::ImageSpec& spec, const OIIO::ImageSpec& config) override {
        const OIIO::ParamValue* p = config.find_attribute(kSourceAttribute, OIIO::TypeDesc::PTR);
        if (!p) return false;
        source_ = *static_cast<TextureSource* const*>(p->data());
        inner_ = openTextureSource(*source_, proxy_);
        if (!inner_) return false;
        m_spec = inner_->spec();
        conversion_ = conversionOf(*source_, m_spec);
        m_spec.set_format(OIIO::TypeDesc::FLOAT);
        m_spec.tile_width = m_spec.tile_height = m_spec.tile_depth = 0;
        spec = m_spec;
        return true;
    }
    bool close() override {
        inner_.reset();
        return true;
    }
    bool read_native_scanline(int, int, int y, int z, void* data) override {
        // PNG and JPEG decode forwards only; an earlier row (the cache evicted it) starts over.
        if (y < nextRow_) {
            inner_.reset();  // before its proxy is replaced
            inner_ = openTextureSource(*source_, proxy_);
            if (!inner_) return false;
        }
        nextRow_ = y + 1;
        int nch = m_spec.nchannels;
        auto* out = static_cast<float*>(data);
        if (conversion_.decodeSrgb && inner_->spec().format == OIIO::TypeDesc::UINT8) {
            codes_.resize(size_t(m_spec.width) * size_t(nch));
            if (!inner_->read_scanlines(0, 0, y, y + 1, z, 0, nch, OIIO::TypeDesc::UINT8,
                                        codes_.data()))
                return false;
            decodeSrgb8Texels(codes_.data(), out, size_t(m_spec.width), nch);
            return true;
        }
        if (!inner_->read_scanlines(0, 0, y, y + 1, z, 0, nch, OIIO::TypeDesc::FLOAT, data))
            return false;
        conversion_.apply(out, size_t(m_spec.width), nch);
        return true;
    }

  private:
    std::unique_ptr<OIIO::ImageInput> inner_;
    std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy_;
    const TextureSource* source_ = nullptr;
    std::vector<uint8_t> codes_;  // an 8-bit scanline
    int nextRow_ = 0;
    TexelConversion conversion_;
};

OIIO::ImageInput* createWorkingSpaceInput() { return new WorkingSpaceInput; }

bool isMipMapped(OIIO::ImageInput& in) {
    if (in.spec().tile_width == 0) return false;
    OIIO::ImageSpec level1;
    return in.seek_subimage(0, 1, level1);
}

// The tiled MIP-mapped file of a plain image in the texture cache directory: converted now, or
// by an earlier render of the same content. Empty, with a note, when the directory cannot take it
// (the image is then read whole through automip).
std::string tiledMipFile(const TextureSource& source, OIIO::ImageInput& in, std::string* note) {
    namespace fs = std::filesystem;
    TexelConversion conversion = conversionOf(source, in.spec());
    std::string dir = textureCacheDir();
    try {
        std::string identity;
        if (source.bytes) {
            identity.assign(source.bytes->begin(), source.bytes->end());
        } else {
            fs::path path = fs::absolute(source.name);
            identity = path.string() + "\n" + std::to_string(fs::file_size(path)) + "\n" +
                       std::to_string(fs::last_write_time(path).time_since_epoch().count());
        }
        if (conversion
                .decodeSrgb) {  // decoded through the OCIO config: another config converts again
            std::string config = colorConfigPath();
            identity += "\n" + config + "\n" +
                        std::to_string(fs::last_write_time(config).time_since_epoch().count());
        }
        std::string target = (fs::path(dir) / convertedTextureName(identity, conversion)).string();
        if (fs::exists(target)) {
            logDebug("texture {}: reusing {}", source.name, target);
            return target;
        }
        fs::create_directories(dir);
        auto start = std::chrono::steady_clock::now();
        convertToTiledMip(in, conversion, target);
        logInfo("texture {}: converted to the tiled MIP-mapped {} ({:.2f} s)", source.name, target,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        return target;
    } catch (const std::exception& e) {
        if (note)
            *note = std::string("not converted to a tiled MIP-mapped file in ") + dir + " (" +
                    e.what() + "): read whole, outside --texture-cache-mb";
        return "";
    }
}

}  // namespace

struct OiioTextures {
    OIIO::TextureSystem* system = nullptr;
    std::vector<OIIO::TextureSystem::TextureHandle*> handles;
    std::vector<int> channels;  // per handle
    ~OiioTextures() {
        // Never destroyed: OIIO's per-thread micro-cache outlives a TextureSystem and keys its last
        // tile by the file record's address, so a later scene's texture allocated at a freed
        // record's address read the earlier scene's tiles (NormalMap tests after AssetScenes ones
        // in one process). Its tiles and open files are released; the small file records stay.
        if (!system) return;
        system->imagecache()->invalidate_all(true);
        system->imagecache()->close_all();
    }
};

OiioTextures* createTextures(float cacheMb) {
    auto textures = std::make_unique<OiioTextures>();
    // A private system: its cache limit and files belong to this scene alone.
    textures->system = OIIO::TextureSystem::create(false);
    textures->system->attribute("max_memory_MB", cacheMb);
    textures->system->attribute("automip", 1);
    textures->system->attribute("autotile", 64);
    textures->system->attribute("accept_untiled", 1);
    // Converted files keep straight (unassociated) alpha, as the sources do.
    textures->system->attribute("unassociatedalpha", 1);
    return textures.release();
}

void destroyTextures(OiioTextures* textures) { delete textures; }

int addTexture(OiioTextures& textures, const TextureSource& stored, size_t number,
               std::string* note) {
    std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
    auto in = openTextureSource(stored, proxy);
    if (!in) throw ImageReadError(stored.name, "cannot read texture: " + OIIO::geterror());
    std::string file;  // what the cache reads; empty: the source through automip
    // A MIP-mapped file is read as stored unless its linear colour needs a matrix (another
    // working space or stated chromaticities): a converted copy then holds the working space's.
    if (!stored.bytes && isMipMapped(*in) && !conversionOf(stored, in->spec()).matrix) {
        file = stored.name;
        if (note && stored.encoding == TextureEncoding::Color && isSrgbEncoded(in->spec()))
            *note =
                "8-bit MIP-mapped texture used as stored (taken as linear; convert it with "
                "maketx --colorconvert sRGB linear)";
    } else {
        file = tiledMipFile(stored, *in, note);
    }
    in.reset();  // before its proxy
    std::string key = file;
    if (file.empty()) {
        // A name of its own per source and encoding: the cache keys files by name.
        key = "kiln-texture:" + std::to_string(number) + ":" + stored.name;
        OIIO::ImageSpec config;
        const TextureSource* source = &stored;
        config.attribute(kSourceAttribute, OIIO::TypeDesc::PTR, &source);
        textures.system->imagecache()->add_file(OIIO::ustring(key), createWorkingSpaceInput,
                                                &config);
    }
    auto* handle = textures.system->get_texture_handle(OIIO::ustring(key));
    OIIO::ImageSpec spec;
    if (!handle || !textures.system->get_imagespec(handle, nullptr, 0, spec))
        throw ImageReadError(stored.name, "cannot read texture: " + textures.system->geterror());
    textures.handles.push_back(handle);
    textures.channels.push_back(spec.nchannels);
    return int(textures.handles.size()) - 1;
}

namespace {

OIIO::TextureOpt::Wrap oiioWrap(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Clamp:
            return OIIO::TextureOpt::WrapClamp;
        case TextureWrap::Mirror:
            return OIIO::TextureOpt::WrapMirror;
        case TextureWrap::Black:
            return OIIO::TextureOpt::WrapBlack;
        case TextureWrap::Repeat:
            break;
    }
    return OIIO::TextureOpt::WrapPeriodic;
}

}  // namespace

Color lookupTexture(const OiioTextures& textures, int id, float s, float t, float width,
                    const WrapModes& wrap) {
    OIIO::TextureOpt opt;
    opt.swrap = oiioWrap(wrap.s), opt.twrap = oiioWrap(wrap.t);
    float rgb[3] = {0, 0, 0};
    opt.fill = 0;
    textures.system->texture(textures.handles[size_t(id)], nullptr, opt, s, t, width, 0, 0, width,
                             3, rgb);
    return Color(rgb[0], rgb[1], rgb[2]);
}

float lookupTextureChannel(const OiioTextures& textures, int id, int channel, float s, float t,
                           float width, const WrapModes& wrap) {
    if (channel >= textures.channels[size_t(id)]) return 1.0f;
    OIIO::TextureOpt opt;
    opt.swrap = oiioWrap(wrap.s), opt.twrap = oiioWrap(wrap.t);
    opt.firstchannel = channel;
    float value = 1.0f;
    textures.system->texture(textures.handles[size_t(id)], nullptr, opt, s, t, width, 0, 0, width,
                             1, &value);
    return value;
}

}  // namespace kiln
