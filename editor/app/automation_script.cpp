#include "automation_script.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <GLFW/glfw3.h>

#include "displacement/brush.h"

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
    {"wait-seconds", {Arg::Float}, {}},
    {"wait-file", {Arg::Word}, {Arg::Float}},
    {"action", {Arg::Word}, {}},
    {"click-button", {Arg::Text}, {}},
    {"open", {Arg::Text}, {}},
    {"save", {}, {}},
    {"save-as", {Arg::Text}, {}},
    {"quit", {}, {}},
    {"autosave", {}, {}},
    {"select-vertex", {Arg::Int}, {Arg::Word}},
    {"select-edge", {Arg::Int, Arg::Int}, {}},
    {"clear-selection", {}, {}},
    {"select-mode", {Arg::Word}, {}},
    {"select", {Arg::Word, Arg::Word}, {Arg::Word}},
    {"box-select", {Arg::Int, Arg::Float, Arg::Float, Arg::Float, Arg::Float}, {Arg::Word}},
    {"move-selection", {Arg::Float, Arg::Float, Arg::Float}, {}},
    {"set-tool", {Arg::Word}, {}},
    {"brush", {Arg::Word, Arg::Float, Arg::Float}, {Arg::Word, Arg::Word}},
    {"displacement-resolution", {Arg::Int}, {}},
    {"clear-displacement", {}, {}},
    {"set-space", {Arg::Word}, {}},
    {"transform", {Arg::Word, Arg::Float, Arg::Float, Arg::Float}, {Arg::Float}},
    {"extrude", {}, {Arg::Float}},
    {"delete", {}, {}},
    {"split", {}, {}},
    {"loop", {}, {Arg::Int, Arg::Int, Arg::Float}},
    {"merge", {}, {Arg::Word}},
    {"make-face", {}, {}},
    {"crease", {Arg::Float}, {}},
    {"corner", {Arg::Float}, {}},
    {"hole", {Arg::Word}, {}},
    {"crease-method", {Arg::Word}, {}},
    {"set-edge-sharpness", {Arg::Int, Arg::Int, Arg::Float}, {}},
    {"set-frame", {Arg::Float}, {}},
    {"play", {}, {}},
    {"pause", {}, {}},
    {"insert-key", {}, {}},
    {"set-interpolation", {Arg::Word}, {}},
    {"undo", {}, {}},
    {"redo", {}, {}},
    {"jump-history", {Arg::Int}, {}},
    {"set-viewports", {Arg::Int}, {}},
    {"set-scheme", {Arg::Int, Arg::Word}, {}},
    {"set-color-by", {Arg::Int, Arg::Word}, {}},
    {"set-cull", {Arg::Int, Arg::Word}, {}},
    {"set-link", {Arg::Int, Arg::Word}, {}},
    {"heatmap", {Arg::Int, Arg::Word}, {}},
    {"set-tessellation", {Arg::Word, Arg::Float}, {}},
    {"set-plans-path", {Arg::Word}, {}},
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
    {"time-frame", {Arg::Word, Arg::Text}, {}},
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
        {"tab", GLFW_KEY_TAB},    {"space", GLFW_KEY_SPACE},   {"delete", GLFW_KEY_DELETE}, {"backspace", GLFW_KEY_BACKSPACE},
        {"period", GLFW_KEY_PERIOD}, {"comma", GLFW_KEY_COMMA}, {"kpadd", GLFW_KEY_KP_ADD}, {"kpsubtract", GLFW_KEY_KP_SUBTRACT},
        {"alt", GLFW_KEY_LEFT_ALT}, {"ctrl", GLFW_KEY_LEFT_CONTROL}, {"shift", GLFW_KEY_LEFT_SHIFT},
        {"left", GLFW_KEY_LEFT}, {"right", GLFW_KEY_RIGHT}, {"up", GLFW_KEY_UP}, {"down", GLFW_KEY_DOWN}};
    for (auto [text, code] : named)
        if (n == text) return code;
    return -1;
}

std::optional<SelectionMode> parseSelectionModeWord(const std::string& word) {
    if (word == "vertex" || word == "vertices") return SelectionMode::Vertex;
    if (word == "edge" || word == "edges") return SelectionMode::Edge;
    if (word == "face" || word == "faces") return SelectionMode::Face;
    return std::nullopt;
}

std::optional<SelectOp> parseSelectOpWord(const std::string& word) {
    if (word == "replace") return SelectOp::Replace;
    if (word == "add") return SelectOp::Add;
    if (word == "toggle") return SelectOp::Toggle;
    if (word == "remove") return SelectOp::Remove;
    return std::nullopt;
}

