#include "huge_page_malloc.h"

#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

// ASan replaces malloc: the tunable would do nothing there. gcc says so with a macro, clang with
// __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define QP_MALLOC_REPLACED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define QP_MALLOC_REPLACED 1
#endif
#endif

namespace qp::cli {

void useHugePagesForMalloc(char** argv) {
#if defined(__GLIBC__) && !defined(QP_MALLOC_REPLACED)
    if (std::getenv("GLIBC_TUNABLES")) return;  // the user's tunables, or the second run
    std::ifstream modeFile("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode;
    std::getline(modeFile, mode);
    if (mode.find("[madvise]") == std::string::npos) return;  // "always" has them, "never" refuses
    setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 1);
    execv("/proc/self/exe", argv);
    unsetenv("GLIBC_TUNABLES");
#else
    (void)argv;
#endif
}

}  // namespace qp::cli
