// The kiln subcommands; each returns the process exit code (0 ok, 1 failure found, 2 bad
// input/usage).
#pragma once

#include <string>
#include <vector>

namespace kiln {

int runRender(const std::vector<std::string>& args);
// kiln render-frames: render command lines joined by --then, one scene load for frames that differ
// only in camera (what kiln batch and farm shards run).
int runRenderFrames(const std::vector<std::string>& args);
int runMerge(const std::vector<std::string>& args);  // kiln merge SHARD.ckpt... -o OUT
int runInfo(const std::vector<std::string>& args);
int runCrosscheck(const std::vector<std::string>& args);
int runBench(const std::vector<std::string>& args);
int runBatch(const std::vector<std::string>& args);            // kiln batch FILE
int runFarm(const std::vector<std::string>& args);             // kiln farm submit|status|...
int runTools(const std::vector<std::string>& args);            // kiln tools subdivide
int runAccuracyCommand(const std::vector<std::string>& args);  // kiln bench accuracy
int runReport(const std::vector<std::string>& args);           // kiln report cs184
int runDenoise(const std::vector<std::string>& args);          // kiln denoise IN.exr -o OUT

// kiln render's checks of a command line (SCENE and options, without "render") that need no scene
// and no output: the parser, option ranges and combinations, the camera override, the colour
// config's display and view. Throws UsageError.
struct CheckedRender {
    bool outputGiven = false;        // -o or -f
    std::vector<std::string> files;  // the images it writes: EXR, preview, the heat map if any
};
CheckedRender checkRenderArguments(const std::vector<std::string>& args);

}  // namespace kiln

namespace kiln::farm {
struct RenderTask;
struct TaskOrigin;
}  // namespace kiln::farm

namespace kiln {

// Every render of a job file through checkRenderArguments, as the child `kiln render` will get it,
// before the first one starts (kiln batch, kiln farm submit). With origins (one per task, from
// readJobFile) the error names the job file, the entry and the field ("job.json: cameras[0]:
// 'up': --up takes finite coordinates ..."), or the render when only the combination fails;
// without, the render's output. Throws UsageError.
void checkJobRenders(const std::vector<farm::RenderTask>& tasks, int checkpointSeconds,
                     const std::vector<farm::TaskOrigin>* origins = nullptr);

}  // namespace kiln
