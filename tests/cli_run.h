// Running the real `quadplan` executable from a test, and reading the PNGs it writes.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <sys/wait.h>

namespace qp::test {

struct CommandRun {
    int status = -1;
    std::string out;  // stdout, and stderr too with mergeStderr
};

inline CommandRun runQuadplan(const std::string& args, bool mergeStderr = false) {
    std::string command = std::string(QUADPLAN_BINARY) + " " + args + (mergeStderr ? " 2>&1" : " 2>/dev/null");
    CommandRun run;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return run;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
    int raw = pclose(pipe);
    run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return run;
}

struct Png {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;
    const uint8_t* at(int x, int y) const { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
};

// Empty (width 0) when the file cannot be read. Defined in test_cli.cpp (stb_image).
Png loadPng(const std::string& path);

}  // namespace qp::test
