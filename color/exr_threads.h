// OpenEXR's (de)compression threads: every core, as OpenImageIO set them when it read and wrote
// kiln's EXRs. Set once per process, before the first file is opened.
#pragma once

#include <OpenEXR/ImfThreading.h>

#include <algorithm>
#include <thread>

namespace kiln {

inline void exrThreadsOnEveryCore() {
    static const bool set = [] {
        Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency())));
        return true;
    }();
    (void)set;
}

}  // namespace kiln
