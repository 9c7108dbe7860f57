// Runs render tasks one after another as child `kiln render` processes on this machine: skips
// complete outputs, resumes checkpointed ones, reports progress per task and overall. Shared by
// `kiln batch` and the farm's shard tasks.
#pragma once

#include <string>
#include <vector>

#include "renderer/farm/render_task.h"

namespace kiln::farm {

enum class Outcome { Skipped, Rendered, Resumed, Failed, Interrupted, NotRun };
const char* outcomeName(Outcome o);

struct TaskResult {
    RenderTask task;
    Outcome outcome = Outcome::NotRun;
    int exitCode = 0;
    double seconds = 0;
};

struct RunOptions {
    int checkpointSeconds = 60;
    bool quietChildren = false;  // no per-pixel progress bar from the renders
    // Per-task reports on stderr: a line through the log (info, so --log-level warning silences
    // it: "kiln: [3/8] out: rendered (exit 0) in 2.10s, batch ETA 10.5s"), or with jsonEvents a
    // {"event": "task", ...} line (docs/output.md).
    bool report = true;
    // A finished render's OUT.ckpt (the film's exact sums, 0.7 GB at 1080p) is removed unless kept
    // (for refinement with a higher -s, or as a shard for kiln merge); not kept, the renders are
    // given --no-final-checkpoint (none written at their end only to be removed).
    bool keepCheckpoints = false;
    bool jsonEvents = false;
    // Appended to each render's command line, but not to what its done marker records: how it
    // reports (--log-level, --progress json), which does not change the image.
    std::vector<std::string> childArgs;
};

// Stops at the first interrupted task (exit 130, exit 3 from a render's own --time-limit, or a
// forwarded signal): the rest stay NotRun.
std::vector<TaskResult> runTasks(const std::vector<RenderTask>& tasks, const RunOptions& options);

// What runTasks would do with each task, running none: "render", "resume" (from its checkpoint)
// or "skip" (complete).
std::vector<std::string> dryRun(const std::vector<RenderTask>& tasks, const RunOptions& options);

// 0 when every task is complete, 130 when one was interrupted, 1 when one failed.
int exitCodeOf(const std::vector<TaskResult>& results);

// One line per outcome count ("3 renders: 2 rendered, 1 skipped, 4.20s rendering"), and the JSON
// form of the whole run for --json.
std::string summaryLine(const std::vector<TaskResult>& results);
std::string summaryJson(const std::vector<TaskResult>& results);

}  // namespace kiln::farm
