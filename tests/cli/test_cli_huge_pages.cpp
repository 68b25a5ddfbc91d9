// The executable asks glibc's malloc for transparent huge pages where the kernel gives them only
// on request (editor/huge_page_malloc.h): the program it runs sees the tunable, and a
// GLIBC_TUNABLES the user set, even empty, is left alone.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

// The environment variable as a Python script run by `quadplan run-script` sees it.
std::string tunablesSeenByScript(const std::string& environmentPrefix) {
    const fs::path script = fs::temp_directory_path() / ("quadplan-huge-pages-" + std::to_string(::getpid()) + ".py");
    std::ofstream(script) << "import os\nprint('tunables=' + os.environ.get('GLIBC_TUNABLES', '<unset>'))\n";
    const std::string command = environmentPrefix + " " + QUADPLAN_BINARY + " run-script " + script.string() + " 2>&1";
    std::string out;
    if (FILE* pipe = popen(command.c_str(), "r")) {
        std::array<char, 4096> buffer;
        size_t n;
        while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) out.append(buffer.data(), n);
        pclose(pipe);
    }
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
    EXPECT_EQ(tunablesSeenByScript("env -u GLIBC_TUNABLES"), "glibc.malloc.hugetlb=1");
}

TEST(CliHugePages, TunablesTheUserSetAreLeftAlone) {
    EXPECT_EQ(tunablesSeenByScript("env GLIBC_TUNABLES="), "");
    EXPECT_EQ(tunablesSeenByScript("env GLIBC_TUNABLES=glibc.malloc.arena_max=2"), "glibc.malloc.arena_max=2");
}
