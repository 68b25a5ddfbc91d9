#include "scene.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <span>
#include <utility>

#include <glm/geometric.hpp>

#include "displacement_io.h"
#include "file_io.h"
#include "obj_io.h"

namespace qp {

namespace {

using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;
namespace fs = std::filesystem;

constexpr const char* kFormatName = "quadplan-scene";
constexpr int kMaxTessellationFactor = 64;

// ---------------------------------------------------------------------------------------------
// Names of enumerated values, shared by the reader and the writer.

template <class E>
struct EnumName {
    const char* name;
    E value;
};

constexpr EnumName<BoundaryInterpolation> kBoundaryNames[] = {
    {"edges-and-corners", BoundaryInterpolation::EdgesAndCorners},
    {"edges-only", BoundaryInterpolation::EdgesOnly},
    {"none", BoundaryInterpolation::None}};
constexpr EnumName<CreaseMethod> kCreaseMethodNames[] = {
    {"normal", CreaseMethod::Normal}, {"chaikin", CreaseMethod::Chaikin}};
constexpr EnumName<TriangleSubdivision> kTriangleNames[] = {
    {"catmark", TriangleSubdivision::Catmark}, {"smooth", TriangleSubdivision::Smooth}};
constexpr EnumName<FVarInterpolation> kFVarNames[] = {
    {"none", FVarInterpolation::None},
    {"corners-only", FVarInterpolation::CornersOnly},
    {"corners-plus1", FVarInterpolation::CornersPlus1},
    {"corners-plus2", FVarInterpolation::CornersPlus2},
    {"boundaries", FVarInterpolation::Boundaries},
    {"all", FVarInterpolation::All}};
constexpr EnumName<Projection> kProjectionNames[] = {
    {"perspective", Projection::Perspective}, {"orthographic", Projection::Orthographic}};
constexpr EnumName<CameraLink> kCameraLinkNames[] = {
    {"linked", CameraLink::Linked}, {"independent", CameraLink::Independent}};
constexpr EnumName<TessellationMode> kTessellationModeNames[] = {
    {"uniform", TessellationMode::Uniform}, {"adaptive", TessellationMode::Adaptive}};
constexpr EnumName<UpAxis> kUpAxisNames[] = {{"y", UpAxis::Y}, {"z", UpAxis::Z}};
constexpr EnumName<Shading> kShadingNames[] = {{"studio", Shading::Studio}, {"matcap", Shading::Matcap}};

template <class E>
const char* enumName(std::span<const EnumName<E>> names, E value) {
    for (const EnumName<E>& n : names)
        if (n.value == value) return n.name;
    assert(false && "enum value missing from its name table");
    return "";
}

// ---------------------------------------------------------------------------------------------
// Reading. The readers throw FieldError, caught once in parseScene: every check would
// otherwise need an early return through several levels of nested objects.

struct FieldError {
    std::string field;  // JSON path such as "cage.faces[12][3]"; empty for the whole document
    std::string message;
};

[[noreturn]] void fail(const std::string& field, std::string message) {
    throw FieldError{field, std::move(message)};
}

std::string member(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}

std::string element(const std::string& path, size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

std::string describe(const json& value) {
    return std::string(value.is_array() || value.is_object() ? "an " : "a ") + value.type_name();
}

// A JSON object being read: remembers which fields were looked at, so that the rest can be
// reported as unknown (usually a typo, or a field from a newer Quadplan).
class ObjectReader {
public:
    ObjectReader(const json& value, std::string path) : value_(value), path_(std::move(path)) {
        if (!value.is_object())
            fail(path_, "expected an object, got " + describe(value));
    }

    const json* optional(const std::string& key) {
        seen_.insert(key);
        auto it = value_.find(key);
        return it == value_.end() ? nullptr : &*it;
    }

    const json& required(const std::string& key) {
        const json* value = optional(key);
        if (!value) fail(field(key), "required field is missing");
        return *value;
    }

    bool has(const std::string& key) const { return value_.contains(key); }
    std::string field(const std::string& key) const { return member(path_, key); }
    const std::string& path() const { return path_; }

    void warnAboutUnknownFields(const std::string& source, std::vector<std::string>* warnings) const {
        if (!warnings) return;
        for (const auto& [key, value] : value_.items())
            if (!seen_.count(key))
                warnings->push_back(source + ": " + field(key) + ": unknown field, ignored");
    }

private:
    const json& value_;
    std::string path_;
    std::set<std::string> seen_;
};

const json& readArray(const json& value, const std::string& field) {
    if (!value.is_array()) fail(field, "expected an array, got " + describe(value));
    return value;
}

float readFloat(const json& value, const std::string& field) {
    if (!value.is_number()) fail(field, "expected a number, got " + describe(value));
    double number = value.get<double>();
    // JSON has no NaN, but 1e300 (or 1e400, which parses as infinity) does not fit a float.
    if (!std::isfinite(number) || std::fabs(number) > double(FLT_MAX))
        fail(field, "number " + value.dump() + " is too large");
    return float(number);
}

float readPositiveFloat(const json& value, const std::string& field) {
    float number = readFloat(value, field);
    if (number <= 0.0f) fail(field, "must be greater than 0, got " + value.dump());
    return number;
}

float readSharpness(const json& value, const std::string& field) {
    float sharpness = readFloat(value, field);
    if (sharpness < 0.0f || sharpness > kInfiniteSharpness)
        fail(field, "sharpness " + value.dump() + " is outside [0, 10] (10 is infinitely sharp)");
    return sharpness;
}

int64_t readInteger(const json& value, const std::string& field) {
    if (!value.is_number_integer()) fail(field, "expected an integer, got " + describe(value));
    if (value.is_number_unsigned() && value.get<uint64_t>() > uint64_t(INT64_MAX))
        fail(field, "integer " + value.dump() + " is too large");
    return value.get<int64_t>();
}

int readIntInRange(const json& value, const std::string& field, int lo, int hi) {
    int64_t number = readInteger(value, field);
    if (number < lo || number > hi)
        fail(field, "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " +
                        std::to_string(number));
    return int(number);
}

// `what` names the indexed thing ("vertex"), `plural` its plural; `count` is how many there are.
uint32_t readIndex(const json& value, const std::string& field, const char* what, size_t count,
                   const char* plural) {
    int64_t index = readInteger(value, field);
    if (index < 0 || uint64_t(index) >= count)
        fail(field, std::string(what) + " index " + std::to_string(index) + " out of range (cage has " +
                        std::to_string(count) + " " + plural + ")");
    return uint32_t(index);
}

bool readBool(const json& value, const std::string& field) {
    if (!value.is_boolean()) fail(field, "expected true or false, got " + describe(value));
    return value.get<bool>();
}

std::string readName(const json& value, const std::string& field) {
    if (!value.is_string()) fail(field, "expected a string, got " + describe(value));
    std::string name = value.get<std::string>();
    if (name.empty()) fail(field, "must not be empty");
    return name;
}

template <class E>
E readEnum(const json& value, const std::string& field, std::span<const EnumName<E>> names) {
    std::string name = readName(value, field);
    std::string expected;
    for (const EnumName<E>& n : names) {
        if (name == n.name) return n.value;
        expected += (expected.empty() ? "\"" : ", \"") + std::string(n.name) + "\"";
    }
    fail(field, "unknown value \"" + name + "\"; expected one of " + expected);
}

template <int N>
glm::vec<N, float> readVector(const json& value, const std::string& field) {
    readArray(value, field);
    if (value.size() != N)
        fail(field, "expected " + std::to_string(N) + " numbers, got " + std::to_string(value.size()));
    glm::vec<N, float> result;
    for (int i = 0; i < N; ++i) result[i] = readFloat(value[i], element(field, i));
    return result;
}

struct Context {
    std::string source;
    std::string baseDir;
    std::vector<std::string>* warnings;
};

// --- the cage ---

std::vector<glm::vec3> readPositions(const json& value, const std::string& field) {
    std::vector<glm::vec3> positions;
    for (size_t i = 0; i < readArray(value, field).size(); ++i)
        positions.push_back(readVector<3>(value[i], element(field, i)));
    return positions;
}

void readFace(const json& value, const std::string& field, Cage& cage) {
    readArray(value, field);
    if (value.size() < 3)
        fail(field, "a face needs at least 3 vertices, got " + std::to_string(value.size()));
    std::vector<uint32_t> face;
    for (size_t i = 0; i < value.size(); ++i) {
        uint32_t v = readIndex(value[i], element(field, i), "vertex", cage.vertexCount(), "vertices");
        if (!face.empty() && face.back() == v)
            fail(element(field, i), "vertex " + std::to_string(v) + " follows itself (zero-length edge)");
        face.push_back(v);
    }
    if (face.front() == face.back())
        fail(element(field, value.size() - 1), "vertex " + std::to_string(face.back()) +
                                                   " closes the face onto itself (zero-length edge)");
    cage.addFace(face.data(), uint32_t(face.size()));
}

void readFaces(const json& value, const std::string& field, Cage& cage) {
    for (size_t f = 0; f < readArray(value, field).size(); ++f) readFace(value[f], element(field, f), cage);
}

std::set<std::pair<uint32_t, uint32_t>> collectEdges(const Cage& cage) {
    std::set<std::pair<uint32_t, uint32_t>> edges;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t* fv = cage.faceBegin(f);
        for (uint32_t i = 0, n = cage.faceSize(f); i < n; ++i)
            edges.insert(std::minmax(fv[i], fv[(i + 1) % n]));
    }
    return edges;
}

void readCreases(const json& value, const std::string& field, Cage& cage) {
    auto edges = collectEdges(cage);
    for (size_t i = 0; i < readArray(value, field).size(); ++i) {
        ObjectReader crease(value[i], element(field, i));
        const json& edge = readArray(crease.required("edge"), crease.field("edge"));
        if (edge.size() != 2)
            fail(crease.field("edge"), "expected 2 vertex indices, got " + std::to_string(edge.size()));
        uint32_t a = readIndex(edge[0], element(crease.field("edge"), 0), "vertex", cage.vertexCount(), "vertices");
        uint32_t b = readIndex(edge[1], element(crease.field("edge"), 1), "vertex", cage.vertexCount(), "vertices");
        if (!edges.count(std::minmax(a, b)))
            fail(crease.field("edge"), "no face has an edge between vertices " + std::to_string(a) + " and " +
                                           std::to_string(b));
        float sharpness = readSharpness(crease.required("sharpness"), crease.field("sharpness"));
        cage.creases.push_back({a, b, sharpness});
    }
}

void readCorners(const json& value, const std::string& field, Cage& cage) {
    for (size_t i = 0; i < readArray(value, field).size(); ++i) {
        ObjectReader corner(value[i], element(field, i));
        uint32_t v = readIndex(corner.required("vertex"), corner.field("vertex"), "vertex", cage.vertexCount(),
                               "vertices");
        float sharpness = readSharpness(corner.required("sharpness"), corner.field("sharpness"));
        cage.corners.push_back({v, sharpness});
    }
}

void readHoles(const json& value, const std::string& field, Cage& cage) {
    for (size_t i = 0; i < readArray(value, field).size(); ++i)
        cage.holes.push_back(readIndex(value[i], element(field, i), "face", cage.faceCount(), "faces"));
}

SubdivisionOptions readOptions(const json& value, const std::string& field, const Context& ctx) {
    ObjectReader object(value, field);
    SubdivisionOptions options;
    if (const json* v = object.optional("boundary"))
        options.boundary = readEnum<BoundaryInterpolation>(*v, object.field("boundary"), kBoundaryNames);
    if (const json* v = object.optional("crease_method"))
        options.creaseMethod = readEnum<CreaseMethod>(*v, object.field("crease_method"), kCreaseMethodNames);
    if (const json* v = object.optional("triangle_subdivision"))
        options.triangleSubdivision =
            readEnum<TriangleSubdivision>(*v, object.field("triangle_subdivision"), kTriangleNames);
    if (const json* v = object.optional("fvar_interpolation"))
        options.fvarInterpolation = readEnum<FVarInterpolation>(*v, object.field("fvar_interpolation"), kFVarNames);
    if (const json* v = object.optional("fvar_propagate_corners"))
        options.fvarPropagateCorners = readBool(*v, object.field("fvar_propagate_corners"));
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return options;
}

// "face_uvs" parallels "faces": one texture-coordinate index per face corner.
void readUVs(ObjectReader& object, Cage& cage) {
    const json* uvs = object.optional("uvs");
    const json* faceUVs = object.optional("face_uvs");
    if (!uvs && !faceUVs) return;
    if (!uvs || !faceUVs) fail(object.field(uvs ? "face_uvs" : "uvs"), "required when \"" +
                                   std::string(uvs ? "uvs" : "face_uvs") + "\" is given");
    for (size_t i = 0; i < readArray(*uvs, object.field("uvs")).size(); ++i)
        cage.uvs.push_back(readVector<2>((*uvs)[i], element(object.field("uvs"), i)));
    std::string field = object.field("face_uvs");
    if (readArray(*faceUVs, field).size() != cage.faceCount())
        fail(field, "has " + std::to_string(faceUVs->size()) + " entries but the cage has " +
                        std::to_string(cage.faceCount()) + " faces");
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const json& face = readArray((*faceUVs)[f], element(field, f));
        if (face.size() != cage.faceSize(f))
            fail(element(field, f), "has " + std::to_string(face.size()) + " indices but face " +
                                        std::to_string(f) + " has " + std::to_string(cage.faceSize(f)) + " vertices");
        for (size_t i = 0; i < face.size(); ++i)
            cage.faceUVIndices.push_back(
                readIndex(face[i], element(element(field, f), i), "texture coordinate", cage.uvs.size(), "uvs"));
    }
}

Cage readInlineCage(ObjectReader& object, const Context& ctx) {
    Cage cage;
    cage.positions = readPositions(object.required("positions"), object.field("positions"));
    readFaces(object.required("faces"), object.field("faces"), cage);
    if (const json* v = object.optional("creases")) readCreases(*v, object.field("creases"), cage);
    if (const json* v = object.optional("corners")) readCorners(*v, object.field("corners"), cage);
    if (const json* v = object.optional("holes")) readHoles(*v, object.field("holes"), cage);
    if (const json* v = object.optional("options")) cage.options = readOptions(*v, object.field("options"), ctx);
    readUVs(object, cage);
    return cage;
}

constexpr const char* kInlineOnlyFields[] = {"positions", "faces", "creases", "corners", "holes",
                                             "options", "uvs", "face_uvs"};

Cage readReferencedCage(ObjectReader& object, const Context& ctx, std::string& cagePath) {
    // Keeping tags in exactly one place (the OBJ) means there is nothing to merge or to
    // get out of sync when the OBJ is edited elsewhere.
    for (const char* key : kInlineOnlyFields)
        if (object.has(key))
            fail(object.field(key), "not allowed with \"path\": a referenced cage keeps its geometry and tags "
                                    "in the OBJ file");
    cagePath = readName(object.required("path"), object.field("path"));
    std::string resolved = (fs::path(ctx.baseDir) / cagePath).string();
    Result<Cage> cage = loadObj(resolved, ctx.warnings);
    if (!cage) fail(object.field("path"), "cannot load the referenced cage \"" + cagePath + "\": " + cage.error().message);
    return std::move(cage).value();
}

Cage readCage(const json& value, const Context& ctx, std::string& cagePath) {
    ObjectReader object(value, "cage");
    Cage cage = object.has("path") ? readReferencedCage(object, ctx, cagePath) : readInlineCage(object, ctx);
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    normalizeTags(cage);
    if (Status valid = validateCage(cage, ctx.source + ": " + object.path()); !valid)
        throw valid.error();
    return cage;
}

// --- everything else ---

Camera readCamera(const json& value, const Context& ctx) {
    ObjectReader object(value, "camera");
    Camera camera;
    camera.eye = readVector<3>(object.required("eye"), object.field("eye"));
    camera.target = readVector<3>(object.required("target"), object.field("target"));
    if (const json* v = object.optional("up")) camera.up = readVector<3>(*v, object.field("up"));
    if (const json* v = object.optional("projection"))
        camera.projection = readEnum<Projection>(*v, object.field("projection"), kProjectionNames);
    if (const json* v = object.optional("fov_y_degrees")) {
        camera.fovYDegrees = readFloat(*v, object.field("fov_y_degrees"));
        if (camera.fovYDegrees <= 0.0f || camera.fovYDegrees >= 180.0f)
            fail(object.field("fov_y_degrees"), "must be between 0 and 180 degrees (exclusive), got " + v->dump());
    }
    if (const json* v = object.optional("ortho_height"))
        camera.orthoHeight = readPositiveFloat(*v, object.field("ortho_height"));
    if (camera.eye == camera.target) fail(object.field("target"), "must differ from \"eye\"");
    if (glm::length(glm::cross(camera.target - camera.eye, camera.up)) == 0.0f)
        fail(object.field("up"), "must be non-zero and not parallel to the view direction");
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return camera;
}

Viewport readViewport(const json& value, const std::string& field, const Context& ctx) {
    ObjectReader object(value, field);
    Viewport viewport;
    // Any non-empty scheme name is accepted: schemes come from plugins, which may not be
    // loaded yet (or at all) when a scene is read.
    viewport.scheme = readName(object.required("scheme"), object.field("scheme"));
    if (const json* v = object.optional("camera"))
        viewport.camera = readEnum<CameraLink>(*v, object.field("camera"), kCameraLinkNames);
    if (const json* v = object.optional("color_by")) viewport.colorBy = readName(*v, object.field("color_by"));
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return viewport;
}

std::vector<Viewport> readViewports(const json& value, const Context& ctx) {
    std::vector<Viewport> viewports;
    for (size_t i = 0; i < readArray(value, "viewports").size(); ++i)
        viewports.push_back(readViewport(value[i], element("viewports", i), ctx));
    if (viewports.empty()) fail("viewports", "must list at least one viewport");
    return viewports;
}

Tessellation readTessellation(const json& value, const Context& ctx) {
    ObjectReader object(value, "tessellation");
    Tessellation t;
    if (const json* v = object.optional("mode"))
        t.mode = readEnum<TessellationMode>(*v, object.field("mode"), kTessellationModeNames);
    if (const json* v = object.optional("factor"))
        t.factor = readIntInRange(*v, object.field("factor"), 1, kMaxTessellationFactor);
    if (const json* v = object.optional("pixels_per_edge"))
        t.pixelsPerEdge = readPositiveFloat(*v, object.field("pixels_per_edge"));
    if (const json* v = object.optional("show_cage")) t.showCage = readBool(*v, object.field("show_cage"));
    if (const json* v = object.optional("show_wireframe"))
        t.showWireframe = readBool(*v, object.field("show_wireframe"));
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return t;
}

DisplaySettings readDisplay(const json& value, const Context& ctx) {
    ObjectReader object(value, "display");
    DisplaySettings d;
    if (const json* v = object.optional("up_axis")) d.upAxis = readEnum<UpAxis>(*v, object.field("up_axis"), kUpAxisNames);
    if (const json* v = object.optional("shading"))
        d.shading = readEnum<Shading>(*v, object.field("shading"), kShadingNames);
    if (const json* v = object.optional("show_grid")) d.showGrid = readBool(*v, object.field("show_grid"));
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return d;
}

// Needs the cage: the displacement's sizes follow from its topology (displacement_io.h).
Displacement readDisplacement(const json& value, const Cage& cage, const Context& ctx) {
    Result<Displacement> displacement = readDisplacementJson(value, cage, ctx.source, ctx.warnings);
    if (!displacement) fail("", displacement.error().message);
    return std::move(displacement).value();
}

void checkFormatAndVersion(ObjectReader& top) {
    const json& format = top.required("format");
    if (!format.is_string() || format.get<std::string>() != kFormatName)
        fail("format", "expected \"" + std::string(kFormatName) + "\", got " + format.dump() +
                           " (this is not a Quadplan scene)");
    int64_t version = readInteger(top.required("version"), "version");
    if (version > kSceneVersion)
        fail("version", "scene version " + std::to_string(version) + " was written by a newer Quadplan; this build "
                        "reads versions up to " + std::to_string(kSceneVersion));
    if (version < 1) fail("version", "scene version " + std::to_string(version) + " is not valid (versions start at 1)");
}

Scene readScene(const json& root, const Context& ctx) {
    if (!root.is_object()) fail("", "expected a JSON object at the top level, got " + describe(root));
    ObjectReader top(root, "");
    // Version first: a newer file may be laid out differently, and "newer version" is the
    // only useful message for it.
    checkFormatAndVersion(top);
    Scene scene;
    scene.cage = readCage(top.required("cage"), ctx, scene.cagePath);
    if (const json* v = top.optional("camera")) scene.camera = readCamera(*v, ctx);
    if (const json* v = top.optional("viewports")) scene.viewports = readViewports(*v, ctx);
    if (const json* v = top.optional("tessellation")) scene.tessellation = readTessellation(*v, ctx);
    if (const json* v = top.optional("display")) scene.display = readDisplay(*v, ctx);
    if (const json* v = top.optional("displacement")) scene.displacement = readDisplacement(*v, scene.cage, ctx);
    top.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return scene;
}

// nlohmann reports the byte offset of a syntax error; people navigate by line and column.
std::string lineAndColumn(std::string_view text, size_t byte) {
    size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size());
    size_t line = 1, column = 1;
    for (size_t i = 0; i < end; ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return std::to_string(line) + ":" + std::to_string(column);
}

// what() is "[json.exception.<kind>.<id>] <detail>".
std::string withoutExceptionId(const json::exception& e) {
    std::string message = e.what();
    size_t bracket = message.find("] ");
    return bracket == std::string::npos ? message : message.substr(bracket + 2);
}

Error syntaxError(std::string_view text, const std::string& source, const json::parse_error& e) {
    // The detail is "parse error at line L, column C: <what is wrong>"; the position is
    // reported in the usual file:line:column form instead.
    std::string detail = withoutExceptionId(e);
    if (size_t colon = detail.find(": "); colon != std::string::npos) detail = detail.substr(colon + 2);
    return Error{source + ":" + lineAndColumn(text, e.byte) + ": invalid JSON (byte " + std::to_string(e.byte) +
                 "): " + detail};
}

// ---------------------------------------------------------------------------------------------
// Writing.

// The shortest decimal that reads back as the same float, so that 0.1f is written as 0.1
// rather than 0.10000000149011612.
double shortestDecimal(float value) {
    char buffer[32];
    auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
    *end = '\0';
    double decimal = std::strtod(buffer, nullptr);
    // Reading back goes decimal -> double -> float; fall back to the exact value in the rare
    // case where that double rounding would land on a different float.
    return float(decimal) == value ? decimal : double(value);
}

ordered_json vectorJson(std::span<const float> components) {
    ordered_json array = ordered_json::array();
    for (float c : components) array.push_back(shortestDecimal(c));
    return array;
}

ordered_json vec3Json(const glm::vec3& v) { return vectorJson(std::span<const float>(&v.x, 3)); }
ordered_json vec2Json(const glm::vec2& v) { return vectorJson(std::span<const float>(&v.x, 2)); }

ordered_json facesJson(const Cage& cage, const std::vector<uint32_t>& indices) {
    ordered_json faces = ordered_json::array();
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        faces.push_back(std::vector<uint32_t>(indices.begin() + cage.faceOffsets[f],
                                              indices.begin() + cage.faceOffsets[f + 1]));
    return faces;
}

ordered_json optionsJson(const SubdivisionOptions& o) {
    return {{"boundary", enumName<BoundaryInterpolation>(kBoundaryNames, o.boundary)},
            {"crease_method", enumName<CreaseMethod>(kCreaseMethodNames, o.creaseMethod)},
            {"triangle_subdivision", enumName<TriangleSubdivision>(kTriangleNames, o.triangleSubdivision)},
            {"fvar_interpolation", enumName<FVarInterpolation>(kFVarNames, o.fvarInterpolation)},
            {"fvar_propagate_corners", o.fvarPropagateCorners}};
}

ordered_json inlineCageJson(const Cage& cage) {
    ordered_json out;
    out["positions"] = ordered_json::array();
    for (const glm::vec3& p : cage.positions) out["positions"].push_back(vec3Json(p));
    out["faces"] = facesJson(cage, cage.faceVertices);
    out["creases"] = ordered_json::array();
    for (const EdgeCrease& c : cage.creases)
        out["creases"].push_back({{"edge", {c.v0, c.v1}}, {"sharpness", shortestDecimal(c.sharpness)}});
    out["corners"] = ordered_json::array();
    for (const VertexCorner& c : cage.corners)
        out["corners"].push_back({{"vertex", c.vertex}, {"sharpness", shortestDecimal(c.sharpness)}});
    out["holes"] = cage.holes;
    out["options"] = optionsJson(cage.options);
    if (!cage.faceUVIndices.empty()) {
        out["uvs"] = ordered_json::array();
        for (const glm::vec2& uv : cage.uvs) out["uvs"].push_back(vec2Json(uv));
        out["face_uvs"] = facesJson(cage, cage.faceUVIndices);
    }
    return out;
}

ordered_json cameraJson(const Camera& c) {
    return {{"eye", vec3Json(c.eye)},
            {"target", vec3Json(c.target)},
            {"up", vec3Json(c.up)},
            {"fov_y_degrees", shortestDecimal(c.fovYDegrees)},
            {"projection", enumName<Projection>(kProjectionNames, c.projection)},
            {"ortho_height", shortestDecimal(c.orthoHeight)}};
}

ordered_json viewportsJson(const std::vector<Viewport>& viewports) {
    ordered_json out = ordered_json::array();
    for (const Viewport& v : viewports)
        out.push_back({{"scheme", v.scheme},
                       {"camera", enumName<CameraLink>(kCameraLinkNames, v.camera)},
                       {"color_by", v.colorBy}});
    return out;
}

ordered_json tessellationJson(const Tessellation& t) {
    return {{"mode", enumName<TessellationMode>(kTessellationModeNames, t.mode)},
            {"factor", t.factor},
            {"pixels_per_edge", shortestDecimal(t.pixelsPerEdge)},
            {"show_cage", t.showCage},
            {"show_wireframe", t.showWireframe}};
}

ordered_json displayJson(const DisplaySettings& d) {
    ordered_json out = ordered_json::object();
    if (d.upAxis) out["up_axis"] = enumName<UpAxis>(kUpAxisNames, *d.upAxis);
    out["shading"] = enumName<Shading>(kShadingNames, d.shading);
    out["show_grid"] = d.showGrid;
    return out;
}

ordered_json sceneJson(const Scene& scene, const std::string* cagePath) {
    ordered_json root;
    root["format"] = kFormatName;
    root["version"] = kSceneVersion;
    root["cage"] = cagePath ? ordered_json{{"path", *cagePath}} : inlineCageJson(scene.cage);
    if (scene.camera) root["camera"] = cameraJson(*scene.camera);
    root["viewports"] = viewportsJson(scene.viewports);
    root["tessellation"] = tessellationJson(scene.tessellation);
    root["display"] = displayJson(scene.display);
    root["displacement"] = displacementJson(scene.displacement);
    return root;
}

// nlohmann's pretty printer puts every number on a line of its own, which turns a cage into
// thousands of lines; this one keeps short leaves ([x, y, z], a face, a crease) on one line.
constexpr size_t kMaxLineValue = 80;

void writeCompact(const ordered_json& value, std::string& out) {
    if (!value.is_structured()) {
        out += value.dump();
        return;
    }
    bool isObject = value.is_object();
    out += isObject ? "{" : "[";
    const char* separator = "";
    for (const auto& item : value.items()) {
        out += separator;
        separator = ", ";
        if (isObject) out += ordered_json(item.key()).dump() + ": ";
        writeCompact(item.value(), out);
    }
    out += isObject ? "}" : "]";
}

bool isFlatArray(const ordered_json& value) {
    return value.is_array() && std::none_of(value.begin(), value.end(), [](const ordered_json& v) {
               return v.is_structured();
           });
}

bool fitsOnOneLine(const ordered_json& value) {
    if (!value.is_structured() || value.empty() || isFlatArray(value)) return true;
    for (const ordered_json& v : value)
        if (v.is_object() || (v.is_array() && !isFlatArray(v))) return false;
    std::string compact;
    writeCompact(value, compact);
    return compact.size() <= kMaxLineValue;
}

void writePretty(const ordered_json& value, int indent, std::string& out) {
    if (fitsOnOneLine(value)) {
        writeCompact(value, out);
        return;
    }
    bool isObject = value.is_object();
    std::string inner(size_t(indent + 2), ' ');
    out += isObject ? "{\n" : "[\n";
    const char* separator = "";
    for (const auto& item : value.items()) {
        out += separator;
        separator = ",\n";
        out += inner;
        if (isObject) out += ordered_json(item.key()).dump() + ": ";
        writePretty(item.value(), indent + 2, out);
    }
    out += "\n" + std::string(size_t(indent), ' ') + (isObject ? "}" : "]");
}

std::string formatSceneWith(const Scene& scene, const std::string* cagePath) {
    std::string out;
    writePretty(sceneJson(scene, cagePath), 0, out);
    return out + "\n";
}

std::string lowercaseExtension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

}  // namespace

