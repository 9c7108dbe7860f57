// How much memory kiln may still use, for refusing work that would not fit before allocating it.
#pragma once

#include <cstdint>

namespace kiln {

// MemAvailable from /proc/meminfo, or $KILN_MEMORY_LIMIT (bytes) when set; UINT64_MAX if unknown.
uint64_t availableMemoryBytes();

}  // namespace kiln
