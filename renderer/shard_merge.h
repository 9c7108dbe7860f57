// kiln merge: shards of one render (sample ranges, crop regions, or both) combined into the film
// the single-process render would hold, bit for bit (the film's sums are exact integers, so their
// order does not matter). Overlapping, missing, unfinished or foreign shards are refused.
#pragma once

#include <string>
#include <vector>

#include "renderer/checkpoint.h"

namespace kiln {

struct MergedRender {
    Film film;
    CheckpointInfo info;  // totals over the shards; metadata for the EXR
};

// Throws CheckpointError (bad input: one line naming the shard and the problem).
MergedRender mergeShards(const std::vector<std::string>& paths);

}  // namespace kiln
