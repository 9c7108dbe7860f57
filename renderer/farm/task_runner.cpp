#include "renderer/farm/task_runner.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "renderer/farm/child_process.h"

namespace kiln::farm {
namespace {

namespace fs = std::filesystem;

constexpr Outcome kOutcomes[] = {Outcome::Rendered, Outcome::Resumed,     Outcome::Skipped,
                                 Outcome::Failed,   Outcome::Interrupted, Outcome::NotRun};

std::vector<std::string> commandOf(const RenderTask& task, const RunOptions& options) {
    return renderCommand(task, options.checkpointSeconds, options.quietChildren);
}

// Marks r skipped (and says so) when its output is complete.
bool skippedAsComplete(TaskResult& r, const RunOptions& options, size_t i, size_t n) {
    if (!isComplete(r.task.output, commandOf(r.task, options))) return false;
    r.outcome = Outcome::Skipped;
    if (options.progress)
        std::fprintf(options.progress, "kiln: [%zu/%zu] %s: complete, skipped\n", i + 1, n,
                     r.task.output.c_str());
    return true;
}

void reportEnd(const TaskResult& r, const RunOptions& options, size_t i, size_t n) {
    if (options.progress)
        std::fprintf(options.progress, "kiln: [%zu/%zu] %s: %s (exit %d) in %.2fs\n", i + 1, n,
                     r.task.output.c_str(), outcomeName(r.outcome), r.exitCode, r.seconds);
}

TaskResult runOne(const RenderTask& task, const RunOptions& options, size_t i, size_t n) {
    TaskResult r{task};
    std::vector<std::string> command = commandOf(task, options);
    if (skippedAsComplete(r, options, i, n)) return r;
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
    reportEnd(r, options, i, n);
    return r;
}

// A child's command line stays far below the kernel's limit on arguments (2 MiB with the usual
// 8 MiB stack); a longer run of frames goes on in the next child.
constexpr size_t kFramesCommandBytes = 256 * 1024;

// From `next` on: the run of tasks of one scene to render in one child, the complete ones among
// them marked skipped; `next` moves past them.
std::vector<size_t> nextGroup(std::vector<TaskResult>& results, size_t& next,
                              const RunOptions& options) {
    std::vector<size_t> group;
    size_t bytes = 0;
    for (; next < results.size(); ++next) {
        const RenderTask& task = results[next].task;
        if (!group.empty() && task.scene != results[group[0]].task.scene) break;
        if (skippedAsComplete(results[next], options, next, results.size())) continue;
        for (const std::string& a : commandOf(task, options)) bytes += a.size() + 1;
        if (!group.empty() && bytes > kFramesCommandBytes) break;
        group.push_back(next);
    }
    return group;
}

// `kiln render-frames` with every task's render command, joined by --then.
std::vector<std::string> framesCommand(const std::vector<TaskResult>& results,
                                       const std::vector<size_t>& group,
                                       const RunOptions& options) {
    std::vector<std::string> command{"render-frames"};
    for (size_t k : group) {
        std::vector<std::string> one = commandOf(results[k].task, options);
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
                              const RunOptions& options) {
    const size_t n = results.size();
    if (options.progress)
        std::fprintf(options.progress, "kiln: [%zu/%zu] %s: %zu renders from one scene load\n",
                     group[0] + 1, n, results[group[0]].task.scene.c_str(), group.size());
    std::vector<bool> resuming;
    for (size_t k : group) {
        const std::string& output = results[k].task.output;
        resuming.push_back(hasCheckpoint(output));
        if (resuming.back() && options.progress)
            std::fprintf(options.progress, "kiln: [%zu/%zu] %s: resuming from its checkpoint\n",
                         k + 1, n, output.c_str());
        fs::create_directories(fs::path(output).parent_path());
    }
    auto previous = fs::file_time_type::clock::now();
    int code = runForwardingSignals(kilnExecutable(), framesCommand(results, group, options));
    for (size_t g = 0; g < group.size(); ++g) {
        TaskResult& r = results[group[g]];
        std::vector<std::string> command = commandOf(r.task, options);
        bool done = isComplete(r.task.output, command);
        auto end = done ? fs::last_write_time(doneMarkerPath(r.task.output))
                        : fs::file_time_type::clock::now();
        r.seconds = std::max(0.0, std::chrono::duration<double>(end - previous).count());
        previous = end;
        if (done) {
            r.outcome = resuming[g] ? Outcome::Resumed : Outcome::Rendered;
            if (!options.keepCheckpoints) fs::remove(r.task.output + ".ckpt");
            reportEnd(r, options, group[g], n);
            continue;
        }
        // The child stopped at this render: its exit status is this render's.
        r.exitCode = code;
        bool saved = code == 130 || code == 3;
        r.outcome = saved ? Outcome::Interrupted : Outcome::Failed;
        reportEnd(r, options, group[g], n);
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
    auto interrupted = [&results] {
        return std::any_of(results.begin(), results.end(),
                           [](const TaskResult& r) { return r.outcome == Outcome::Interrupted; });
    };
    for (size_t next = 0; next < tasks.size() && lastForwardedSignal() == 0 && !interrupted();) {
        std::vector<size_t> group = nextGroup(results, next, options);
        while (group.size() > 1 && lastForwardedSignal() == 0)
            group = runFrames(results, group, options);
        if (group.size() == 1 && lastForwardedSignal() == 0)
            results[group[0]] = runOne(tasks[group[0]], options, group[0], tasks.size());
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
