// kiln batch FILE: every render of a job file on this machine, each a child `kiln render`.
#include <cstdio>
#include <set>

#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
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

int runBatch(const std::vector<std::string>& args) {
    farm::RunOptions run;
    bool json = false, quiet = false;
    ArgParser parser("batch", "FILE.json [options]   (docs/farm.md: the job file)");
    parser.flag("json", "", "print the summary as JSON on stdout", json);
    parser.flag("quiet", "q", "no progress bars from the renders", quiet);
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
    run.quietChildren = quiet;
    checkJobRenders(tasks, run.checkpointSeconds, &origins);
    std::vector<farm::TaskResult> results = farm::runTasks(tasks, run);
    std::fprintf(stderr, "%s\n", farm::summaryLine(results).c_str());
    if (json) std::printf("%s\n", farm::summaryJson(results).c_str());
    return farm::exitCodeOf(results);
}

}  // namespace kiln
