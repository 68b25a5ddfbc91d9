// Regression tests for what the hardening work (issue 9, docs/hardening.md) found in the text
// entry points: the automation parser accepted numbers its runner could not convert (1e30
// seconds or frames overflowed int), and a sculpt stroke with a tiny spacing on a long path
// ran for hours.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdio>

#include <sys/wait.h>

#include "automation_script.h"
#include "displacement/sculpt_script.h"

using namespace qp;
using namespace qp::editor;

namespace {

const AutomationVocabulary kAnyWord{[](std::string_view) { return true; }};

std::string parseError(const std::string& script) {
    auto parsed = parseAutomation(script, "s", kAnyWord);
    return parsed ? std::string() : parsed.error().message;
}

}  // namespace

TEST(AutomationParserLimits, RefusesNumbersTheRunnerCannotConvert) {
    const std::pair<const char*, const char*> cases[] = {
        {"select-vertex 99999999999\n", "s:1: select-vertex: '99999999999' is not a whole number from 0 to 1000000000"},
        {"wait-frames 4294967296\n", "'4294967296' is not a whole number"},
        {"resize 100 1000000001\n", "'1000000001' is not a whole number"},
        {"wait-file x.json 1e30\n", "'1e30' is not a number from -1e9 to 1e9"},
        {"set-tessellation uniform 1e30\n", "'1e30' is not a number"},
        {"move-selection 0 0 -2e9\n", "'-2e9' is not a number"},
        {"scroll inf\n", "'inf' is not a number"},
    };
    for (auto [script, expected] : cases)
        EXPECT_NE(parseError(script).find(expected), std::string::npos) << script << " -> " << parseError(script);
    // The limits themselves are accepted.
    EXPECT_EQ(parseError("select-vertex 1000000000\nmove-selection 1e9 -1e9 0\nwait-file x 1e9\n"), "");
}

TEST(AutomationParserLimits, ParsesWithoutAWindow) {
    auto parsed = parseAutomation("key ctrl\nmouse-down left # comment\nlog  two words \n", "s", kAnyWord);
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    ASSERT_EQ(parsed->size(), 3u);
    EXPECT_EQ((*parsed)[2].args, std::vector<std::string>{"two words"});
    EXPECT_GE(automationKeyCode("ctrl"), 0);
    EXPECT_EQ(automationMouseButton("left"), 0);
    EXPECT_LT(automationKeyCode("hyper"), 0);
}

TEST(StrokeLimits, RefusesAStrokeWithTooManyDabs) {
    auto strokes = parseStrokeFile(
        R"({"strokes": [{"brush": "raise", "radius": 1e-20, "strength": 0.1, "path": [[0,0,0], [1e20,0,0]]}]})", "s.json");
    ASSERT_FALSE(strokes.ok());
    EXPECT_NE(strokes.error().message.find("s.json: strokes[0].path: the path is"), std::string::npos)
        << strokes.error().message;
    EXPECT_NE(strokes.error().message.find("dabs"), std::string::npos) << strokes.error().message;
    // A long but reasonable stroke is fine: 4 / (0.25 * 0.01) = 1600 dabs.
    EXPECT_TRUE(parseStrokeFile(R"({"strokes": [{"brush": "raise", "radius": 0.01, "strength": 0.1,
                                   "path": [[0,0,0], [4,0,0]]}]})", "ok.json").ok());
}

// Before the limit this command did not finish within 20 s (measured: killed by timeout).
TEST(StrokeLimits, HeadlessSculptRefusesItQuickly) {
    const std::string command = std::string("'") + QUADPLAN_BINARY + "' sculpt '" + QUADPLAN_SCENES_DIR +
                                "/creased_box.json' --radius 1e-20 --strength 0.1 --path '0,1.2,0;1e20,1.2,0' "
                                "--out /nonexistent-dir/never.json 2>&1";
    const auto start = std::chrono::steady_clock::now();
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    std::array<char, 4096> buffer;
    for (size_t n; (n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0;) output.append(buffer.data(), n);
    const int raw = pclose(pipe);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) != 0) << output;
    EXPECT_NE(output.find("--path: the path is"), std::string::npos) << output;
    EXPECT_LT(seconds, 30.0);
}
