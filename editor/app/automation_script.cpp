#include "automation_script.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <GLFW/glfw3.h>

namespace qp::editor {

namespace {

enum class Arg { Int, Float, Word, Text };  // Text: the rest of the line

struct CommandSpec {
    const char* name;
    std::vector<Arg> required;
    std::vector<Arg> optional;
};

const std::vector<CommandSpec> kCommands = {
    {"wait-frames", {Arg::Int}, {}},
    {"wait-idle", {}, {}},
    {"wait-file", {Arg::Word}, {Arg::Float}},
    {"action", {Arg::Word}, {}},
    {"click-button", {Arg::Text}, {}},
    {"open", {Arg::Text}, {}},
    {"save", {}, {}},
    {"save-as", {Arg::Text}, {}},
    {"quit", {}, {}},
    {"select-vertex", {Arg::Int}, {Arg::Word}},
    {"select-edge", {Arg::Int, Arg::Int}, {}},
    {"clear-selection", {}, {}},
    {"move-selection", {Arg::Float, Arg::Float, Arg::Float}, {}},
    {"set-edge-sharpness", {Arg::Int, Arg::Int, Arg::Float}, {}},
    {"undo", {}, {}},
    {"redo", {}, {}},
    {"set-viewports", {Arg::Int}, {}},
    {"set-scheme", {Arg::Int, Arg::Word}, {}},
    {"set-color-by", {Arg::Int, Arg::Word}, {}},
    {"set-link", {Arg::Int, Arg::Word}, {}},
    {"set-tessellation", {Arg::Word, Arg::Float}, {}},
    {"set-draw-path", {Arg::Word}, {}},
    {"mouse-move", {Arg::Float, Arg::Float}, {}},
    {"mouse-down", {Arg::Word}, {}},
    {"mouse-up", {Arg::Word}, {}},
    {"scroll", {Arg::Float}, {}},
    {"key-down", {Arg::Word}, {}},
    {"key-up", {Arg::Word}, {}},
    {"key", {Arg::Word}, {}},
    {"resize", {Arg::Int, Arg::Int}, {}},
    {"screenshot", {Arg::Text}, {}},
    {"dump-state", {Arg::Text}, {}},
    {"measure-frames", {Arg::Int, Arg::Word}, {Arg::Word}},
    {"log", {}, {Arg::Text}},
    {"simulate-device-loss", {}, {}},
};

}  // namespace

int automationKeyCode(std::string_view name) {
    std::string n(name);
    std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (n.size() == 1 && n[0] >= 'a' && n[0] <= 'z') return GLFW_KEY_A + (n[0] - 'a');
    if (n.size() == 1 && n[0] >= '0' && n[0] <= '9') return GLFW_KEY_0 + (n[0] - '0');
    if (n.size() == 3 && n.rfind("kp", 0) == 0 && n[2] >= '0' && n[2] <= '9') return GLFW_KEY_KP_0 + (n[2] - '0');
    if (n.size() >= 2 && n[0] == 'f' && std::isdigit((unsigned char)n[1])) {
        const int k = std::atoi(n.c_str() + 1);
        if (k >= 1 && k <= 12) return GLFW_KEY_F1 + k - 1;
    }
    static const std::pair<const char*, int> named[] = {
        {"esc", GLFW_KEY_ESCAPE}, {"escape", GLFW_KEY_ESCAPE}, {"home", GLFW_KEY_HOME}, {"enter", GLFW_KEY_ENTER},
        {"tab", GLFW_KEY_TAB},    {"space", GLFW_KEY_SPACE},   {"delete", GLFW_KEY_DELETE},
        {"alt", GLFW_KEY_LEFT_ALT}, {"ctrl", GLFW_KEY_LEFT_CONTROL}, {"shift", GLFW_KEY_LEFT_SHIFT}};
    for (auto [text, code] : named)
        if (n == text) return code;
    return -1;
}

int automationMouseButton(std::string_view name) {
    if (name == "left") return 0;
    if (name == "right") return 1;
    if (name == "middle") return 2;
    return -1;
}

namespace {

bool isNumber(const std::string& text, bool integer) {
    if (text.empty()) return false;
    char* end = nullptr;
    errno = 0;
    if (integer) {
        const long v = std::strtol(text.c_str(), &end, 10);
        return *end == '\0' && errno == 0 && v >= 0 && v <= kMaxAutomationInt;
    }
    const float v = std::strtof(text.c_str(), &end);
    return *end == '\0' && std::isfinite(v) && std::fabs(v) <= kMaxAutomationNumber;
}

// Extra checks that need no app: enumerations and key names.
std::string checkWords(const AutomationCommand& c, const AutomationVocabulary& words) {
    const std::string& name = c.name;
    if (name == "action" && !words.isAction(c.args[0])) return "unknown action '" + c.args[0] + "' (see docs/editor.md)";
    if ((name == "mouse-down" || name == "mouse-up") && automationMouseButton(c.args[0]) < 0)
        return "mouse button must be left, middle or right";
    if ((name == "key-down" || name == "key-up" || name == "key") && automationKeyCode(c.args[0]) < 0)
        return "unknown key '" + c.args[0] + "'";
    if (name == "select-vertex" && c.args.size() > 1 && c.args[1] != "add") return "the optional word must be 'add'";
    if (name == "set-color-by" && !words.isColorMode(c.args[1])) return "colour mode must be shading, node-kind, depth or sharpness";
    if (name == "set-link" && c.args[1] != "linked" && c.args[1] != "independent") return "use 'linked' or 'independent'";
    if (name == "set-tessellation" && c.args[0] != "uniform" && c.args[0] != "adaptive")
        return "use 'uniform FACTOR' or 'adaptive PIXELS'";
    if (name == "set-draw-path" && !words.isDrawPath(c.args[0])) return "draw path must be auto, tess or grid";
    if (name == "measure-frames" && c.args.size() > 2 && c.args[2] != "drag" && c.args[2] != "orbit")
        return "the optional mode must be 'drag' or 'orbit'";
    return {};
}

}  // namespace

Result<std::vector<AutomationCommand>> parseAutomation(std::string_view text, const std::string& source,
                                                       const AutomationVocabulary& vocabulary) {
    std::vector<AutomationCommand> commands;
    std::istringstream lines{std::string(text)};
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
        if (size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream words(line);
        AutomationCommand c;
        c.line = number;
        if (!(words >> c.name)) continue;
        auto spec = std::find_if(kCommands.begin(), kCommands.end(), [&](const CommandSpec& s) { return c.name == s.name; });
        auto where = [&] { return source + ":" + std::to_string(number) + ": "; };
        if (spec == kCommands.end()) return Error{where() + "unknown command '" + c.name + "'"};
        std::vector<Arg> kinds = spec->required;
        kinds.insert(kinds.end(), spec->optional.begin(), spec->optional.end());
        for (size_t i = 0; i < kinds.size(); ++i) {
            std::string word;
            if (kinds[i] == Arg::Text) {
                std::getline(words >> std::ws, word);
                while (!word.empty() && std::isspace((unsigned char)word.back())) word.pop_back();
                if (word.size() >= 2 && word.front() == '"' && word.back() == '"') word = word.substr(1, word.size() - 2);
                if (word.empty()) break;
            } else if (!(words >> word)) {
                break;
            }
            if ((kinds[i] == Arg::Int || kinds[i] == Arg::Float) && !isNumber(word, kinds[i] == Arg::Int))
                return Error{where() + c.name + ": '" + word + "' is not " +
                             (kinds[i] == Arg::Int ? "a whole number from 0 to 1000000000" : "a number from -1e9 to 1e9")};
            c.args.push_back(word);
        }
        std::string extra;
        if (words >> extra) return Error{where() + c.name + ": unexpected '" + extra + "'"};
        if (c.args.size() < spec->required.size())
            return Error{where() + c.name + " needs " + std::to_string(spec->required.size()) + " argument(s)"};
        if (std::string problem = checkWords(c, vocabulary); !problem.empty()) return Error{where() + c.name + ": " + problem};
        commands.push_back(std::move(c));
    }
    return commands;
}

}  // namespace qp::editor
