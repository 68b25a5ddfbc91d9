#include "plans/memory_estimate.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace qp {

namespace {

std::string gib(uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(1ull << 30));
    return text;
}

}  // namespace

uint64_t planningBytesEstimate(const Cage& cage) {
    uint64_t subfaces = 0;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) subfaces += cage.faceSize(f) == 4 ? 1 : cage.faceSize(f);
    return subfaces * kPlanningBytesPerSubface;
}

uint64_t availableMemoryBytes() {
    std::ifstream meminfo("/proc/meminfo");
    std::string line;
    while (std::getline(meminfo, line)) {
        std::istringstream fields(line);
        std::string key;
        uint64_t kib = 0;
        if (fields >> key >> kib && key == "MemAvailable:") return kib * 1024;
    }
    return 0;
}

void releaseFreedMemory() {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

Status checkMemory(uint64_t needed, uint64_t available, const std::string& what) {
    if (available == 0 || needed <= available) return success();
    return Error{what + " needs about " + gib(needed) + " of memory and " + gib(available) +
                 " is available: close other programs, or split the cage into smaller objects"};
}

}  // namespace qp
