#include "renderer/farm/task_runner.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "renderer/core/json.h"
#include "renderer/core/log.h"
#include "renderer/farm/child_process.h"

namespace kiln::farm {
namespace {

namespace fs = std::filesystem;

constexpr Outcome kOutcomes[] = {Outcome::Rendered, Outcome::Resumed,     Outcome::Skipped,
                                 Outcome::Failed,   Outcome::Interrupted, Outcome::NotRun};

std::vector<std::string> commandOf(const RenderTask& task, const RunOptions& options) {
    return renderCommand(task, options.checkpointSeconds, options.quietChildren);
}

bool taskComplete(const RenderTask& task, const RunOptions& options) {
    return isComplete(task.output, commandOf(task, options));
}

// What a child's command adds to the task's: the report options, and --no-final-checkpoint where
// the batch removes a finished frame's checkpoint anyway (0.7 GB at 1080p, written then removed).
// The done marker leaves them out: they do not change the image (the flag is left out by
// joinLines itself, so only the report options make the batch rewrite a child's marker).
std::vector<std::string> childOnlyArgs(const RunOptions& options) {
    std::vector<std::string> args = options.childArgs;
    if (!options.keepCheckpoints) args.push_back("--no-final-checkpoint");
    return args;
}

// The command as a child runs it.
std::vector<std::string> withChildArgs(std::vector<std::string> command,
                                       const RunOptions& options) {
    const std::vector<std::string> extra = childOnlyArgs(options);
    command.insert(command.end(), extra.begin(), extra.end());
    return command;
}

// What the batch reports about task i: its state ("rendering", "resuming", or an outcome), and
// when known the exit code, the seconds and the batch's estimated seconds left.
struct TaskReport {
    size_t index, total;
    const TaskResult& result;
    std::string state;
    double etaSeconds = -1;  // < 0: not known yet
};

void report(const RunOptions& options, const TaskReport& r) {
    if (!options.report) return;
    const RenderTask& task = r.result.task;
    const bool ended = r.state != "rendering" && r.state != "resuming";
    if (options.jsonEvents) {
        Json line = {{"event", "task"},
                     {"index", r.index + 1},
                     {"total", r.total},
                     {"scene", task.scene},
                     {"output", task.output},
                     {"state", r.state},
                     {"exit_code", r.result.exitCode},
                     {"seconds", r.result.seconds}};
        if (r.etaSeconds >= 0) line["eta_seconds"] = r.etaSeconds;
        logLine(jsonText(line, -1));
        return;
    }
    std::string eta = r.etaSeconds >= 0 ? fmt::format(", batch ETA {:.1f}s", r.etaSeconds) : "";
    if (r.state == "skipped")
        logInfo("[{}/{}] {}: complete, skipped", r.index + 1, r.total, task.output);
    else if (!ended)
        logInfo("[{}/{}] {} -> {}: {}", r.index + 1, r.total, task.scene, task.output,
                r.state == "resuming" ? "resuming from its checkpoint" : "rendering");
    else
        logInfo("[{}/{}] {}: {} (exit {}) in {:.2f}s{}", r.index + 1, r.total, task.output, r.state,
                r.result.exitCode, r.result.seconds, eta);
}

// The batch's time so far, to estimate what is left: the mean time of the renders run (skipped
// ones cost nothing) times the renders still to run.
struct BatchClock {
    size_t toRun = 0, ran = 0;
    double seconds = 0;
    double etaSeconds() const {
        return ran ? seconds / double(ran) * double(toRun > ran ? toRun - ran : 0) : -1.0;
    }
};

// Marks r skipped (and says so) when its output is complete.
bool skippedAsComplete(TaskResult& r, const RunOptions& options, size_t i, size_t n,
                       const BatchClock& clock) {
    if (!taskComplete(r.task, options)) return false;
    r.outcome = Outcome::Skipped;
    report(options, {i, n, r, "skipped", clock.etaSeconds()});
    return true;
}

void reportEnd(const TaskResult& r, const RunOptions& options, size_t i, size_t n,
               BatchClock& clock) {
    ++clock.ran, clock.seconds += r.seconds;
    report(options, {i, n, r, outcomeName(r.outcome), clock.etaSeconds()});
}

TaskResult runOne(const RenderTask& task, const RunOptions& options, size_t i, size_t n,
                  BatchClock& clock) {
    TaskResult r{task};
    std::vector<std::string> command = commandOf(task, options);
    if (skippedAsComplete(r, options, i, n, clock)) return r;
    bool resuming = hasCheckpoint(task.output);
    report(options, {i, n, r, resuming ? "resuming" : "rendering", clock.etaSeconds()});
    fs::create_directories(fs::path(task.output).parent_path());
    auto t0 = std::chrono::steady_clock::now();
    r.exitCode = runForwardingSignals(kilnExecutable(), withChildArgs(command, options));
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.exitCode == 0) {
        markComplete(task.output, command);
        if (!options.keepCheckpoints) fs::remove(task.output + ".ckpt");
    }
    // 130: interrupted, 3: its --time-limit reached; both saved their checkpoint.
    bool saved = r.exitCode == 130 || r.exitCode == 3;
    r.outcome = r.exitCode == 0 ? (resuming ? Outcome::Resumed : Outcome::Rendered)
                : saved         ? Outcome::Interrupted
                                : Outcome::Failed;
    reportEnd(r, options, i, n, clock);
    return r;
}

// A child's command line stays far below the kernel's limit on arguments (2 MiB with the usual
// 8 MiB stack); a longer run of frames goes on in the next child.
constexpr size_t kFramesCommandBytes = 256 * 1024;

// From `next` on: the run of tasks of one scene to render in one child, the complete ones among
// them marked skipped; `next` moves past them.
std::vector<size_t> nextGroup(std::vector<TaskResult>& results, size_t& next,
                              const RunOptions& options, const BatchClock& clock) {
    std::vector<size_t> group;
    size_t bytes = 0;
    for (; next < results.size(); ++next) {
        const RenderTask& task = results[next].task;
        if (!group.empty() && task.scene != results[group[0]].task.scene) break;
        if (skippedAsComplete(results[next], options, next, results.size(), clock)) continue;
        for (const std::string& a : withChildArgs(commandOf(task, options), options))
            bytes += a.size() + 1;
        if (!group.empty() && bytes > kFramesCommandBytes) break;
        group.push_back(next);
    }
    return group;
}

// `kiln render-frames` with every task's render command (and the report options), joined by
// --then.
std::vector<std::string> framesCommand(const std::vector<TaskResult>& results,
                                       const std::vector<size_t>& group,
                                       const RunOptions& options) {
    std::vector<std::string> command{"render-frames"};
    for (size_t k : group) {
        std::vector<std::string> one = withChildArgs(commandOf(results[k].task, options), options);
        if (command.size() > 1) command.push_back("--then");
        command.insert(command.end(), one.begin() + 1, one.end());  // without "render"
    }
    return command;
}

// The tasks of `group` in one child, which loads their scene once (the frames differ only in
// camera) and writes each frame's done marker as it finishes; it stops at the first render that
// does not exit 0. Each task's time runs from the marker before it. Returns the tasks after a
// failed one, for the next child; none after an interruption.
std::vector<size_t> runFrames(std::vector<TaskResult>& results, const std::vector<size_t>& group,
                              const RunOptions& options, BatchClock& clock) {
    const size_t n = results.size();
    if (options.report && !options.jsonEvents)
        logInfo("[{}/{}] {}: {} renders from one scene load", group[0] + 1, n,
                results[group[0]].task.scene, group.size());
    std::vector<bool> resuming;
    for (size_t k : group) {
        const std::string& output = results[k].task.output;
        resuming.push_back(hasCheckpoint(output));
        report(options,
               {k, n, results[k], resuming.back() ? "resuming" : "rendering", clock.etaSeconds()});
        fs::create_directories(fs::path(output).parent_path());
    }
    auto previous = fs::file_time_type::clock::now();
    int code = runForwardingSignals(kilnExecutable(), framesCommand(results, group, options));
    for (size_t g = 0; g < group.size(); ++g) {
        TaskResult& r = results[group[g]];
        std::vector<std::string> command = commandOf(r.task, options);
        // The child's marker holds the command as it ran; the batch's leaves the report options
        // out.
        bool done = isComplete(r.task.output, withChildArgs(command, options));
        auto end = done ? fs::last_write_time(doneMarkerPath(r.task.output))
                        : fs::file_time_type::clock::now();
        r.seconds = std::max(0.0, std::chrono::duration<double>(end - previous).count());
        previous = end;
        if (done) {
            if (!options.childArgs.empty()) markComplete(r.task.output, command);
            r.outcome = resuming[g] ? Outcome::Resumed : Outcome::Rendered;
            if (!options.keepCheckpoints) fs::remove(r.task.output + ".ckpt");
            reportEnd(r, options, group[g], n, clock);
            continue;
        }
        // The child stopped at this render: its exit status is this render's.
        r.exitCode = code;
        bool saved = code == 130 || code == 3;
        r.outcome = saved ? Outcome::Interrupted : Outcome::Failed;
        reportEnd(r, options, group[g], n, clock);
        if (saved) return {};
        return std::vector<size_t>(group.begin() + std::ptrdiff_t(g) + 1, group.end());
    }
    return {};
}

}  // namespace

