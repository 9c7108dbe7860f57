// kiln farm: renders split into shards over a Slurm cluster (docs/farm.md). submit writes the job
// directory and submits the array and its merge job; status, merge and resubmit work on it;
// run-shard is what each array task runs.
#include <fmt/format.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/core/log.h"
#include "renderer/farm/child_process.h"
#include "renderer/farm/farm_status.h"
#include "renderer/farm/job_file.h"
#include "renderer/farm/task_runner.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

// "kiln farm: ..." through the log (farm status reads these lines back from the shard logs).
template <class... Args>
void farmNote(fmt::format_string<Args...> format, Args&&... args) {
    logMessage(LogLevel::Info, fmt::format(format, std::forward<Args>(args)...), "farm");
}

constexpr const char* kFarmUsage =
    "usage: kiln farm submit FILE.json|SCENE [render options] --shards N [--by "
    "samples|region|frames] [--frames-per-task K] [-d DIR] [-o OUT] [--partition P] [--time T] "
    "[--mem M]\n"
    "       kiln farm status DIR | merge DIR | resubmit DIR\n";

struct SubmitArgs {
    std::string input, dir, output;
    farm::ShardBy by = farm::ShardBy::Frames;
    int shards = 1, checkpointSeconds = 60, framesPerTask = 0;
    bool keepCheckpoints = false;
    std::vector<std::string> renderArgs, sbatch;
};

// The farm's own options; everything else after FILE|SCENE is passed to kiln render.
ArgParser submitParser(SubmitArgs& a) {
    ArgParser p("farm submit", "FILE.json|SCENE [render options] --shards N [options]");
    p.intOption("shards", "n", "array tasks to split the work into", a.shards, 1, 100000);
    p.enumOption("by", "how to split (default frames)", a.by);
    p.intOption("frames-per-task", "",
                "by frames: K frames to each array task instead of --shards (one scene load "
                "per task)",
                a.framesPerTask, 1, 1 << 20);
    p.option("dir", "d", 1, "DIR", "job directory (default: FILE or SCENE name + .farm)",
             [&a](const auto& v) { a.dir = v[0]; });
    p.option("output", "o", 1, "OUT", "SCENE form: output base (default DIR/SCENE name)",
             [&a](const auto& v) { a.output = v[0]; });
    p.intOption("checkpoint-every", "", "seconds between checkpoints (default 60)",
                a.checkpointSeconds, 1, 1 << 24);
    p.flag("keep-checkpoints", "", "keep OUT.ckpt of finished frames and merged shards",
           a.keepCheckpoints);
    for (const char* name : {"partition", "time", "mem"})
        p.option(name, "", 1, "VALUE", std::string("sbatch --") + name, [&a, name](const auto& v) {
            a.sbatch.push_back(std::string("--") + name + "=" + v[0]);
        });
    return p;
}

SubmitArgs parseSubmit(const std::vector<std::string>& args) {
    SubmitArgs a;
    ArgParser parser = submitParser(a);
    if (args.empty() || args[0].empty() || args[0][0] == '-') {
        if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
            std::fputs(parser.helpText().c_str(), stdout);
            std::exit(0);
        }
        throw UsageError("needs FILE.json or SCENE first\n" + std::string(kFarmUsage));
    }
    a.input = args[0];
    // Pick the farm's options out by name; the rest are render options for every shard.
    const std::vector<std::pair<std::string, int>> own{{"--shards", 1},
                                                       {"-n", 1},
                                                       {"--by", 1},
                                                       {"--frames-per-task", 1},
                                                       {"--dir", 1},
                                                       {"-d", 1},
                                                       {"--output", 1},
                                                       {"-o", 1},
                                                       {"--checkpoint-every", 1},
                                                       {"--keep-checkpoints", 0},
                                                       {"--partition", 1},
                                                       {"--time", 1},
                                                       {"--mem", 1}};
    std::vector<std::string> farmArgs;
    for (size_t i = 1; i < args.size(); ++i) {
        int n = -1;
        for (const auto& [name, count] : own) n = args[i] == name ? count : n;
        if (n < 0) {
            a.renderArgs.push_back(args[i]);
            continue;
        }
        for (int k = 0; k <= n && i + size_t(k) < args.size(); ++k) farmArgs.push_back(args[i + k]);
        i += size_t(n);
    }
    parser.parse(farmArgs);
    if (a.framesPerTask > 0 && (a.by != farm::ShardBy::Frames || a.shards != 1))
        throw UsageError(
            "--frames-per-task splits by frames and sets the task count: not with "
            "--by samples|region or --shards");
    return a;
}

