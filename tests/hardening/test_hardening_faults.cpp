// Faults at the fallible boundaries outside files (issue 9 item 6; files: test_hardening_files.cpp):
// no Vulkan driver, no matching Vulkan device, a missing plugin directory and broken plugins.
// The headless commands exit non-zero (or, with some schemes still usable, list the broken
// ones) with a message that says what to do; no output file is written.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>

#include <sys/wait.h>

#include "render_test_support.h"

namespace fs = std::filesystem;

namespace {

struct CommandRun {
    int exit = -1;
    std::string output;
};

CommandRun runQuadplan(const std::string& environment, const std::string& args) {
    CommandRun run;
    FILE* pipe = popen((environment + " '" + QUADPLAN_BINARY + "' " + args + " 2>&1").c_str(), "r");
    if (!pipe) return run;
    std::array<char, 4096> buffer;
    for (size_t n; (n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0;) run.output.append(buffer.data(), n);
    const int raw = pclose(pipe);
    run.exit = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return run;
}

std::string renderArgs(const fs::path& png) {
    return std::string("render '") + QUADPLAN_SCENES_DIR + "/default.json' --out '" + png.string() + "'";
}

}  // namespace

TEST(VulkanFaults, NoDriverGivesAClearMessage) {
    const fs::path png = qp::test::testOutputDir() / "hardening_no_driver.png";
    fs::remove(png);
    const CommandRun run = runQuadplan("VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json", renderArgs(png));
    EXPECT_EQ(run.exit, 1) << run.output;
    EXPECT_NE(run.output.find("no Vulkan driver was found (for the CPU renderer install mesa-vulkan-drivers"),
              std::string::npos)
        << run.output;
    EXPECT_FALSE(fs::exists(png));
}

TEST(VulkanFaults, NoMatchingDeviceGivesAClearMessage) {
    if (!fs::exists(qp::test::kLavapipeIcd)) GTEST_SKIP() << "lavapipe is not installed";
    const fs::path png = qp::test::testOutputDir() / "hardening_no_device.png";
    fs::remove(png);
    const CommandRun run = runQuadplan(std::string("VK_ICD_FILENAMES=") + qp::test::kLavapipeIcd +
                                    " QUADPLAN_VK_DEVICE=no-such-gpu",
                                renderArgs(png));
    EXPECT_EQ(run.exit, 1) << run.output;
    EXPECT_NE(run.output.find("no usable Vulkan device"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("its name does not contain 'no-such-gpu'"), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(png));
}

TEST(PluginFaults, MissingPluginDirectory) {
    const CommandRun run = runQuadplan("", "schemes --plugin-dir /nonexistent/quadplan-plugins");
    EXPECT_EQ(run.exit, 1) << run.output;
    EXPECT_NE(run.output.find("the scheme plugin directory /nonexistent/quadplan-plugins does not exist"), std::string::npos)
        << run.output;
}

// The loader's own tests (test_schemes.cpp) check every broken variant; here the command a
// user runs reports them and still offers the good scheme.
TEST(PluginFaults, BrokenPluginsAreNamedAndTheRestWorks) {
    const CommandRun run = runQuadplan("", std::string("schemes --plugin-dir '") + QUADPLAN_TEST_PLUGIN_DIR + "'");
    EXPECT_EQ(run.exit, 0) << run.output;
    EXPECT_NE(run.output.find("test-flat"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("has no entry point 'quadplan_scheme_module': it is not a Quadplan scheme"), std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("undefined symbol: quadplan_test_symbol_nobody_defines"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("rebuild the plugin against this quadplan"), std::string::npos) << run.output;
}

// A file that is not a shared library at all, under a plugin's name.
TEST(PluginFaults, AFileThatIsNotALibrary) {
    const fs::path dir = qp::test::testOutputDir() / "hardening_garbage_plugin";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::FILE* f = std::fopen((dir / "quadplan-scheme-garbage.so").c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("this is not an ELF file\n", f);
    std::fclose(f);
    const CommandRun run = runQuadplan("", "schemes --plugin-dir '" + dir.string() + "'");
    EXPECT_EQ(run.exit, 1) << run.output;
    EXPECT_NE(run.output.find("quadplan-scheme-garbage.so"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("not loaded"), std::string::npos) << run.output;
}