const char* outcomeName(Outcome o) {
    switch (o) {
        case Outcome::Skipped:
            return "skipped";
        case Outcome::Rendered:
            return "rendered";
        case Outcome::Resumed:
            return "resumed";
        case Outcome::Failed:
            return "failed";
        case Outcome::Interrupted:
            return "interrupted";
        case Outcome::NotRun:
            break;
    }
    return "not run";
}

std::vector<TaskResult> runTasks(const std::vector<RenderTask>& tasks, const RunOptions& options) {
    std::vector<TaskResult> results;
    for (const RenderTask& t : tasks) results.push_back({t});
    BatchClock clock;
    for (const RenderTask& t : tasks) clock.toRun += !taskComplete(t, options);
    auto interrupted = [&results] {
        return std::any_of(results.begin(), results.end(),
                           [](const TaskResult& r) { return r.outcome == Outcome::Interrupted; });
    };
    for (size_t next = 0; next < tasks.size() && lastForwardedSignal() == 0 && !interrupted();) {
        std::vector<size_t> group = nextGroup(results, next, options, clock);
        while (group.size() > 1 && lastForwardedSignal() == 0)
            group = runFrames(results, group, options, clock);
        if (group.size() == 1 && lastForwardedSignal() == 0)
            results[group[0]] = runOne(tasks[group[0]], options, group[0], tasks.size(), clock);
    }
    return results;
}

