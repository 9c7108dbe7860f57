#include "renderer/farm/slurm.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "renderer/farm/child_process.h"

namespace kiln::farm {
namespace {

namespace fs = std::filesystem;

// A single-quoted shell word.
std::string quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string header(const FarmJob& job, const std::string& name, const std::string& log) {
    std::string text = "#!/bin/bash\n# Written by kiln farm submit (docs/farm.md).\n";
    text += "#SBATCH --job-name=" + name + "\n";
    text += "#SBATCH --output=" + log + "\n#SBATCH --open-mode=append\n";
    text += "#SBATCH --chdir=" + job.dir + "\n";
    for (const std::string& o : job.sbatchOptions) text += "#SBATCH " + o + "\n";
    return text;
}

long submit(const std::vector<std::string>& args) {
    CommandResult r = runCapturing("sbatch", args);
    if (r.exitCode != 0) {
        std::string message = r.output.substr(0, r.output.find('\n'));
        throw std::runtime_error("sbatch failed (exit " + std::to_string(r.exitCode) +
                                 "): " + message);
    }
    long id = std::atol(r.output.c_str());  // --parsable: "ID" or "ID;cluster"
    if (id <= 0) throw std::runtime_error("sbatch printed no job id: " + r.output);
    return id;
}

std::string arrayList(const std::vector<int>& shards) {
    std::string list;
    for (int s : shards) list.append(list.empty() ? "" : ",").append(std::to_string(s));
    return list;
}

// "Key=Value Key=Value ..." of one scontrol -o record (values hold no spaces for our keys).
std::map<std::string, std::string> fieldsOf(const std::string& line) {
    std::map<std::string, std::string> fields;
    std::istringstream words(line);
    for (std::string w; words >> w;)
        if (size_t eq = w.find('='); eq != std::string::npos && !fields.count(w.substr(0, eq)))
            fields[w.substr(0, eq)] = w.substr(eq + 1);
    return fields;
}

SlurmTaskState stateOf(std::map<std::string, std::string>& f) {
    SlurmTaskState s;
    s.jobId = std::atol(f["JobId"].c_str());
    s.state = f["JobState"].empty() ? "UNKNOWN" : f["JobState"];
    s.exitCode = f["ExitCode"];
    s.reason = f["Reason"];
    s.restarts = std::atoi(f["Restarts"].c_str());
    return s;
}

}  // namespace

std::string shardLogPath(const FarmJob& job, int shard) {
    return (fs::path(job.dir) / "logs" / ("shard_" + std::to_string(shard) + ".log")).string();
}

std::string shardScript(const FarmJob& job) {
    std::string text = header(job, "kiln-shards", job.dir + "/logs/shard_%a.log");
    text += "#SBATCH --requeue\n#SBATCH --signal=B:TERM@60\n";
    // exec: bash would run a trap only after its child exits; kiln forwards the TERM itself.
    text += "exec " + quoted(job.kiln) + " farm run-shard " + quoted(job.dir) +
            " \"$SLURM_ARRAY_TASK_ID\"\n";
    return text;
}

std::string mergeScript(const FarmJob& job) {
    return header(job, "kiln-merge", job.dir + "/logs/merge.log") + "exec " + quoted(job.kiln) +
           " farm merge " + quoted(job.dir) + "\n";
}

Submission submitShards(FarmJob& job, const std::vector<int>& shards) {
    fs::create_directories(fs::path(job.dir) / "logs");
    std::string shardFile = job.dir + "/shard.sbatch", mergeFile = job.dir + "/merge.sbatch";
    writeFileAtomically(shardFile, shardScript(job));
    writeManifest(job);  // before sbatch: a task may start at once and reads its renders from it
    Submission s;
    s.shards = shards;
    s.arrayJob = submit({"--parsable", "--array=" + arrayList(shards), shardFile});
    job.submissions.push_back(s);
    writeManifest(job);
    if (!job.merges.empty()) {
        writeFileAtomically(mergeFile, mergeScript(job));
        s.mergeJob =
            submit({"--parsable", "--dependency=afterok:" + std::to_string(s.arrayJob), mergeFile});
        job.submissions.back() = s;
        writeManifest(job);
    }
    return s;
}

std::string findSbatch() {
    const char* path = std::getenv("PATH");
    std::istringstream dirs(path ? path : "");
    for (std::string dir; std::getline(dirs, dir, ':');) {
        fs::path candidate = fs::path(dir.empty() ? "." : dir) / "sbatch";
        if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    return "";
}

std::vector<int> parseArrayTaskIds(const std::string& text) {
    std::vector<int> ids;
    std::string list = text.substr(0, text.find('%'));
    std::istringstream parts(list);
    for (std::string part; std::getline(parts, part, ',');) {
        if (part.empty()) continue;
        size_t dash = part.find('-');
        int first = std::atoi(part.c_str());
        int last = dash == std::string::npos ? first : std::atoi(part.c_str() + dash + 1);
        for (int i = first; i <= last; ++i) ids.push_back(i);
    }
    return ids;
}

std::map<int, SlurmTaskState> parseScontrolArray(const std::string& text) {
    std::map<int, SlurmTaskState> tasks;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        auto fields = fieldsOf(line);
        if (!fields.count("ArrayTaskId")) continue;
        SlurmTaskState s = stateOf(fields);
        for (int id : parseArrayTaskIds(fields["ArrayTaskId"])) tasks[id] = s;
    }
    return tasks;
}

SlurmTaskState parseScontrolJob(const std::string& text) {
    auto fields = fieldsOf(text.substr(0, text.find('\n')));
    return fields.count("JobState") ? stateOf(fields) : SlurmTaskState{};
}

std::map<int, SlurmTaskState> queryArray(long arrayJob) {
    CommandResult r = runCapturing("scontrol", {"-o", "show", "job", std::to_string(arrayJob)});
    return r.exitCode == 0 ? parseScontrolArray(r.output) : std::map<int, SlurmTaskState>{};
}

SlurmTaskState queryJob(long job) {
    CommandResult r = runCapturing("scontrol", {"-o", "show", "job", std::to_string(job)});
    return r.exitCode == 0 ? parseScontrolJob(r.output) : SlurmTaskState{};
}

void cancelIfPending(long job) {
    if (queryJob(job).state == "PENDING") runCapturing("scancel", {std::to_string(job)});
}

std::string requeueSelfBeforeTimeLimit() {
    const char* job = std::getenv("SLURM_JOB_ID");
    if (!job) return "not in a Slurm job: not requeued";
    SlurmTaskState self = queryJob(std::atol(job));
    if (self.state != "RUNNING") return "job is " + self.state + ": not requeued";
    CommandResult r = runCapturing("scontrol", {"requeue", job});
    return r.exitCode == 0 ? "time limit near: requeued to resume from the checkpoint"
                           : "scontrol requeue failed: " + r.output.substr(0, r.output.find('\n'));
}

}  // namespace kiln::farm
