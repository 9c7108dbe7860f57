// Where a farm job stands, per shard: done (its outputs are complete on disk), running, pending,
// or failed (with the last error line of its log), from Slurm's view and the files.
#pragma once

#include <string>
#include <vector>

#include "renderer/core/json.h"
#include "renderer/farm/farm_job.h"
#include "renderer/farm/slurm.h"

namespace kiln::farm {

enum class ShardState { Done, Running, Pending, Failed };
const char* shardStateName(ShardState s);

struct ShardStatus {
    int shard = 0;
    ShardState state = ShardState::Pending;
    long arrayJob = 0;  // the submission that last ran it
    SlurmTaskState slurm;
    std::string logLine;  // failed shards: the last error line of the log
};

struct FarmStatus {
    std::vector<ShardStatus> shards;
    bool merged = false;  // every merge output complete (or none needed)
    SlurmTaskState mergeJob;
    size_t count(ShardState s) const;
};

// The shard commands as run-shard runs them (quiet children, the job's checkpoint period).
bool shardComplete(const FarmJob& job, int shard);
bool mergeComplete(const Merge& merge);

// Slurm's state for a shard that is not complete on disk, mapped to ours.
ShardState stateFromSlurm(const std::string& jobState);
FarmStatus farmStatus(const FarmJob& job);
std::string statusText(const FarmJob& job, const FarmStatus& status);
// The same as one JSON document (docs/output.md's farm-status and farm-shard): the counts, the
// merge, and each shard's state, Slurm job, Slurm state, exit code, restarts and log line.
Json statusJson(const FarmJob& job, const FarmStatus& status);
// The line of a log to show for a failure: the last one with "error", else the last one that is
// not a progress line of the shard runner.
std::string lastErrorLine(const std::string& logText);

}  // namespace kiln::farm