std::vector<std::string> dryRun(const std::vector<RenderTask>& tasks, const RunOptions& options) {
    std::vector<std::string> plan;
    for (const RenderTask& t : tasks)
        plan.push_back(taskComplete(t, options)  ? "skip"
                       : hasCheckpoint(t.output) ? "resume"
                                                 : "render");
    return plan;
}

int exitCodeOf(const std::vector<TaskResult>& results) {
    int code = 0;
    for (const TaskResult& r : results) {
        if (r.outcome == Outcome::Interrupted || r.outcome == Outcome::NotRun) return 130;
        if (r.outcome == Outcome::Failed) code = 1;
    }
    return code;
}

std::string summaryLine(const std::vector<TaskResult>& results) {
    std::string line = std::to_string(results.size()) + " renders:";
    double seconds = 0;
    for (const TaskResult& r : results) seconds += r.seconds;
    for (Outcome o : kOutcomes) {
        size_t n = 0;
        for (const TaskResult& r : results) n += r.outcome == o;
        if (n)
            line.append(" ")
                .append(std::to_string(n))
                .append(" ")
                .append(outcomeName(o))
                .append(",");
    }
    return line + fmt::format(" {:.2f}s rendering", seconds);
}

std::string summaryJson(const std::vector<TaskResult>& results) {
    nlohmann::json doc = {{"renders", nlohmann::json::array()},
                          {"counts", nlohmann::json::object()}};
    for (Outcome o : kOutcomes) doc["counts"][outcomeName(o)] = 0;
    for (const TaskResult& r : results) {
        doc["renders"].push_back({{"scene", r.task.scene},
                                  {"output", r.task.output},
                                  {"args", r.task.args},
                                  {"outcome", outcomeName(r.outcome)},
                                  {"exit_code", r.exitCode},
                                  {"seconds", r.seconds}});
        doc["counts"][outcomeName(r.outcome)] =
            doc["counts"][outcomeName(r.outcome)].get<int>() + 1;
    }
    doc["exit_code"] = exitCodeOf(results);
    return doc.dump(2);
}

}  // namespace kiln::farm
