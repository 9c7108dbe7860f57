// kiln: a batch path tracer. This file only dispatches subcommands and turns errors into exit
// codes.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "renderer/build_info.h"
#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/core/log.h"
#include "scene/scene_error.h"

namespace {

constexpr const char* kUsage =
    "usage: kiln <command> [options]\n"
    "\n"
    "commands:\n"
    "  render SCENE      render a scene to EXR + PNG\n"
    "  render-frames SCENE ... --then SCENE ...   several renders from one scene load\n"
    "  merge SHARD...    combine render shards (--sample-range, --crop) into EXR + PNG\n"
    "  info SCENE        describe a scene (--json for the machine-readable form)\n"
    "  crosscheck SCENE  trace the same rays through Embree and the reference BVH and compare\n"
    "  bench accel       build time and rays/s of both accelerators\n"
    "  bench plan        render time of the plan's specialised path against the general one\n"
    "  bench accuracy    error against time over spp, strategies, depth, adaptive sampling\n"
    "  batch FILE        every render of a job file on this machine (skips done, resumes)\n"
    "  farm submit|status|merge|resubmit   renders split over a Slurm cluster\n"
    "  tools subdivide   1-to-4 midpoint subdivision of a mesh, written as binary PLY\n"
    "  report cs184      the CS184 PathTracer write-up (five parts) as one HTML page\n"
    "\n"
    "'kiln <command> --help' lists each command's options.\n";

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty() || args[0] == "-h" || args[0] == "--help") {
        std::fputs(kUsage, args.empty() ? stderr : stdout);
        return args.empty() ? 2 : 0;
    }
    if (args[0] == "--version") {
        std::fputs(kiln::versionText().c_str(), stdout);
        return 0;
    }
    std::string command = args[0];
    args.erase(args.begin());
    try {
        if (command == "render") return kiln::runRender(args);
        if (command == "render-frames") return kiln::runRenderFrames(args);
        if (command == "merge") return kiln::runMerge(args);
        if (command == "info") return kiln::runInfo(args);
        if (command == "crosscheck") return kiln::runCrosscheck(args);
        if (command == "bench") return kiln::runBench(args);
        if (command == "batch") return kiln::runBatch(args);
        if (command == "farm") return kiln::runFarm(args);
        if (command == "tools") return kiln::runTools(args);
        if (command == "report") return kiln::runReport(args);
        kiln::logError("unknown command '{}'", command);
        std::fputs(kUsage, stderr);
        return 2;
    } catch (const kiln::UsageError& e) {
        kiln::logMessage(kiln::LogLevel::Error, e.what(), command);  // "kiln render: ..."
        return 2;
    } catch (const kiln::SceneError& e) {
        kiln::logError("{}", e.what());
        return 2;
    } catch (const std::exception& e) {
        kiln::logError("{}", e.what());
        return 1;
    }
}
