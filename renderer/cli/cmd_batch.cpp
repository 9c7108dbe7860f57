// kiln batch FILE: every render of a job file on this machine, each a child `kiln render`.
#include <cstdio>
#include <set>

#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/queue_output.h"
#include "renderer/cli/render_command.h"
#include "renderer/core/log.h"
#include "renderer/farm/job_file.h"
#include "renderer/farm/task_runner.h"

namespace kiln {

void checkJobRenders(const std::vector<farm::RenderTask>& tasks, int checkpointSeconds,
                     const std::vector<farm::TaskOrigin>* origins) {
    std::set<std::vector<std::string>> checked;
    for (size_t i = 0; i < tasks.size(); ++i) {
        const farm::RenderTask& t = tasks[i];
        std::vector<std::string> command = farm::renderCommand(t, checkpointSeconds, true);
        command.erase(command.begin());  // "render"
        if (!checked.insert(command).second) continue;
        try {
            checkRenderArguments(command);
        } catch (const UsageError& e) {
            if (!origins || i >= origins->size())
                throw UsageError("the render of " + t.output + ": " + e.what());
            // The entry and field: the first source whose options fail on their own.
            const farm::TaskOrigin& origin = (*origins)[i];
            for (const farm::ArgSource& source : origin.sources) {
                std::vector<std::string> alone{t.scene};
                alone.insert(alone.end(), source.args.begin(), source.args.end());
                try {
                    checkRenderArguments(alone);
                } catch (const UsageError& own) {
                    throw UsageError(source.where + ": " + own.what());
                }
            }
            throw UsageError(origin.label + ": " + e.what());
        }
    }
}

namespace {

// The renders' own messages one level below the batch's (a batch at info shows its task lines and
// the renders' warnings; --log-level debug shows the renders' summaries too), and JSON progress
// passed on, so their stage and progress lines flow through the batch's stderr.
std::vector<std::string> childReportArgs(ProgressOutput progress) {
    LogLevel level = logLevel() == LogLevel::Debug  ? LogLevel::Info
                     : logLevel() == LogLevel::Info ? LogLevel::Warning
                                                    : logLevel();
    std::vector<std::string> args{"--log-level", toString(level)};
    if (progress == ProgressOutput::Json) args.insert(args.end(), {"--progress", "json"});
    return args;
}

// --dry-run: what each render would do, nothing run.
int printDryRun(const std::vector<farm::RenderTask>& tasks, const farm::RunOptions& run,
                bool json) {
    std::vector<std::string> plan = farm::dryRun(tasks, run);
    Json renders = Json::array();
    for (size_t i = 0; i < tasks.size(); ++i) {
        const farm::RenderTask& t = tasks[i];
        renders.push_back(
            {{"scene", t.scene}, {"output", t.output}, {"args", t.args}, {"state", plan[i]}});
        if (!json)
            std::printf("[%zu/%zu] %s -> %s: %s\n", i + 1, tasks.size(), t.scene.c_str(),
                        t.output.c_str(), plan[i].c_str());
    }
    if (json)
        printResult({{"command", "batch"},
                     {"status", exitStatus(0)},
                     {"exit_code", 0},
                     {"dry_run", true},
                     {"renders", renders}});
    return 0;
}

}  // namespace

int runBatch(const std::vector<std::string>& args) {
    farm::RunOptions run;
    bool json = false, quiet = false, dryRun = false;
    ProgressOutput progress = ProgressOutput::Bar;
    ArgParser parser("batch", "FILE.json [options]   (docs/farm.md: the job file)");
    parser.flag("json", "", "print the summary as JSON on stdout", json);
    parser.flag("quiet", "q", "no progress bars from the renders", quiet);
    parser.enumOption("progress",
                      "progress on stderr: the renders' bars, JSON lines (task events, the "
                      "renders' stages and progress, every message), or none (as -q)",
                      progress);
    parser.flag("dry-run", "",
                "expand the job file and check every render's arguments, print what each would "
                "do (render, resume, skip), render nothing",
                dryRun);
    parser.flag("keep-checkpoints", "",
                "keep a finished render's OUT.ckpt (to refine it later with a higher -s)",
                run.keepCheckpoints);
    parser.intOption("checkpoint-every", "", "seconds between checkpoints of a render (default 60)",
                     run.checkpointSeconds, 1, 1 << 24);
    std::vector<std::string> pos = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        return 0;
    }
    if (pos.size() != 1) throw UsageError("needs exactly one job file (see 'kiln batch --help')");
    std::vector<farm::RenderTask> tasks;
    std::vector<farm::TaskOrigin> origins;
    try {
        tasks = farm::readJobFile(pos[0], &origins);
    } catch (const farm::FarmInputError& e) {
        throw UsageError(e.what());
    }
    run.quietChildren = quiet || progress == ProgressOutput::None;
    run.jsonEvents = progress == ProgressOutput::Json;
    run.childArgs = childReportArgs(progress);
    checkJobRenders(tasks, run.checkpointSeconds, &origins);
    if (dryRun) return printDryRun(tasks, run, json);
    std::vector<farm::TaskResult> results = farm::runTasks(tasks, run);
    logInfo("{}", farm::summaryLine(results));
    int code = farm::exitCodeOf(results);
    if (json) {
        Json result = {{"command", "batch"}, {"status", exitStatus(code)}};
        result.update(Json::parse(farm::summaryJson(results)));
        printResult(result);
    }
    return code;
}

}  // namespace kiln
