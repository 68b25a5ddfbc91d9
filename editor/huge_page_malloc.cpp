#include "huge_page_malloc.h"

#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

namespace qp::cli {

void useHugePagesForMalloc(char** argv) {
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
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
