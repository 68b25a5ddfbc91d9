// `quadplan run-script FILE.py [ARGS...]`: runs a Python script with the quadplan module
// importable, headless (docs/python.md). The process becomes the interpreter (exec), so the
// exit status is the script's and an uncaught exception prints its traceback and exits 1.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "commands.h"

namespace qp::cli {

namespace {

namespace fs = std::filesystem;

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

int runScript(const std::vector<std::string>& arguments) {
#ifndef QUADPLAN_PYTHON_EXECUTABLE
    (void)arguments;
    return fail("this quadplan was built without the Python module (configured with -DQUADPLAN_PYTHON=OFF)");
#else
    if (arguments.empty()) return fail("run-script needs a script: quadplan run-script FILE.py [ARGS...]");
    const std::string& script = arguments[0];
    std::error_code error;
    if (!fs::is_regular_file(script, error)) return fail("cannot run '" + script + "': no such file");
    // The package is built beside the executable: <build>/bin/quadplan, <build>/python/quadplan.
    const fs::path packageDir = fs::read_symlink("/proc/self/exe", error).parent_path().parent_path() / "python";
    if (error || !fs::exists(packageDir / "quadplan" / "__init__.py"))
        return fail("the quadplan Python package is not beside this executable (looked in " + packageDir.string() +
                    "); build the target quadplan_python");
    const char* pythonPath = std::getenv("PYTHONPATH");
    const std::string path = packageDir.string() + (pythonPath && pythonPath[0] ? ":" + std::string(pythonPath) : "");
    setenv("PYTHONPATH", path.c_str(), 1);

    const char* python = std::getenv("QUADPLAN_PYTHON");
    if (!python || !python[0]) python = QUADPLAN_PYTHON_EXECUTABLE;
    std::vector<char*> argv{const_cast<char*>(python)};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    std::fflush(stdout);
    std::fflush(stderr);
    execv(python, argv.data());
    return fail(std::string("cannot start the Python interpreter ") + python + ": " + std::strerror(errno));
#endif
}

}  // namespace

void registerRunScript(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand(
        "run-script", "Run a Python script headless with the quadplan module importable; exits with the script's status");
    // Everything after the script's name belongs to the script, options included.
    cmd->prefix_command();
    cmd->footer("Usage: quadplan run-script FILE.py [ARGS...]   (sys.argv = [FILE.py, ARGS...]; docs/python.md)\n"
                "QUADPLAN_PYTHON overrides the interpreter the module was built for.");
    cmd->callback([cmd, &exitCode] { exitCode = runScript(cmd->remaining()); });
}

}  // namespace qp::cli