std::vector<farm::RenderTask> submitTasks(const SubmitArgs& a, const std::string& dir) {
    if (fs::path(a.input).extension() == ".json") {
        if (!a.output.empty())
            throw UsageError("-o is for a SCENE; a job file names its outputs in \"output\"");
        if (!a.renderArgs.empty())
            throw UsageError("render options go into the job file's \"args\", not after " +
                             a.input);
        std::vector<farm::TaskOrigin> origins;
        std::vector<farm::RenderTask> tasks = farm::readJobFile(a.input, &origins);
        checkJobRenders(tasks, a.checkpointSeconds, &origins);
        return tasks;
    }
    std::error_code ec;
    if (!fs::is_regular_file(a.input, ec))
        throw UsageError("scene '" + a.input + "' does not exist");
    std::string out =
        a.output.empty() ? (fs::path(dir) / fs::path(a.input).stem()).string() : a.output;
    return {{fs::absolute(a.input).lexically_normal().string(), a.renderArgs,
             fs::absolute(out).lexically_normal().string()}};
}

bool sameWork(const farm::FarmJob& a, const farm::FarmJob& b) {
    if (a.by != b.by || a.shards.size() != b.shards.size()) return false;
    for (size_t i = 0; i < a.shards.size(); ++i) {
        const auto &x = a.shards[i].tasks, &y = b.shards[i].tasks;
        if (x.size() != y.size()) return false;
        for (size_t t = 0; t < x.size(); ++t)
            if (x[t].scene != y[t].scene || x[t].args != y[t].args || x[t].output != y[t].output)
                return false;
    }
    return true;
}

// Every shard's render options through kiln render's own checks, before anything is submitted:
// a typo, a value out of range, or a combination a shard makes impossible (-a with a sample range
// that does not start at 0).
void checkRenderOptions(const farm::FarmJob& job) {
    std::vector<farm::RenderTask> all;
    for (const farm::Shard& s : job.shards) all.insert(all.end(), s.tasks.begin(), s.tasks.end());
    checkJobRenders(all, job.checkpointSeconds);
}

std::vector<int> allShards(const farm::FarmJob& job) {
    std::vector<int> shards;
    for (size_t i = 0; i < job.shards.size(); ++i) shards.push_back(int(i));
    return shards;
}

int submitCommand(const std::vector<std::string>& args) {
    SubmitArgs a = parseSubmit(args);
    std::string dir = a.dir.empty() ? fs::path(a.input).stem().string() + ".farm" : a.dir;
    farm::FarmJob job =
        farm::planFarmJob(submitTasks(a, dir), a.by, a.shards, dir, a.framesPerTask);
    job.kiln = farm::kilnExecutable();
    job.checkpointSeconds = a.checkpointSeconds;
    job.keepCheckpoints = a.keepCheckpoints;
    job.sbatchOptions = a.sbatch;
    if (fs::exists(farm::manifestPath(job.dir)) &&
        !farm::readManifest(job.dir).submissions.empty()) {
        farm::FarmJob existing = farm::readManifest(job.dir);
        if (!sameWork(existing, job))
            throw UsageError(job.dir + " already holds a different farm job; choose another -d");
        std::fprintf(stderr, "kiln farm: %s already holds this job: nothing submitted\n%s",
                     job.dir.c_str(),
                     farm::statusText(existing, farm::farmStatus(existing)).c_str());
        return 0;
    }
    checkRenderOptions(job);
    fs::create_directories(fs::path(job.dir) / "shards");
    for (const farm::Shard& s : job.shards)
        for (const farm::RenderTask& t : s.tasks)
            fs::create_directories(fs::path(t.output).parent_path());
    for (const farm::Merge& m : job.merges)
        fs::create_directories(fs::path(m.output).parent_path());
    farm::Submission s;
    try {
        s = farm::submitShards(job, allShards(job));
    } catch (const std::runtime_error&) {
        // Nothing was submitted: leave no manifest that would make a retry a no-op.
        if (job.submissions.empty()) fs::remove(farm::manifestPath(job.dir));
        throw;
    }
    std::printf("%ld\n", s.arrayJob);
    farmNote("{}: array job {} with {} shards by {}{}; kiln farm status {}", job.dir, s.arrayJob,
             job.shards.size(), farm::shardByName(job.by),
             s.mergeJob ? ", merge job " + std::to_string(s.mergeJob) : "", job.dir);
    return 0;
}

