// The order a render hands out its tiles. Only the schedule depends on it: each tile's pixels are
// its own, so the image is the same whatever the order.
#pragma once

#include <functional>
#include <vector>

namespace kiln {

// Tile indices, the costliest of the last wave first (longest processing time first: a greedy
// schedule whose idle tail is about one cheap tile, not one costly one; an environment-lit mesh's
// background tiles cost a ray a sample, its statue's a whole path). Ties, and a first wave with no
// times, keep the image's order.
std::vector<int> costliestFirst(const std::vector<double>& lastWaveSeconds);

// Calls fn(tile) once for every tile of `order` on `workers` threads of the current task arena,
// each worker taking the next tile from one counter, so tiles start in that order (a parallel_for
// over the indices splits them in halves and starts a costly tile whenever a thread reaches it).
// An exception from fn stops the others taking tiles and reaches the caller.
void forEachTileInOrder(const std::vector<int>& order, int workers,
                        const std::function<void(int)>& fn);

}  // namespace kiln
