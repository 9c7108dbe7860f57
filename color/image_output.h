// Writes the film: a scene-linear EXR (crash-safe: temporary file + rename; OpenEXR, film_exr.cpp)
// and a display-referred preview (PNG/JPEG) through OpenColorIO (preview.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "color/color_config.h"
#include "renderer/core/enum_names.h"
#include "renderer/film/film.h"

namespace kiln {

using Metadata = std::map<std::string, std::string>;

// OpenEXR's standard camera attributes (Imath row-vector matrices, p' = p M): world to the
// left-handed camera space (+z along the view) and to NDC ((0, 0) top left, (1, 1) bottom right of
// the display window, after the divide by w).
struct ExrCamera {
    std::array<float, 16> worldToCamera{}, worldToNDC{};
};

// The EXR compressions OIIO writes (pxr24, b44, b44a, dwaa and dwab are lossy).
enum class ExrCompression { None, Rle, Zip, Zips, Piz, Pxr24, B44, B44a, Dwaa, Dwab };
template <>
struct EnumNames<ExrCompression> {
    static constexpr std::pair<ExrCompression, const char*> table[] = {
        {ExrCompression::None, "none"}, {ExrCompression::Rle, "rle"},
        {ExrCompression::Zip, "zip"},   {ExrCompression::Zips, "zips"},
        {ExrCompression::Piz, "piz"},   {ExrCompression::Pxr24, "pxr24"},
        {ExrCompression::B44, "b44"},   {ExrCompression::B44a, "b44a"},
        {ExrCompression::Dwaa, "dwaa"}, {ExrCompression::Dwab, "dwab"}};
};

struct ExrOptions {
    bool half = false;  // colour layers (beauty, light AOVs, albedo, N) as half; data stays float
    ExrCompression compression = ExrCompression::Zip;
    std::optional<ExrCamera> camera;
    std::string software;  // the Software attribute; empty: "kiln VERSION"
    // The OCIO config's name for kiln's working space (its scene_linear): kiln:colorspace.
    std::string colorSpace = "lin_rec709";
    // Cryptomatte manifests (JSON text) by layer name ("CryptoObject", "CryptoMaterial").
    std::map<std::string, std::string> cryptoManifests;
    // A denoised beauty (premultiplied RGB per pixel, row-major) for R,G,B; the film's own beauty
    // then goes to noisy.R/G/B, as Cycles' "Noisy Image" pass.
    std::shared_ptr<const std::vector<Color>> denoised;
    // Denoised light-path layers by name ("direct": the film's layout().denoisedLayers()): each
    // replaces its layer's R,G,B, the film's own going to noisy.LAYER.R/G/B.
    std::map<std::string, std::shared_ptr<const std::vector<Color>>> denoisedLayers;
};

// Beauty R,G,B,A (A: coverage, colour premultiplied by it), every AOV of the film's layout as
// "layer.channel", Z, samples.X, variance.V and the Cryptomatte layers when requested, the
// noisy beauty with a denoised one (and noisy.LAYER.* with denoised layers), the half-buffers
// (halfA.*, then halfA.LAYER.* of each denoised layer, halfB.*, ...) with DenoiseHalves.
// Metadata keys are written as "kiln:KEY", numbers as numbers. Throws std::runtime_error.
void writeExr(const std::string& path, const Film& film, const Metadata& metadata,
              const ExrOptions& options = {});

// The EXR's channels grouped by layer, in the file's order: "" (R, G, B, A), then each AOV layer
// ("direct": R G B, "N": X Y Z, "Z": Z, "samples": count, "variance": V, "CryptoObject00": R G B
// A, ...).
struct ExrLayer {
    std::string name;                   // "" for the beauty
    std::vector<std::string> channels;  // "R", "X", "count", ...
    size_t first = 0;                   // its first channel's index in the file's order
};
std::vector<ExrLayer> exrLayers(const Film& film);
// Pixel (x, y) of the film in the file's channel order: the values writeExr stores (as float).
void exrPixel(const Film& film, int x, int y, std::vector<float>& values);

// One attribute of an EXR header: an integer, a number, text, or floats (matrices, chromaticities).
using ExrAttribute = std::variant<int, double, std::string, std::vector<float>>;
// The header attributes writeExr writes for this film, metadata and options (all but the channels
// and windows), by name, with the types a reader of the file finds.
std::map<std::string, ExrAttribute> exrHeader(const Film& film, const Metadata& metadata,
                                              const ExrOptions& options = {});

// The per-pixel sample counts as a heat map (blue few, red many) with a legend bar and its range.
void writeSampleHeatMap(const std::string& path, const Film& film);

// Display-referred 8-bit preview through the OCIO display/view (empty: the config's defaults),
// from the config's scene_linear, the scene light first scaled by 2^exposureStops, through the
// config's look named `look` first when given. denoised: shown instead of the film's beauty
// (ExrOptions::denoised).
void writePreview(const std::string& path, const Film& film, const std::string& display = "",
                  const std::string& view = "", float exposureStops = 0,
                  const std::string& look = "", const std::vector<Color>* denoised = nullptr);

// Whether writePreview writes this path as PNG itself (a .png or no extension) rather than through
// the image module.
bool writesPngPreview(const std::string& path);

// A preview in a format other than PNG (JPEG, ...): RGBA display codes written by OpenImageIO, in
// the image module (writePreview writes a PNG itself).
void writeDisplayImage(const std::string& path, int w, int h, const std::vector<uint8_t>& rgba);

// The scene-linear -> display transform of one value (for tests and tools).
float displayTransform(float linear, const std::string& display = "", const std::string& view = "");

}  // namespace kiln
