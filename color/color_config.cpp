#include "color/color_config.h"

#include <OpenColorIO/OpenColorIO.h>
#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "color/ocio_configs.h"

namespace kiln {
namespace OCIO = OCIO_NAMESPACE;
namespace fs = std::filesystem;

namespace {

std::string joinedNames(int n, auto nameOf) {
    std::string text;
    for (int i = 0; i < n; ++i) text += (i ? ", " : "") + std::string(nameOf(i));
    return text;
}

std::string resolveSceneLinear(const OCIO::ConstConfigRcPtr& config) {
    for (const char* name : {"scene_linear", "linear"})
        if (OCIO::ConstColorSpaceRcPtr cs = config->getColorSpace(name)) return cs->getName();
    return "";
}

void resolveDisplayView(const OCIO::ConstConfigRcPtr& config, ColorSetup& setup) {
    const std::string& path = setup.configPath;
    if (setup.display.empty()) setup.display = config->getDefaultDisplay();
    int nd = config->getNumDisplays();
    auto displayName = [&](int i) { return config->getDisplay(i); };
    bool found = false;
    for (int d = 0; d < nd; ++d) found |= setup.display == config->getDisplay(d);
    if (!found)
        throw std::invalid_argument(fmt::format("{}: unknown display '{}' (known: {})", path,
                                                setup.display, joinedNames(nd, displayName)));
    const char* display = setup.display.c_str();
    if (setup.view.empty()) setup.view = config->getDefaultView(display);
    int nv = config->getNumViews(display);
    auto viewName = [&](int i) { return config->getView(display, i); };
    found = false;
    for (int v = 0; v < nv; ++v) found |= setup.view == config->getView(display, v);
    if (!found)
        throw std::invalid_argument(fmt::format("{}: display '{}' has no view '{}' (known: {})",
                                                path, setup.display, setup.view,
                                                joinedNames(nv, viewName)));
}

void checkLook(const OCIO::ConstConfigRcPtr& config, const ColorSetup& setup) {
    if (setup.look.empty() || config->getLook(setup.look.c_str())) return;
    int n = config->getNumLooks();
    auto lookName = [&](int i) { return config->getLookNameByIndex(i); };
    throw std::invalid_argument(fmt::format("{}: unknown look '{}' (known: {})", setup.configPath,
                                            setup.look, n ? joinedNames(n, lookName) : "none"));
}

// kiln renders in whatever scene_linear is (working_space.h, through the same roles); without an
// interchange role it cannot tell its primaries and takes them as Rec.709's.
void checkWorkingSpace(const OCIO::ConstConfigRcPtr& config, ColorSetup& setup) {
    if (!config->getColorSpace("aces_interchange") &&
        !config->getColorSpace("cie_xyz_d65_interchange"))
        setup.warnings.push_back(fmt::format(
            "{}: no aces_interchange or cie_xyz_d65_interchange role: scene_linear '{}' is "
            "taken as linear Rec.709 (colours given in files are not converted)",
            setup.configPath, setup.sceneLinear));
}

// OCIO's message on one line, naming the config.
std::invalid_argument unusable(const std::string& path, const OCIO::Exception& e) {
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    return std::invalid_argument(path + ": OCIO config unusable: " + what);
}

std::string& bundledConfig() {
    static std::string path;
    return path;
}

}  // namespace

void setBundledColorConfig(const std::string& path) { bundledConfig() = path; }

namespace {

// Where a config beside the binary would be (PREFIX/share/kiln/config.ocio for PREFIX/bin/kiln).
fs::path installedConfig(const fs::path& exe) {
    return (exe.parent_path() / KILN_CONFIG_FROM_BINARY).lexically_normal();
}

fs::path runningBinary() {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : exe;
}

// Without $OCIO or a config beside the binary: the source tree's, which a binary run from its
// build directory uses; a binary moved elsewhere is told where kiln looked (a warning when the
// source tree is still there, an error when it is gone).
void checkFallback(ColorSetup& setup) {
    std::error_code ec;
    if (std::getenv("OCIO") && *std::getenv("OCIO")) return;
    fs::path exe = runningBinary();
    if (exe.empty() || setup.configPath == installedConfig(exe).string()) return;
    if (setup.configPath == bundledConfig()) return;
    std::string looked = fmt::format("$OCIO is unset and there is no {} beside {}",
                                     installedConfig(exe).string(), exe.string());
    if (!fs::exists(setup.configPath, ec))
        throw std::invalid_argument(fmt::format(
            "no OCIO config: {}, nor {} (set OCIO, or install kiln with cmake --install)", looked,
            setup.configPath));
    // The build tree's binary or another host (the Python module) uses the source tree's config
    // as a matter of course.
    const bool moved = exe.parent_path() != fs::path(KILN_BUILD_BINARY_DIR);
    if (moved && exe.filename() == "kiln")
        setup.warnings.push_back(
            fmt::format("{}: using the source tree's {}", looked, setup.configPath));
}

}  // namespace

std::string colorConfigPath() {
    if (const char* env = std::getenv("OCIO"); env && *env) return env;
    std::error_code ec;
    if (!bundledConfig().empty() && fs::exists(bundledConfig(), ec)) return bundledConfig();
    fs::path exe = runningBinary();
    if (!exe.empty() && fs::exists(installedConfig(exe), ec)) return installedConfig(exe).string();
    return std::string(KILN_SOURCE_DIR) + "/color/config.ocio";
}

namespace {

// A variable's value, or none when unset (a config's declared default applies then).
std::optional<std::string> environmentValue(const char* name) {
    const char* value = std::getenv(name);
    return value ? std::optional<std::string>(value) : std::nullopt;
}

// The file's identity (inode, size, modification time) and the variables OCIO reads beside it
// when it builds a config.
std::string fileStamp(const std::string& path) {
    struct stat st {};
    std::string stamp;
    if (::stat(path.c_str(), &st) == 0)
        stamp = fmt::format("{} {} {} {}", st.st_ino, st.st_size, st.st_mtim.tv_sec,
                            st.st_mtim.tv_nsec);
    for (const char* name :
         {"OCIO_ACTIVE_DISPLAYS", "OCIO_ACTIVE_VIEWS", "OCIO_INACTIVE_COLORSPACES"})
        stamp += fmt::format("\n{}", environmentValue(name).value_or("(unset)"));
    return stamp;
}

// The environment's values of the context variables the config captured when read ($SHOT in a
// LUT's path; every variable of the environment for a config that declares none).
using ContextValues = std::vector<std::pair<std::string, std::optional<std::string>>>;
ContextValues contextValues(const OCIO::ConstConfigRcPtr& config) {
    OCIO::ConstContextRcPtr context = config->getCurrentContext();
    ContextValues values;
    for (int i = 0; i < context->getNumStringVars(); ++i) {
        const char* name = context->getStringVarNameByIndex(i);
        values.emplace_back(name, environmentValue(name));
    }
    return values;
}

bool contextUnchanged(const ContextValues& values) {
    for (const auto& [name, value] : values)
        if (environmentValue(name.c_str()) != value) return false;
    return true;
}

struct ReadConfig {
    std::string stamp;
    OCIO::ConstConfigRcPtr config;
    ContextValues context;
    uint64_t generation = 0;
};

// The config at path as last read (one per path: a config read again replaces it), and its
// generation, which changes with every read.
ReadConfig currentConfig(const std::string& path) {
    static std::mutex mutex;
    static std::map<std::string, ReadConfig> read;
    static uint64_t generations = 0;
    const std::string stamp = fileStamp(path);
    std::lock_guard lock(mutex);
    auto it = read.find(path);
    if (it == read.end() || it->second.stamp != stamp || !contextUnchanged(it->second.context)) {
        OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(path.c_str());
        ContextValues context = contextValues(config);
        it = read.insert_or_assign(path,
                                   ReadConfig{stamp, config, std::move(context), ++generations})
                 .first;
    }
    return it->second;
}

}  // namespace

OCIO::ConstConfigRcPtr sharedOcioConfig(const std::string& path) {
    return currentConfig(path).config;
}

std::string ocioConfigStamp(const std::string& path) {
    try {
        return fmt::format("{}\n{}", path, currentConfig(path).generation);
    } catch (const OCIO::Exception&) {
        return fmt::format("{}\nunreadable", path);  // checkColorConfig says why
    }
}

namespace {

ColorSetup checkedColorSetup(const std::string& configPath, const std::string& stamp,
                             const std::string& display, const std::string& view,
                             const std::string& look) {
    ColorSetup setup{configPath, stamp, "", display, view, look, {}};
    checkFallback(setup);
    try {
        OCIO::ConstConfigRcPtr config = sharedOcioConfig(setup.configPath);
        setup.sceneLinear = resolveSceneLinear(config);
        if (setup.sceneLinear.empty())
            throw std::invalid_argument(
                setup.configPath +
                ": OCIO config has no scene_linear role (nor a 'linear' "
                "colour space or alias): kiln cannot name its working space");
        resolveDisplayView(config, setup);
        checkLook(config, setup);
        config
            ->getProcessor(setup.sceneLinear.c_str(), setup.display.c_str(), setup.view.c_str(),
                           OCIO::TRANSFORM_DIR_FORWARD)
            ->getDefaultCPUProcessor();
        checkWorkingSpace(config, setup);
        // Last: what kiln uses has been tried above, with the more precise messages.
        config->validate();
    } catch (const OCIO::Exception& e) {
        throw unusable(setup.configPath, e);
    }
    return setup;
}

}  // namespace

// Checked once per config and display, view and look in a process (a frame of a batch checks
// what the one before did); a failed check is not kept, so it fails again with its message.
ColorSetup checkColorConfig(const std::string& display, const std::string& view,
                            const std::string& look) {
    static MadeFromConfig<ColorSetup> checked;
    const std::string path = colorConfigPath(), stamp = ocioConfigStamp(path);
    return checked.get(stamp, display, view, look,
                       [&] { return checkedColorSetup(path, stamp, display, view, look); });
}

ColorConfigNames listColorConfig() {
    ColorConfigNames names{colorConfigPath(), "", {}, {}};
    try {
        OCIO::ConstConfigRcPtr config = sharedOcioConfig(names.configPath);
        names.sceneLinear = resolveSceneLinear(config);
        for (int d = 0; d < config->getNumDisplays(); ++d) {
            const char* display = config->getDisplay(d);
            std::vector<std::string> views;
            for (int v = 0; v < config->getNumViews(display); ++v)
                views.emplace_back(config->getView(display, v));
            names.displays.emplace_back(display, std::move(views));
        }
        for (int i = 0; i < config->getNumLooks(); ++i)
            names.looks.emplace_back(config->getLookNameByIndex(i));
    } catch (const OCIO::Exception& e) {
        throw unusable(names.configPath, e);
    }
    return names;
}

}  // namespace kiln
