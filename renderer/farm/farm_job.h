// A farm job: the renders split into shards (one Slurm array task each) and the merges that join
// sample or region shards into the final images; kept as DIR/manifest.json.
#pragma once

#include <string>
#include <vector>

#include "renderer/core/enum_names.h"
#include "renderer/farm/render_task.h"

namespace kiln::farm {
enum class ShardBy { Samples, Region, Frames };
}  // namespace kiln::farm

namespace kiln {
template <>
struct EnumNames<farm::ShardBy> {
    static constexpr std::pair<farm::ShardBy, const char*> table[] = {
        {farm::ShardBy::Samples, "samples"},
        {farm::ShardBy::Region, "region"},
        {farm::ShardBy::Frames, "frames"}};
};
}  // namespace kiln

namespace kiln::farm {

ShardBy parseShardBy(const std::string& text);  // throws FarmInputError
const char* shardByName(ShardBy by);

struct Shard {
    std::vector<RenderTask> tasks;  // run one after another by `kiln farm run-shard`
};

// `kiln merge INPUTS.ckpt... -o OUTPUT`, then OUTPUT.done.
struct Merge {
    std::string output;
    std::vector<std::string> inputs;  // shard output bases
};

struct Submission {
    long arrayJob = 0, mergeJob = 0;  // mergeJob 0: none
    std::vector<int> shards;
};

struct FarmJob {
    std::string dir, kiln;
    ShardBy by = ShardBy::Frames;
    int checkpointSeconds = 60;
    bool keepCheckpoints = false;  // else removed once a frame is done or its shards are merged
    std::vector<std::string> sbatchOptions;  // --partition, --time, --mem as given
    std::vector<Shard> shards;
    std::vector<Merge> merges;
    std::vector<Submission> submissions;
};

// Splits the tasks into shards: by frames, `shards` groups of whole renders, or with
// framesPerTask > 0 runs of that many renders (the last one shorter: Deadline's and OpenCue's
// chunk size); by samples or region, every render in `shards` parts (--sample-range / --crop)
// rendered into DIR/shards and merged. Throws FarmInputError when a render cannot be split that
// many ways. A shard's frames of one scene render from one scene load (task_runner.h).
FarmJob planFarmJob(const std::vector<RenderTask>& tasks, ShardBy by, int shards,
                    const std::string& dir, int framesPerTask = 0);

// The merge command line (without the program) and its marker check.
std::vector<std::string> mergeCommand(const Merge& merge);

std::string manifestPath(const std::string& dir);
void writeManifest(const FarmJob& job);
FarmJob readManifest(const std::string& dir);  // throws FarmInputError

}  // namespace kiln::farm
