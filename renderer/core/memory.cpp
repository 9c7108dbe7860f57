#include "renderer/core/memory.h"

#include <cstdlib>
#include <fstream>
#include <string>

namespace kiln {

uint64_t availableMemoryBytes() {
    if (const char* limit = std::getenv("KILN_MEMORY_LIMIT"); limit && *limit)
        return std::strtoull(limit, nullptr, 10);
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    uint64_t kb = 0;
    while (meminfo >> key >> kb) {
        if (key == "MemAvailable:") return kb * 1024;
        meminfo.ignore(256, '\n');
    }
    return UINT64_MAX;
}

}  // namespace kiln
