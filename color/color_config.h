// The OCIO config kiln follows: $OCIO when set, else the one a front end ships beside itself (the
// installed Python module's package), else the one installed beside the binary
// (PREFIX/share/kiln/config.ocio for PREFIX/bin/kiln), else the source tree's (build directory).
// Everything kiln needs from it is checked before a render starts.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace kiln {

std::string colorConfigPath();

// The config shipped beside a front end that is not the kiln binary (the Python module: its
// package's config.ocio when installed); taken when the file exists. Empty: none.
void setBundledColorConfig(const std::string& path);

// What a render uses from the config, resolved and checked.
struct ColorSetup {
    std::string configPath;
    std::string configStamp;    // the read of the config checked (ocioConfigStamp)
    std::string sceneLinear;    // the colour space of the scene_linear role (or the "linear" alias)
    std::string display, view;  // as asked, or the config's defaults
    std::string look;           // as asked (empty: none)
    std::vector<std::string> warnings;
};

// Loads and validates the config, finds scene_linear, the display and view (empty: the config's
// defaults), builds the display transform (so missing LUT files show now), and warns when no
// interchange role tells scene_linear's primaries (working_space.h). Throws std::invalid_argument
// with one line naming the config and the problem.
// A look (--look) must be one the config defines.
ColorSetup checkColorConfig(const std::string& display = "", const std::string& view = "",
                            const std::string& look = "");

// The names a user may pass as --display, --view and --look, from the config kiln follows (for
// 'kiln info --ocio' and the shell completion). Throws std::invalid_argument as above.
struct ColorConfigNames {
    std::string configPath, sceneLinear;
    std::vector<std::pair<std::string, std::vector<std::string>>> displays;  // with their views
    std::vector<std::string> looks;
};
ColorConfigNames listColorConfig();

}  // namespace kiln
