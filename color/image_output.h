// Writes the film: a scene-linear EXR (crash-safe: temporary file + rename) and a display-referred
// preview (PNG/JPEG) through OpenColorIO.
#pragma once

#include <map>
#include <string>

#include "renderer/film.h"

namespace kiln {

using Metadata = std::map<std::string, std::string>;

// The OCIO config in force: $OCIO when set, else the one shipped in color/.
std::string colorConfigPath();

// Beauty R,G,B,A plus a 'samples' channel (per-pixel sample count). Throws std::runtime_error.
void writeExr(const std::string& path, const Film& film, const Metadata& metadata);

// Display-referred 8-bit preview through the OCIO display/view.
void writePreview(const std::string& path, const Film& film, const std::string& display = "sRGB",
                  const std::string& view = "Standard");

// The scene-linear -> display transform of one value (for tests and tools).
float displayTransform(float linear, const std::string& display = "sRGB", const std::string& view = "Standard");

}  // namespace kiln