std::optional<ElementList> parseElementList(const std::string& text, SelectionMode mode) {
    ElementList list;
    std::istringstream items(text);
    std::string item;
    while (std::getline(items, item, ',')) {
        const size_t dash = item.find('-');
        if ((mode == SelectionMode::Edge) != (dash != std::string::npos)) return std::nullopt;
        auto index = [](const std::string& t) -> std::optional<uint32_t> {
            // At most 9 digits: within [0, kMaxAutomationInt] like every other whole number.
            if (t.empty() || t.size() > 9 || t.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
            return uint32_t(std::strtoul(t.c_str(), nullptr, 10));
        };
        if (mode == SelectionMode::Edge) {
            std::optional<uint32_t> a = index(item.substr(0, dash)), b = index(item.substr(dash + 1));
            if (!a || !b) return std::nullopt;
            list.edges.push_back(makeEdgeKey(*a, *b));
        } else {
            std::optional<uint32_t> i = index(item);
            if (!i) return std::nullopt;
            list.indices.push_back(*i);
        }
    }
    if (list.indices.empty() && list.edges.empty()) return std::nullopt;
    return list;
}

const char* selectionModeWord(SelectionMode mode) {
    return mode == SelectionMode::Vertex ? "vertex" : mode == SelectionMode::Edge ? "edge" : "face";
}

int automationMouseButton(std::string_view name) {
    if (name == "left") return 0;
    if (name == "right") return 1;
    if (name == "middle") return 2;
    return -1;
}

namespace {

bool isOneOf(const std::string& word, std::initializer_list<const char*> choices) {
    for (const char* c : choices)
        if (word == c) return true;
    return false;
}

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
    if (name == "set-link" && c.args[1] != "linked" && c.args[1] != "independent") return "use 'linked' or 'independent'";
    if (name == "set-tessellation" && c.args[0] != "uniform" && c.args[0] != "adaptive")
        return "use 'uniform FACTOR' or 'adaptive PIXELS'";
    if ((name == "set-draw-path" || name == "set-plans-path") && !isOneOf(c.args[0], {"auto", "tess", "grid", "cpu"}))
        return "the plans path must be auto, tess, grid or cpu";
    if ((name == "select-mode" || name == "select") && !parseSelectionModeWord(c.args[0])) return "the mode must be vertex, edge or face";
    if (name == "select" && !parseElementList(c.args[1], *parseSelectionModeWord(c.args[0])))
        return "list the elements separated by commas (edges as A-B): 1,2,3 or 1-2,2-3";
    if ((name == "select" && c.args.size() > 2) || (name == "box-select" && c.args.size() > 5))
        if (!parseSelectOpWord(c.args.back())) return "the operation must be replace, add, toggle or remove";
    if (name == "set-tool" && !isOneOf(c.args[0], {"select", "move", "rotate", "scale", "sculpt"}))
        return "the tool must be select, move, rotate, scale or sculpt";
    if (name == "brush") {
        if (!brushKindFromName(c.args[0])) return "the brush must be raise, lower, smooth, flatten, erase, inflate, crease, mask or unmask";
        if (c.args.size() > 3 && !falloffFromName(c.args[3])) return "the falloff must be smooth, linear, constant or sphere";
        if (c.args.size() > 4 && !mirrorAxisFromName(c.args[4])) return "the mirror axis must be none, x, y or z";
    }
    if (name == "set-space" && !isOneOf(c.args[0], {"world", "local"})) return "the space must be world or local";
    if (name == "transform" && !isOneOf(c.args[0], {"move", "rotate", "scale"}))
        return "use 'transform move X Y Z', 'transform rotate AX AY AZ DEGREES' or 'transform scale X Y Z'";
    if (name == "transform" && (c.args[0] == "rotate") != (c.args.size() == 5))
        return "rotate takes an axis and degrees; move and scale take three numbers";
    if (name == "loop" && c.args.size() == 1) return "give both vertices of the edge (and optionally the fraction)";
    if (name == "merge" && !c.args.empty() && !isOneOf(c.args[0], {"centroid", "last"})) return "merge at 'centroid' or 'last'";
    if ((name == "hole" || name == "heatmap") && !isOneOf(c.args.back(), {"on", "off"})) return "use 'on' or 'off'";
    if (name == "crease-method" && !isOneOf(c.args[0], {"normal", "chaikin"})) return "the crease method must be normal or chaikin";
    if (name == "set-interpolation" && !isOneOf(c.args[0], {"linear", "catmull-rom"}))
        return "the interpolation must be linear or catmull-rom";
    if (name == "measure-frames" && c.args.size() > 2 && !isOneOf(c.args[2], {"drag", "orbit", "sculpt"}))
        return "the optional mode must be 'drag', 'orbit' or 'sculpt'";
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
