// Parsing an automation script (automation.h runs it): text in, checked commands out. Kept
// apart from the runner so it needs no window, GPU or ImGui: the fuzz target
// (tests/fuzz/fuzz_automation.cpp) drives it directly.
//
// Contract of a successful parse, for every command: the name is a known command; it has at
// least its required arguments and at most all of them; every whole-number argument is in
// [0, kMaxAutomationInt] and every number is finite with magnitude at most kMaxAutomationNumber
// (so the runner's conversions to int, uint32_t and milliseconds cannot overflow); key, mouse
// button and enumeration words are ones the runner knows.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <optional>

#include "edit/selection.h"
#include "mesh/result.h"
#include "mesh/topology.h"

namespace qp::editor {

struct AutomationCommand {
    int line = 0;
    std::string name;
    std::vector<std::string> args;
};

inline constexpr long kMaxAutomationInt = 1'000'000'000;
inline constexpr float kMaxAutomationNumber = 1e9f;

// The words the parser checks against a table that lives with the editor's actions. (Colour
// modes are checked when the command runs: they depend on the viewport's scheme.)
struct AutomationVocabulary {
    std::function<bool(std::string_view)> isAction;
};

// Checks every command's name and arguments; the message names the line at fault.
Result<std::vector<AutomationCommand>> parseAutomation(std::string_view text, const std::string& source,
                                                       const AutomationVocabulary& words);

// GLFW key code for "a", "F5", "kp1", "esc", "ctrl", ...; -1 when unknown.
int automationKeyCode(std::string_view name);
// 0 left, 1 right, 2 middle; -1 when unknown.
int automationMouseButton(std::string_view name);

// Words of the selection commands: "vertex"/"vertices", "edge(s)", "face(s)"; "replace", "add",
// "toggle", "remove"; element lists "1,2,3" (vertices, faces) or "1-2,2-3" (edges).
std::optional<SelectionMode> parseSelectionModeWord(const std::string& word);
std::optional<SelectOp> parseSelectOpWord(const std::string& word);
struct ElementList {
    std::vector<uint32_t> indices;
    std::vector<EdgeKey> edges;
};
std::optional<ElementList> parseElementList(const std::string& text, SelectionMode mode);
const char* selectionModeWord(SelectionMode mode);

}  // namespace qp::editor
