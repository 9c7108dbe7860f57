// kiln bench accuracy: what accuracy costs in time on one scene.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/validation/accuracy.h"

namespace kiln {

namespace fs = std::filesystem;

int runAccuracyCommand(const std::vector<std::string>& args) {
    ArgParser parser("bench accuracy",
                     "SCENE [--budget SECONDS] [--out DIR] [-r W H] [--max-spp N] [--ref-spp N]");
    AccuracyOptions o;
    int budget = 300;
    parser.option("out", "o", 1, "DIR", "output folder (default accuracy/)",
                  [&](const std::vector<std::string>& v) { o.outDir = v[0]; });
    parser.intOption("budget", "", "seconds for the sweep, references excluded (default 300)",
                     budget, 1, 1 << 24);
    parser.intOption("max-spp", "", "largest spp of the sweeps (default 1024)", o.maxSpp, 1,
                     1 << 16);
    parser.intOption("ref-spp", "", "reference spp (default 4096)", o.referenceSpp, 1, 1 << 24);
    parser.option("resolution", "r", 2, "W H", "image size (default 128 96)",
                  [&](const std::vector<std::string>& v) {
                      o.width = ArgParser::toInt("-r", v[0], 1, 8192);
                      o.height = ArgParser::toInt("-r", v[1], 1, 8192);
                  });
    parser.flag("quick", "", "a handful of settings (smoke test)", o.quick);
    parser.option("env", "e", 1, "MAP.exr", "add a lat-long environment light, as kiln render's",
                  [&](const std::vector<std::string>& v) { o.environmentMap = v[0]; });
    parser.flag("denoise", "",
                "only the spp sweep, raw and denoised (NFOR, render + denoise time; "
                "docs/denoise.md)",
                o.denoise);
    parser.option("aov", "", 1, "LIST",
                  "also measure the error of these colour AOV layers (e.g. direct,indirect)",
                  [&](const std::vector<std::string>& v) { o.aovs = v[0]; });
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.size() != 1) throw UsageError("needs exactly one scene file");
    o.scene = pos[0];
    o.budgetSeconds = budget;
    try {
        AovRequest::parse(o.aovs, 1);
    } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--aov: ") + e.what());
    }
    AccuracyResult r = runAccuracy(o);
    std::ifstream summary(fs::path(o.outDir) / "summary.md");
    std::fputs(std::string(std::istreambuf_iterator<char>(summary), {}).c_str(), stdout);
    return r.runs.empty() ? 1 : 0;
}

}  // namespace kiln
