// kiln batch FILE: every render of a job file on this machine, each a child `kiln render`.
#include <cstdio>

#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/farm/job_file.h"
#include "renderer/farm/task_runner.h"

namespace kiln {

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
    try {
        tasks = farm::readJobFile(pos[0]);
    } catch (const farm::FarmInputError& e) {
        throw UsageError(e.what());
    }
    run.quietChildren = quiet;
    std::vector<farm::TaskResult> results = farm::runTasks(tasks, run);
    std::fprintf(stderr, "%s\n", farm::summaryLine(results).c_str());
    if (json) std::printf("%s\n", farm::summaryJson(results).c_str());
    return farm::exitCodeOf(results);
}

}  // namespace kiln