std::string dirArgument(const std::vector<std::string>& args, const char* what) {
    if (args.size() != 2) throw UsageError(std::string("usage: kiln farm ") + what + " DIR");
    return args[1];
}

int statusCommand(const std::vector<std::string>& args) {
    farm::FarmJob job = farm::readManifest(dirArgument(args, "status"));
    farm::FarmStatus status = farm::farmStatus(job);
    std::fputs(farm::statusText(job, status).c_str(), stdout);
    return status.count(farm::ShardState::Failed) ? 1 : 0;
}

int runShardCommand(const std::vector<std::string>& args) {
    if (args.size() != 3) throw UsageError("usage: kiln farm run-shard DIR INDEX");
    farm::FarmJob job = farm::readManifest(args[1]);
    int shard = ArgParser::toInt("run-shard INDEX", args[2], 0, int(job.shards.size()) - 1);
    const char* restarts = std::getenv("SLURM_RESTART_COUNT");
    farmNote("shard {} of {}, run {}", shard, job.dir, restarts ? std::atoi(restarts) + 1 : 1);
    // Sample and region shards keep theirs: they are what kiln merge reads.
    farm::RunOptions run{job.checkpointSeconds, true, stderr,
                         job.keepCheckpoints || job.by != farm::ShardBy::Frames};
    int code = farm::exitCodeOf(farm::runTasks(job.shards[size_t(shard)].tasks, run));
    if (code == 130 && farm::lastForwardedSignal() == SIGTERM)
        farmNote("shard {}: {}", shard, farm::requeueSelfBeforeTimeLimit());
    return code;
}

int mergeCommand(const std::vector<std::string>& args) {
    farm::FarmJob job = farm::readManifest(dirArgument(args, "merge"));
    for (size_t i = 0; i < job.shards.size(); ++i)
        if (!farm::shardComplete(job, int(i)))
            throw std::runtime_error(job.dir + ": shard " + std::to_string(i) +
                                     " is not done (kiln farm status " + job.dir + ")");
    int failed = 0;
    for (const farm::Merge& m : job.merges) {
        if (farm::mergeComplete(m)) continue;
        std::vector<std::string> cmd = farm::mergeCommand(m);
        int code = farm::runForwardingSignals(farm::kilnExecutable(), cmd);
        if (code == 0) farm::markComplete(m.output, cmd);
        if (code == 0 && !job.keepCheckpoints)
            for (const std::string& in : m.inputs) fs::remove(in + ".ckpt");
        farmNote("merge {}: {}", m.output,
                 code == 0 ? "done" : "failed, exit " + std::to_string(code));
        failed += code != 0;
    }
    return failed ? 1 : 0;
}

int resubmitCommand(const std::vector<std::string>& args) {
    farm::FarmJob job = farm::readManifest(dirArgument(args, "resubmit"));
    std::vector<int> failed;
    for (const farm::ShardStatus& s : farm::farmStatus(job).shards)
        if (s.state == farm::ShardState::Failed) failed.push_back(s.shard);
    if (failed.empty()) {
        farmNote("{}: no failed shard, nothing resubmitted", job.dir);
        return 0;
    }
    if (!job.submissions.empty() && job.submissions.back().mergeJob)
        farm::cancelIfPending(job.submissions.back().mergeJob);
    farm::Submission s = farm::submitShards(job, failed);
    std::printf("%ld\n", s.arrayJob);
    farmNote("{}: {} failed shards resubmitted as array job {}", job.dir, failed.size(),
             s.arrayJob);
    return 0;
}

}  // namespace

int runFarm(const std::vector<std::string>& args) {
    if (args.empty() || args[0] == "--help" || args[0] == "-h") {
        std::fputs(kFarmUsage, args.empty() ? stderr : stdout);
        return args.empty() ? 2 : 0;
    }
    std::vector<std::string> rest(args.begin() + 1, args.end());
    try {
        if (args[0] == "submit") return submitCommand(rest);
        if (args[0] == "status") return statusCommand(args);
        if (args[0] == "merge") return mergeCommand(args);
        if (args[0] == "resubmit") return resubmitCommand(args);
        if (args[0] == "run-shard") return runShardCommand(args);
    } catch (const farm::FarmInputError& e) {
        throw UsageError(e.what());
    }
    throw UsageError("unknown farm command '" + args[0] + "'\n" + kFarmUsage);
}

}  // namespace kiln
