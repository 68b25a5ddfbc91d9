#include "displacement/sculpt_script.h"

#include <cfloat>
#include <charconv>
#include <cmath>
#include <set>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <nlohmann/json.hpp>

namespace qp {

namespace {

using json = nlohmann::json;

struct FieldError {
    std::string field, message;
};

[[noreturn]] void fail(const std::string& field, std::string message) { throw FieldError{field, std::move(message)}; }

std::string describe(const json& value) {
    return std::string(value.is_array() || value.is_object() ? "an " : "a ") + value.type_name();
}

float readFloat(const json& value, const std::string& field) {
    if (!value.is_number()) fail(field, "expected a number, got " + describe(value));
    double number = value.get<double>();
    if (!std::isfinite(number) || std::fabs(number) > double(FLT_MAX)) fail(field, "number " + value.dump() + " is too large");
    return float(number);
}

std::string readString(const json& value, const std::string& field) {
    if (!value.is_string()) fail(field, "expected a string, got " + describe(value));
    return value.get<std::string>();
}

template <class E>
E readName(const json& value, const std::string& field, std::optional<E> (*fromName)(std::string_view), const char* choices) {
    std::string name = readString(value, field);
    std::optional<E> e = fromName(name);
    if (!e) fail(field, "unknown value \"" + name + "\"; expected one of " + choices);
    return *e;
}

ScriptedStroke readWholeMaskStep(const json& value, const std::string& field) {
    if (value.size() != 1) fail(field, "a \"mask\" step has no other fields");
    const std::string step = readString(value["mask"], field + ".mask");
    if (step != "invert" && step != "clear") fail(field + ".mask", "unknown value \"" + step + "\"; expected \"invert\" or \"clear\"");
    ScriptedStroke out;
    out.wholeMask = step == "invert" ? WholeMaskStep::Invert : WholeMaskStep::Clear;
    return out;
}

ScriptedStroke readStroke(const json& value, const std::string& field) {
    if (!value.is_object()) fail(field, "expected an object, got " + describe(value));
    if (value.contains("mask")) return readWholeMaskStep(value, field);
    static const std::set<std::string> known = {"brush", "radius", "strength", "falloff", "mirror", "spacing", "path"};
    for (const auto& [key, v] : value.items())
        if (!known.count(key)) fail(field + "." + key, "unknown field (a typo?)");
    for (const char* key : {"brush", "radius", "strength", "path"})
        if (!value.contains(key)) fail(field + "." + key, "required field is missing");
    ScriptedStroke stroke;
    Brush& brush = stroke.options.brush;
    brush.kind = readName<BrushKind>(value["brush"], field + ".brush", brushKindFromName,
                                     "\"raise\", \"lower\", \"smooth\", \"flatten\", \"erase\", \"inflate\", \"crease\", "
                                     "\"mask\", \"unmask\"");
    brush.radius = readFloat(value["radius"], field + ".radius");
    brush.strength = readFloat(value["strength"], field + ".strength");
    if (value.contains("falloff"))
        brush.falloff = readName<Falloff>(value["falloff"], field + ".falloff", falloffFromName,
                                          "\"smooth\", \"linear\", \"constant\", \"sphere\"");
    if (value.contains("mirror"))
        stroke.options.mirror =
            readName<MirrorAxis>(value["mirror"], field + ".mirror", mirrorAxisFromName, "\"none\", \"x\", \"y\", \"z\"");
    if (value.contains("spacing")) {
        stroke.options.spacing = readFloat(value["spacing"], field + ".spacing");
        if (stroke.options.spacing < 0.0f) fail(field + ".spacing", "must be >= 0 (0: a quarter of the radius)");
    }
    if (Status valid = validateBrush(brush); !valid) fail(field, valid.error().message);
    const json& path = value["path"];
    if (!path.is_array()) fail(field + ".path", "expected an array of [x, y, z] points, got " + describe(path));
    if (path.empty()) fail(field + ".path", "needs at least one point");
    for (size_t i = 0; i < path.size(); ++i) {
        const std::string at = field + ".path[" + std::to_string(i) + "]";
        if (!path[i].is_array() || path[i].size() != 3) fail(at, "expected [x, y, z], got " + path[i].dump());
        stroke.path.push_back({readFloat(path[i][0], at + "[0]"), readFloat(path[i][1], at + "[1]"),
                               readFloat(path[i][2], at + "[2]")});
    }
    if (Status fits = checkStrokeLength(stroke); !fits) fail(field + ".path", fits.error().message);
    return stroke;
}

}  // namespace

Status checkStrokeLength(const ScriptedStroke& stroke) {
    const double spacing = stroke.options.spacing > 0.0f ? stroke.options.spacing : 0.25 * stroke.options.brush.radius;
    double length = 0.0;
    for (size_t i = 1; i < stroke.path.size(); ++i)
        length += glm::length(glm::dvec3(stroke.path[i]) - glm::dvec3(stroke.path[i - 1]));
    const double dabs = length / spacing;
    if (!(dabs <= kMaxDabsPerStroke))
        return Error{"the path is " + std::to_string(length) + " long, which at a dab spacing of " + std::to_string(spacing) +
                     " makes more than " + std::to_string(int64_t(kMaxDabsPerStroke)) +
                     " dabs; use a larger spacing or radius, or a shorter path"};
    return success();
}

Result<std::vector<glm::vec3>> parsePath(std::string_view text) {
    std::vector<glm::vec3> points;
    size_t start = 0;
    while (start <= text.size()) {
        size_t end = text.find(';', start);
        if (end == std::string_view::npos) end = text.size();
        std::string_view point = text.substr(start, end - start);
        const std::string where = "point " + std::to_string(points.size() + 1) + " (\"" + std::string(point) + "\")";
        glm::vec3 p;
        size_t at = 0;
        for (int axis = 0; axis < 3; ++axis) {
            while (at < point.size() && point[at] == ' ') ++at;
            auto [next, ec] = std::from_chars(point.data() + at, point.data() + point.size(), p[axis]);
            if (ec != std::errc() || !std::isfinite(p[axis]))
                return Error{where + " needs three finite numbers x,y,z"};
            at = size_t(next - point.data());
            while (at < point.size() && point[at] == ' ') ++at;
            if (axis < 2) {
                if (at >= point.size() || point[at] != ',') return Error{where + " needs three numbers separated by commas"};
                ++at;
            }
        }
        if (at != point.size()) return Error{where + " has more than three numbers"};
        points.push_back(p);
        start = end + 1;
        if (end == text.size()) break;
    }
    return points;
}

Result<std::vector<ScriptedStroke>> parseStrokeFile(std::string_view text, const std::string& source) {
    json root;
    try {
        root = json::parse(text);
    } catch (const json::exception& e) {
        return Error{source + ": invalid JSON: " + e.what()};
    }
    try {
        if (!root.is_object() || !root.contains("strokes"))
            fail("strokes", "required field is missing (the file is {\"strokes\": [...]})");
        const json& strokes = root["strokes"];
        if (!strokes.is_array()) fail("strokes", "expected an array, got " + describe(strokes));
        std::vector<ScriptedStroke> out;
        for (size_t i = 0; i < strokes.size(); ++i) out.push_back(readStroke(strokes[i], "strokes[" + std::to_string(i) + "]"));
        return out;
    } catch (const FieldError& e) {
        return Error{source + ": " + e.field + ": " + e.message};
    }
}

}  // namespace qp
