#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "color/color_config.h"
#include "integrators/render_plan.h"
#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/render_options.h"
#include "scene/scene_info.h"
#include "scene/scene_loader.h"

namespace kiln {

namespace {

// One tab-separated line per name (names may hold spaces: "ACES 1.0 - SDR Video"), for scripts
// and the shell completion: config, scene_linear, display, view (its display first), look.
void printColorConfigNames() {
    ColorConfigNames names;
    try {
        names = listColorConfig();
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());  // a bad config is bad input: exit 2
    }
    std::printf("config\t%s\nscene_linear\t%s\n", names.configPath.c_str(),
                names.sceneLinear.c_str());
    for (const auto& [display, views] : names.displays) {
        std::printf("display\t%s\n", display.c_str());
        for (const std::string& view : views)
            std::printf("view\t%s\t%s\n", display.c_str(), view.c_str());
    }
    for (const std::string& look : names.looks) std::printf("look\t%s\n", look.c_str());
}

}  // namespace

int runInfo(const std::vector<std::string>& args) {
    ArgParser parser("info", "SCENE [--json] | --ocio");
    bool json = false, ocio = false;
    LoadOptions load;
    parser.flag("json", "", "print the stable JSON form (keys in docs/info-json.md)", json);
    parser.flag("ocio", "",
                "list the OCIO config's displays, views and looks (tab-separated; no scene)", ocio);
    addLoadOptions(parser, load);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (ocio) {
        if (!pos.empty()) throw UsageError("--ocio takes no scene (see 'kiln info --help')");
        printColorConfigNames();
        return 0;
    }
    if (pos.size() != 1) throw UsageError("needs exactly one scene file (see 'kiln info --help')");
    Scene scene = loadScene(pos[0], load);
    if (json) {
        std::fputs(sceneInfoJson(scene).c_str(), stdout);
        return 0;
    }
    std::fputs(sceneInfoText(scene).c_str(), stdout);
    auto accel = makeEmbreeAccelerator(scene);
    uint64_t tris = std::max<uint64_t>(1, scene.uniqueTriangles());
    std::printf(
        "embree      %llu bytes of BVH (%.1f bytes/triangle), built in %.3f s; scene model + BVH: "
        "%.1f bytes/triangle\n",
        (unsigned long long)accel->stats().memoryBytes,
        double(accel->stats().memoryBytes) / double(tris), accel->stats().buildSeconds,
        double(accel->stats().memoryBytes + summarize(scene).geometryBytes) / double(tris));
    RenderPlan plan = planFor(scene, *accel, AovRequest::defaults());
    std::printf("render plan (%s)\n%s", plan.compact().c_str(), plan.text().c_str());
    return 0;
}

}  // namespace kiln
