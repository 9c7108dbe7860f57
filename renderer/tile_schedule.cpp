#include "renderer/tile_schedule.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <atomic>
#include <numeric>

namespace kiln {

std::vector<int> costliestFirst(const std::vector<double>& lastWaveSeconds) {
    std::vector<int> order(lastWaveSeconds.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return lastWaveSeconds[size_t(a)] > lastWaveSeconds[size_t(b)];
    });
    return order;
}

void forEachTileInOrder(const std::vector<int>& order, int workers,
                        const std::function<void(int)>& fn) {
    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};  // a tile threw: the others take no more tiles
    // One task per worker (simple_partitioner with grain 1 splits down to single indices).
    tbb::parallel_for(
        tbb::blocked_range<int>(0, std::max(1, workers), 1),
        [&](const tbb::blocked_range<int>&) {
            for (size_t i = next++; i < order.size() && !failed; i = next++) {
                try {
                    fn(order[i]);
                } catch (...) {
                    failed = true;
                    throw;
                }
            }
        },
        tbb::simple_partitioner());
}

}  // namespace kiln
