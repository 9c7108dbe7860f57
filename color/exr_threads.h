// OpenEXR's (de)compression threads: a render's -t, or every core (as OpenImageIO set them when it
// read and wrote kiln's EXRs). OpenEXR keeps one pool per process.
#pragma once

#include <OpenEXR/ImfThreading.h>

#include <algorithm>
#include <mutex>
#include <thread>

namespace kiln {
namespace detail {
struct ExrThreadChoice {
    std::mutex mutex;
    bool chosen = false;  // set by a render's -t or the first EXR opened
};
inline ExrThreadChoice& exrThreadChoice() {
    static ExrThreadChoice choice;
    return choice;
}
inline void resizeExrPool(int threads) {
    const int n = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
    if (Imf::globalThreadCount() != n) Imf::setGlobalThreadCount(n);
}
}  // namespace detail

// A render's -t (0: every core): a farm task given 4 cores compresses its EXR on 4 threads too.
// Only while no other thread reads or writes an EXR: OpenEXR drops the work queued in its pool
// when the pool is resized (kiln render and render-frames call it before each load; the Python
// module, whose threads may overlap, does not).
inline void setExrThreads(int threads) {
    detail::ExrThreadChoice& c = detail::exrThreadChoice();
    std::lock_guard lock(c.mutex);
    c.chosen = true;
    detail::resizeExrPool(threads);
}

// Before a file is opened: every core, unless a render chose its count.
inline void exrThreadsOnEveryCore() {
    detail::ExrThreadChoice& c = detail::exrThreadChoice();
    std::lock_guard lock(c.mutex);
    if (c.chosen) return;
    c.chosen = true;
    detail::resizeExrPool(0);
}

}  // namespace kiln
