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

#include <nlohmann/json.hpp>

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

}  // namespace qp::test
