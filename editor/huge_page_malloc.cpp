#include "huge_page_malloc.h"

#include <cstdlib>
#include <fstream>
#include <malloc.h>
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
    // A thread's heap (every thread but the main one has its own) is made writable only as far
    // as it has grown, a page at a time. A huge page is faulted in only where its whole 2 MiB
    // range is writable, so the memory at the growing end of such a heap, which is where fresh
    // blocks go, came in 4 KiB pages. With this pad a new heap is writable whole (64 MiB) and the
    // main heap grows 64 MiB at a time: the planning threads' blocks get huge pages too. Untouched
    // pages cost no memory; the pad is also the free memory kept at the top of a heap.
    constexpr int kMallocTopPad = 64 << 20;
    mallopt(M_TOP_PAD, kMallocTopPad);
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
