#include "renderer/farm/task_runner.h"

#include <fmt/format.h>

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

bool taskComplete(const RenderTask& task, const RunOptions& options) {
    return isComplete(task.output,
                      renderCommand(task, options.checkpointSeconds, options.quietChildren));
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

TaskResult runOne(const RenderTask& task, const RunOptions& options, size_t i, size_t n,
                  BatchClock& clock) {
    TaskResult r{task};
    std::vector<std::string> command =
        renderCommand(task, options.checkpointSeconds, options.quietChildren);
    if (isComplete(task.output, command)) {
        r.outcome = Outcome::Skipped;
        report(options, {i, n, r, "skipped", clock.etaSeconds()});
        return r;
    }
    bool resuming = hasCheckpoint(task.output);
    report(options, {i, n, r, resuming ? "resuming" : "rendering", clock.etaSeconds()});
    fs::create_directories(fs::path(task.output).parent_path());
    std::vector<std::string> run = command;
    run.insert(run.end(), options.childArgs.begin(), options.childArgs.end());
    auto t0 = std::chrono::steady_clock::now();
    r.exitCode = runForwardingSignals(kilnExecutable(), run);
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
    ++clock.ran, clock.seconds += r.seconds;
    report(options, {i, n, r, outcomeName(r.outcome), clock.etaSeconds()});
    return r;
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
    bool stopped = false;
    BatchClock clock;
    for (const RenderTask& t : tasks) clock.toRun += !taskComplete(t, options);
    for (size_t i = 0; i < tasks.size(); ++i) {
        if (stopped || lastForwardedSignal() != 0) {
            results.push_back({tasks[i]});
            continue;
        }
        results.push_back(runOne(tasks[i], options, i, tasks.size(), clock));
        stopped = results.back().outcome == Outcome::Interrupted;
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
