// Slurm as the distributed engine: the sbatch scripts of a farm job, submission through sbatch,
// and shard states from `scontrol -o show job` (docs/farm-local-cluster.md: no slurmdbd needed).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "renderer/farm/farm_job.h"

namespace kiln::farm {

// DIR/shard.sbatch: one array task per shard, requeueable, TERM 60 s before the time limit,
// logs appended across requeues; it execs `kiln farm run-shard DIR $SLURM_ARRAY_TASK_ID` so the
// signal reaches kiln and the render checkpoints.
std::string shardScript(const FarmJob& job);
// DIR/merge.sbatch: `kiln farm merge DIR`.
std::string mergeScript(const FarmJob& job);
std::string shardLogPath(const FarmJob& job, int shard);

// Writes the manifest, submits the array for `shards` (and the merge job with afterok on it, when
// the job merges) and records the submission in the manifest. Throws std::runtime_error with
// sbatch's message when it fails.
Submission submitShards(FarmJob& job, const std::vector<int>& shards);

// "0-3", "1,3,5-7", "2-3%4" -> the task ids.
std::vector<int> parseArrayTaskIds(const std::string& text);

struct SlurmTaskState {
    long jobId = 0;
    std::string state = "UNKNOWN";  // JobState: PENDING RUNNING COMPLETED FAILED CANCELLED ...
    std::string exitCode, reason;
    int restarts = 0;
};
// Array task id -> state, from the one-line-per-task output of `scontrol -o show job ARRAY`.
std::map<int, SlurmTaskState> parseScontrolArray(const std::string& text);
// State of a plain job from the same output (first record).
SlurmTaskState parseScontrolJob(const std::string& text);

// In an array task that was signalled and saved its checkpoint: when Slurm still has the task
// RUNNING, the TERM was --signal's warning before the time limit (scancel, requeue and preemption
// move it out of RUNNING first), so the task requeues itself to resume. Returns what it did.
std::string requeueSelfBeforeTimeLimit();

// scancel of a job still pending (a merge whose shards are resubmitted: a cluster without
// kill_invalid_depend keeps it waiting on a dependency that can never be met).
void cancelIfPending(long job);

// Where sbatch is on $PATH; empty when it is not (kiln farm submit refuses before it writes).
std::string findSbatch();

// The live query (empty map / UNKNOWN when Slurm no longer knows the job).
std::map<int, SlurmTaskState> queryArray(long arrayJob);
SlurmTaskState queryJob(long job);

}  // namespace kiln::farm
