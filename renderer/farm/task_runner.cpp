#include "renderer/farm/task_runner.h"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "renderer/farm/child_process.h"

namespace kiln::farm {
namespace {

namespace fs = std::filesystem;

constexpr Outcome kOutcomes[] = {Outcome::Rendered, Outcome::Resumed,     Outcome::Skipped,
                                 Outcome::Failed,   Outcome::Interrupted, Outcome::NotRun};

TaskResult runOne(const RenderTask& task, const RunOptions& options, size_t i, size_t n) {
    TaskResult r{task};
    std::vector<std::string> command =
        renderCommand(task, options.checkpointSeconds, options.quietChildren);
    if (isComplete(task.output, command)) {
        r.outcome = Outcome::Skipped;
        if (options.progress)
            std::fprintf(options.progress, "kiln: [%zu/%zu] %s: complete, skipped\n", i + 1, n,
                         task.output.c_str());
        return r;
    }
    bool resuming = hasCheckpoint(task.output);
    if (options.progress)
        std::fprintf(options.progress, "kiln: [%zu/%zu] %s -> %s: %s\n", i + 1, n,
                     task.scene.c_str(), task.output.c_str(),
                     resuming ? "resuming from its checkpoint" : "rendering");
    fs::create_directories(fs::path(task.output).parent_path());
    auto t0 = std::chrono::steady_clock::now();
    r.exitCode = runForwardingSignals(kilnExecutable(), command);
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
    if (options.progress)
        std::fprintf(options.progress, "kiln: [%zu/%zu] %s: %s (exit %d) in %.2fs\n", i + 1, n,
                     task.output.c_str(), outcomeName(r.outcome), r.exitCode, r.seconds);
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
    for (size_t i = 0; i < tasks.size(); ++i) {
        if (stopped || lastForwardedSignal() != 0) {
            results.push_back({tasks[i]});
            continue;
        }
        results.push_back(runOne(tasks[i], options, i, tasks.size()));
        stopped = results.back().outcome == Outcome::Interrupted;
    }
    return results;
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
    std::string line = "kiln: " + std::to_string(results.size()) + " renders:";
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
