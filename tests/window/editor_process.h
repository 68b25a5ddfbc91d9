// Running the real `quadplan edit` as a child process for the editor tests: start it with an
// automation script, wait for files it writes, send real X input with xdotool, collect its
// exit status and what it printed.
#pragma once

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>
#include <stb/stb_image.h>  // the implementation is in test_editor_app.cpp

#include "render_test_support.h"

namespace qp::test {

namespace fs = std::filesystem;

struct EditorProcess {
    pid_t pid = -1;
    fs::path log;  // the child's stdout and stderr
    int status = -1;

    // Starts `quadplan ARGS...` in `cwd` with extra environment variables.
    void start(const std::vector<std::string>& args, const fs::path& cwd, const std::map<std::string, std::string>& env,
               const fs::path& logFile) {
        log = logFile;
        pid = fork();
        if (pid == 0) {
            if (chdir(cwd.c_str()) != 0) _exit(126);
            for (const auto& [name, value] : env) {
                if (value.empty()) unsetenv(name.c_str());
                else setenv(name.c_str(), value.c_str(), 1);
            }
            const int fd = open(logFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            dup2(fd, 1);
            dup2(fd, 2);
            std::vector<char*> argv;
            std::string binary = QUADPLAN_BINARY;
            argv.push_back(binary.data());
            std::vector<std::string> copies = args;
            for (std::string& a : copies) argv.push_back(a.data());
            argv.push_back(nullptr);
            execv(binary.c_str(), argv.data());
            _exit(127);
        }
    }

    // Waits for the exit; kills the child after `seconds`. Returns the exit status (-1: killed).
    int wait(double seconds) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (std::chrono::steady_clock::now() < deadline) {
            int raw = 0;
            if (waitpid(pid, &raw, WNOHANG) == pid) {
                status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
                pid = -1;
                return status;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        kill();
        return -1;
    }

    void kill() {
        if (pid <= 0) return;
        ::kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
        pid = -1;
    }

    bool running() const { return pid > 0; }

    std::string output() const {
        std::ifstream in(log);
        std::stringstream text;
        text << in.rdbuf();
        return text.str();
    }

    ~EditorProcess() { kill(); }
};

// Waits until `path` exists (written atomically by the editor) or the child exits.
inline bool waitForFile(const fs::path& path, EditorProcess& editor, double seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < deadline) {
        if (fs::exists(path)) return true;
        int raw = 0;
        if (editor.pid > 0 && waitpid(editor.pid, &raw, WNOHANG) == editor.pid) {
            editor.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
            editor.pid = -1;
            return fs::exists(path);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
}

inline nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in, nullptr, false);
}

inline void writeText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

inline bool haveProgram(const char* name) {
    return std::system((std::string("command -v ") + name + " >/dev/null 2>&1").c_str()) == 0;
}

// Runs xdotool with `args` (real X events on the test's display).
inline int xdotool(const std::string& args) { return std::system(("xdotool " + args).c_str()); }

// Whether there is an X display (ctest runs the window suites under xvfb-run).
inline bool haveDisplay() {
    const char* display = std::getenv("DISPLAY");
    return display && display[0];
}

// The environment an editor test starts `quadplan edit` in: its own recovery directory, and
// lavapipe unless QUADPLAN_VK_DEVICE names another device.
inline std::map<std::string, std::string> editorEnvironment(const fs::path& recoveryDir) {
    std::map<std::string, std::string> env{{"QUADPLAN_RECOVERY_DIR", recoveryDir.string()}};
    if (!std::getenv("QUADPLAN_VK_DEVICE") && fs::exists(kLavapipeIcd)) {
        env["VK_ICD_FILENAMES"] = kLavapipeIcd;
        env["VK_DRIVER_FILES"] = kLavapipeIcd;
    }
    return env;
}

// Screen position ("X Y" for xdotool) of window pixel p, for a window at (x, y).
struct Screen {
    int x = 0, y = 0;
    std::string operator()(glm::vec2 p) const { return std::to_string(x + int(p.x)) + " " + std::to_string(y + int(p.y)); }
};

// Pixels whose colours differ by more than 24 (summed over RGB) between two PNGs of one size.
inline size_t differingPixels(const fs::path& a, const fs::path& b) {
    int wa = 0, ha = 0, wb = 0, hb = 0, c = 0;
    uint8_t* pa = stbi_load(a.c_str(), &wa, &ha, &c, 3);
    uint8_t* pb = stbi_load(b.c_str(), &wb, &hb, &c, 3);
    size_t n = 0;
    if (pa && pb && wa == wb && ha == hb)
        for (size_t i = 0; i < size_t(wa) * ha * 3; i += 3)
            n += std::abs(pa[i] - pb[i]) + std::abs(pa[i + 1] - pb[i + 1]) + std::abs(pa[i + 2] - pb[i + 2]) > 24;
    stbi_image_free(pa);
    stbi_image_free(pb);
    return n;
}

}  // namespace qp::test
