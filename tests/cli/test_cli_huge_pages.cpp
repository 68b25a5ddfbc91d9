// The executable asks glibc's malloc for transparent huge pages where the kernel gives them only
// on request (editor/huge_page_malloc.h): the program it runs sees the tunable, and a
// GLIBC_TUNABLES the user set, even empty, is left alone.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "cli_run.h"

namespace fs = std::filesystem;

namespace {

// GLIBC_TUNABLES as a Python script run by `quadplan run-script` sees it, when quadplan starts
// with `tunables` (nullopt: unset). The variable is set in this process only around the run.
std::string tunablesSeenByScript(const std::optional<std::string>& tunables) {
    const fs::path script = fs::temp_directory_path() / ("quadplan-huge-pages-" + std::to_string(::getpid()) + ".py");
    std::ofstream(script) << "import os\nprint('tunables=' + os.environ.get('GLIBC_TUNABLES', '<unset>'))\n";
    const char* before = std::getenv("GLIBC_TUNABLES");
    const std::optional<std::string> saved = before ? std::optional<std::string>(before) : std::nullopt;
    if (tunables) setenv("GLIBC_TUNABLES", tunables->c_str(), 1);
    else unsetenv("GLIBC_TUNABLES");
    const std::string out = qp::test::runQuadplan("run-script " + script.string(), true).out;
    if (saved) setenv("GLIBC_TUNABLES", saved->c_str(), 1);
    else unsetenv("GLIBC_TUNABLES");
    fs::remove(script);
    const size_t at = out.find("tunables=");
    if (at == std::string::npos) return "no output: " + out;
    return out.substr(at + 9, out.find('\n', at) - at - 9);
}

std::string hugePageMode() {
    std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode;
    std::getline(file, mode);
    return mode;
}

}  // namespace

TEST(CliHugePages, MallocAsksForHugePagesWhereTheKernelWaitsToBeAsked) {
    const std::string mode = hugePageMode();
    if (mode.find("[madvise]") == std::string::npos)
        GTEST_SKIP() << "transparent huge pages are '" << mode << "' here, not given on request: nothing to ask for";
    EXPECT_EQ(tunablesSeenByScript(std::nullopt), "glibc.malloc.hugetlb=1");
}

TEST(CliHugePages, TunablesTheUserSetAreLeftAlone) {
    EXPECT_EQ(tunablesSeenByScript(""), "");
    EXPECT_EQ(tunablesSeenByScript("glibc.malloc.arena_max=2"), "glibc.malloc.arena_max=2");
}