Result<Scene> parseScene(std::string_view text, const std::string& source, const std::string& baseDir,
                         std::vector<std::string>* warnings) {
    json root;
    try {
        root = json::parse(text);
    } catch (const json::parse_error& e) {
        return syntaxError(text, source, e);
    } catch (const json::exception& e) {
        // Such as a number literal beyond the range of a double (1e400), which nlohmann
        // reports without a position.
        return Error{source + ": invalid JSON: " + withoutExceptionId(e)};
    }
    try {
        return readScene(root, Context{source, baseDir, warnings});
    } catch (const FieldError& e) {
        return Error{source + ": " + (e.field.empty() ? "" : e.field + ": ") + e.message};
    } catch (const Error& e) {
        return e;
    }
}

Result<Scene> loadScene(const std::string& path, std::vector<std::string>* warnings) {
    Result<std::string> text = readFile(path);
    if (!text) return text.error();
    return parseScene(*text, path, fs::path(path).parent_path().string(), warnings);
}

std::string formatScene(const Scene& scene, bool inlineCage) {
    assert((inlineCage || !scene.cagePath.empty()) && "a referenced cage needs scene.cagePath");
    return formatSceneWith(scene, inlineCage ? nullptr : &scene.cagePath);
}

Status saveScene(const Scene& scene, const std::string& path, bool inlineCage) {
    // A displacement laid out for another topology would save fine and then not load.
    if (!displacementFitsCage(scene.displacement, scene.cage))
        return Error{path + ": not saved: the displacement does not fit the cage's faces (resample it after "
                            "adding or removing faces)"};
    if (inlineCage) return writeFileAtomically(path, formatSceneWith(scene, nullptr));
    std::string cagePath = scene.cagePath.empty() ? fs::path(path).stem().string() + ".obj" : scene.cagePath;
    // The OBJ goes first so that the scene never refers to a cage that is not there yet.
    if (Status saved = saveObj(scene.cage, (fs::path(path).parent_path() / cagePath).string()); !saved)
        return saved;
    return writeFileAtomically(path, formatSceneWith(scene, &cagePath));
}

Result<Scene> loadSceneOrCage(const std::string& path, std::vector<std::string>* warnings) {
    std::string ext = lowercaseExtension(path);
    if (ext == ".json") return loadScene(path, warnings);
    if (ext == ".obj") {
        Result<Cage> cage = loadObj(path, warnings);
        if (!cage) return cage.error();
        Scene scene;
        scene.cage = std::move(cage).value();
        return scene;
    }
    return Error{path + ": cannot open a file of type \"" + ext +
                 "\"; Quadplan opens scenes (.json) and cages (.obj)"};
}

}  // namespace qp
