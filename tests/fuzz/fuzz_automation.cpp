// libFuzzer target: the editor's automation-script parser (editor/app/automation_script.h) on
// arbitrary text. Besides crashes and sanitizer reports it checks the parser's contract: every
// accepted command is known, has an allowed number of arguments, and its numbers are in the
// ranges the runner converts without overflow.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "actions.h"
#include "automation_script.h"

namespace {

bool isOneOf(std::string_view word, std::initializer_list<std::string_view> names) {
    for (std::string_view n : names)
        if (word == n) return true;
    return false;
}

// The real actions table.
const qp::editor::AutomationVocabulary kWords{[](std::string_view id) { return qp::editor::findAction(id) != nullptr; }};

// A number the runner converts without overflow (automation_script.h).
bool checkNumber(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    return *end == '\0' && std::isfinite(v) && std::fabs(v) <= double(qp::editor::kMaxAutomationNumber);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto parsed = qp::editor::parseAutomation(text, "fuzz.txt", kWords);
    if (!parsed) {
        if (parsed.error().message.rfind("fuzz.txt:", 0) != 0) std::abort();  // errors name the line
        return 0;
    }
    for (const qp::editor::AutomationCommand& c : *parsed) {
        if (c.name.empty() || c.line < 1) std::abort();
        for (const std::string& a : c.args)
            if (a.empty()) std::abort();
        if (isOneOf(c.name, {"wait-frames", "set-viewports"}) && (c.args.size() != 1 || !checkNumber(c.args[0])))
            std::abort();
        if (isOneOf(c.name, {"select-edge", "resize"})) {
            if (c.args.size() != 2) std::abort();
            for (const std::string& a : c.args)
                if (std::strtol(a.c_str(), nullptr, 10) > qp::editor::kMaxAutomationInt) std::abort();
        }
        if (c.name == "move-selection" && (c.args.size() != 3 || !checkNumber(c.args[0]) || !checkNumber(c.args[2])))
            std::abort();
        if (c.name == "wait-file" && c.args.size() == 2 && !checkNumber(c.args[1])) std::abort();
        if (c.name == "set-tessellation" && !checkNumber(c.args[1])) std::abort();
        if (isOneOf(c.name, {"mouse-down", "mouse-up"}) && qp::editor::automationMouseButton(c.args[0]) < 0) std::abort();
        if (isOneOf(c.name, {"key", "key-down", "key-up"}) && qp::editor::automationKeyCode(c.args[0]) < 0) std::abort();
    }
    return 0;
}
