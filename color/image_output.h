// Writes the film: a scene-linear EXR (crash-safe: temporary file + rename) and a display-referred
// preview (PNG/JPEG) through OpenColorIO.
#pragma once

#include <map>
#include <string>

#include "renderer/film/film.h"

namespace kiln {

using Metadata = std::map<std::string, std::string>;

// The OCIO config in force: $OCIO when set, else the one shipped in color/.
std::string colorConfigPath();

struct ExrOptions {
    bool half = false;  // colour layers (beauty, light AOVs, albedo, N) as half; data stays float
    std::string compression = "zip";  // zip or piz
};

// Beauty R,G,B,A and every AOV of the film's layout as "layer.channel"; 'samples' and 'variance'
// when requested. Metadata keys are written as "kiln:KEY" strings. Throws std::runtime_error.
void writeExr(const std::string& path, const Film& film, const Metadata& metadata,
              const ExrOptions& options = {});

// The per-pixel sample counts as a heat map (blue few, red many) with a legend bar and its range.
void writeSampleHeatMap(const std::string& path, const Film& film);

// Throws std::invalid_argument unless the OCIO config has this display and view (checked before
// rendering).
void checkDisplayView(const std::string& display, const std::string& view);

// Display-referred 8-bit preview through the OCIO display/view, the scene light first scaled by
// 2^exposureStops.
void writePreview(const std::string& path, const Film& film, const std::string& display = "sRGB",
                  const std::string& view = "Standard", float exposureStops = 0);

// The scene-linear -> display transform of one value (for tests and tools).
float displayTransform(float linear, const std::string& display = "sRGB",
                       const std::string& view = "Standard");

}  // namespace kiln
