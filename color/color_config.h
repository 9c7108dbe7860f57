// The OCIO config kiln follows: $OCIO when set, else the one a front end ships beside itself (the
// installed Python module's package), else the one installed beside the binary
// (PREFIX/share/kiln/config.ocio for PREFIX/bin/kiln), else the source tree's (build directory).
// Everything kiln needs from it is checked before a render starts.
#pragma once

#include <string>
#include <vector>

namespace kiln {

std::string colorConfigPath();

// The config shipped beside a front end that is not the kiln binary (the Python module: its
// package's config.ocio when installed); taken when the file exists. Empty: none.
void setBundledColorConfig(const std::string& path);

// What a render uses from the config, resolved and checked.
struct ColorSetup {
    std::string configPath;
    std::string sceneLinear;    // the colour space of the scene_linear role (or the "linear" alias)
    std::string display, view;  // as asked, or the config's defaults
    std::vector<std::string> warnings;
};

// Loads and validates the config, finds scene_linear, the display and view (empty: the config's
// defaults), builds the display transform (so missing LUT files show now), and checks that
// scene_linear is kiln's working space (linear Rec.709, D65) where an interchange role lets it
// tell. Throws std::invalid_argument with one line naming the config and the problem.
ColorSetup checkColorConfig(const std::string& display = "", const std::string& view = "");

}  // namespace kiln
