#include "renderer/farm/farm_status.h"

#include <set>
#include <sstream>

namespace kiln::farm {

const char* shardStateName(ShardState s) {
    switch (s) {
        case ShardState::Done:
            return "done";
        case ShardState::Running:
            return "running";
        case ShardState::Pending:
            return "pending";
        case ShardState::Failed:
            break;
    }
    return "failed";
}

size_t FarmStatus::count(ShardState s) const {
    size_t n = 0;
    for (const ShardStatus& st : shards) n += st.state == s;
    return n;
}

bool shardComplete(const FarmJob& job, int shard) {
    for (const RenderTask& t : job.shards[size_t(shard)].tasks)
        if (!isComplete(t.output, renderCommand(t, job.checkpointSeconds, true))) return false;
    return true;
}

bool mergeComplete(const Merge& merge) { return isComplete(merge.output, mergeCommand(merge)); }

ShardState stateFromSlurm(const std::string& jobState) {
    static const std::set<std::string> pending{"PENDING",     "REQUEUED",    "REQUEUE_HOLD",
                                               "REQUEUE_FED", "CONFIGURING", "SUSPENDED",
                                               "RESIZING"};
    if (pending.count(jobState) || jobState == "NOT_SUBMITTED") return ShardState::Pending;
    if (jobState == "RUNNING" || jobState == "COMPLETING") return ShardState::Running;
    // FAILED, CANCELLED, TIMEOUT, NODE_FAIL, OUT_OF_MEMORY, BOOT_FAIL, DEADLINE, PREEMPTED; and
    // COMPLETED or UNKNOWN (Slurm forgot it) without complete outputs.
    return ShardState::Failed;
}

std::string lastErrorLine(const std::string& logText) {
    std::istringstream lines(logText);
    std::string last, lastError;
    for (std::string line; std::getline(lines, line);) {
        // Our own progress lines say that a render failed, not why.
        if (line.empty() || line.rfind("kiln: [", 0) == 0 || line.rfind("kiln farm:", 0) == 0)
            continue;
        last = line;
        if (line.find("error") != std::string::npos) lastError = line;
    }
    return lastError.empty() ? last : lastError;
}

FarmStatus farmStatus(const FarmJob& job) {
    FarmStatus status;
    std::vector<long> arrayOf(job.shards.size(), 0);
    for (const Submission& s : job.submissions)
        for (int shard : s.shards) arrayOf[size_t(shard)] = s.arrayJob;
    std::map<long, std::map<int, SlurmTaskState>> arrays;
    for (const Submission& s : job.submissions) arrays[s.arrayJob] = queryArray(s.arrayJob);
    for (size_t i = 0; i < job.shards.size(); ++i) {
        ShardStatus st;
        st.shard = int(i);
        st.arrayJob = arrayOf[i];
        auto& tasks = arrays[st.arrayJob];
        if (auto it = tasks.find(int(i)); it != tasks.end()) st.slurm = it->second;
        if (st.arrayJob == 0) st.slurm.state = "NOT_SUBMITTED";  // planned, never given to Slurm
        st.state = shardComplete(job, int(i)) ? ShardState::Done : stateFromSlurm(st.slurm.state);
        if (st.state == ShardState::Failed) {
            try {
                st.logLine = lastErrorLine(readFileText(shardLogPath(job, int(i))));
            } catch (const FarmInputError&) {
                st.logLine = "(no log)";
            }
        }
        status.shards.push_back(st);
    }
    status.merged = true;
    for (const Merge& m : job.merges) status.merged = status.merged && mergeComplete(m);
    if (!job.submissions.empty() && job.submissions.back().mergeJob)
        status.mergeJob = queryJob(job.submissions.back().mergeJob);
    return status;
}

std::string statusText(const FarmJob& job, const FarmStatus& status) {
    std::ostringstream out;
    out << job.dir << ": " << status.shards.size() << " shards by " << shardByName(job.by) << ": "
        << status.count(ShardState::Done) << " done, " << status.count(ShardState::Running)
        << " running, " << status.count(ShardState::Pending) << " pending, "
        << status.count(ShardState::Failed) << " failed";
    if (!job.merges.empty()) out << "; merge: " << (status.merged ? "done" : status.mergeJob.state);
    out << "\n";
    for (const ShardStatus& s : status.shards) {
        out << "shard " << s.shard << ": " << shardStateName(s.state) << " (job " << s.arrayJob
            << "_" << s.shard << " " << s.slurm.state;
        if (!s.slurm.exitCode.empty()) out << " exit " << s.slurm.exitCode;
        if (s.slurm.restarts) out << " restarts " << s.slurm.restarts;
        out << ")";
        if (!s.logLine.empty()) out << ": " << s.logLine;
        out << "\n";
    }
    return out.str();
}

Json statusJson(const FarmJob& job, const FarmStatus& status) {
    Json counts = Json::object(), shards = Json::array();
    for (ShardState state :
         {ShardState::Done, ShardState::Running, ShardState::Pending, ShardState::Failed})
        counts[shardStateName(state)] = status.count(state);
    for (const ShardStatus& s : status.shards)
        shards.push_back({{"shard", s.shard},
                          {"state", shardStateName(s.state)},
                          {"array_job", s.arrayJob},
                          {"slurm_state", s.slurm.state},
                          {"slurm_exit_code", s.slurm.exitCode},
                          {"restarts", s.slurm.restarts},
                          {"log_line", s.logLine}});
    return {{"dir", job.dir},
            {"by", shardByName(job.by)},
            {"counts", counts},
            {"merges", job.merges.size()},
            {"merged", status.merged},
            {"merge_state", job.merges.empty() || status.merged ? "done" : status.mergeJob.state},
            {"shards", shards}};
}

}  // namespace kiln::farm
