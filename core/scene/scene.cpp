#include "scene/scene.h"

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

#include "animation/cage_sequence.h"
#include "displacement/displacement_io.h"
#include "mesh/file_io.h"
#include "mesh/mesh_import.h"
#include "mesh/obj_io.h"
#include "scene/scene_names.h"

namespace qp {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;
using namespace scene_names;

constexpr int kMaxTessellationFactor = 64;

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
    // Keeping tags in exactly one place (the cage file) means there is nothing to merge or to
    // get out of sync when the file is edited elsewhere. OBJ and OM carry them; a PLY, OFF or
    // STL cage has none until the scene is saved (saveScene then writes an OBJ beside it).
    for (const char* key : kInlineOnlyFields)
        if (object.has(key))
            fail(object.field(key), "not allowed with \"path\": a referenced cage keeps its geometry and tags "
                                    "in the OBJ file");
    cagePath = readName(object.required("path"), object.field("path"));
    std::string resolved = (fs::path(ctx.baseDir) / cagePath).string();
    Result<Cage> cage = isMeshCageExtension(lowercaseExtension(resolved)) ? loadMeshCage(resolved, ctx.warnings)
                                                                          : loadObj(resolved, ctx.warnings);
    if (!cage) fail(object.field("path"), "cannot load the referenced cage \"" + cagePath + "\": " + cage.error().message);
    return std::move(cage).value();
}

Cage readCage(const json& value, const std::string& field, const Context& ctx, std::string& cagePath) {
    ObjectReader object(value, field);
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
    if (const json* v = object.optional("dense_cage_lines"))
        d.denseCageLines = readBool(*v, object.field("dense_cage_lines"));
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return d;
}

// Needs the cage: the displacement's sizes follow from its topology (displacement_io.h).
// `at` is the path of the object holding it ("objects[2]."; "" in a version 1 file).
Displacement readDisplacement(const json& value, const Cage& cage, const std::string& at, const Context& ctx) {
    Result<Displacement> displacement = readDisplacementJson(value, cage, ctx.source, ctx.warnings, at);
    if (!displacement) fail("", displacement.error().message);
    return std::move(displacement).value();
}

ObjectTransform readTransform(const json& value, const std::string& field, const Context& ctx) {
    ObjectReader object(value, field);
    ObjectTransform t;
    if (const json* v = object.optional("translation")) t.translation = readVector<3>(*v, object.field("translation"));
    if (const json* v = object.optional("rotation_degrees"))
        t.rotationDegrees = readVector<3>(*v, object.field("rotation_degrees"));
    if (const json* v = object.optional("scale")) {
        t.scale = readVector<3>(*v, object.field("scale"));
        for (int k = 0; k < 3; ++k)
            if (t.scale[k] == 0.0f) fail(element(object.field("scale"), size_t(k)), "scale must not be zero");
    }
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return t;
}

// --- animation (cage_animation.h) ---

int32_t readFrame(const json& value, const std::string& field) {
    return int32_t(readIntInRange(value, field, -kMaxKeyFrame, kMaxKeyFrame));
}

// A key's frame, which must come after `previous` (the key before it, if any).
int32_t readKeyFrame(ObjectReader& key, const std::optional<int32_t>& previous) {
    const int32_t frame = readFrame(key.required("frame"), key.field("frame"));
    if (previous && frame <= *previous)
        fail(key.field("frame"), "frame " + std::to_string(frame) + " is not after the previous key's frame " +
                                     std::to_string(*previous) + " (keys are listed in increasing frame order, one per frame)");
    return frame;
}

// "keys": [{"frame": F, "vertices": [...], "positions": [[x, y, z], ...]}, ...], into per-vertex tracks.
VertexKeys readVertexKeys(const json& value, const std::string& field, uint32_t vertexCount, const Context& ctx) {
    std::vector<std::vector<std::pair<int32_t, glm::vec3>>> tracks(vertexCount);
    std::optional<int32_t> previous;
    for (size_t i = 0; i < readArray(value, field).size(); ++i) {
        ObjectReader key(value[i], element(field, i));
        const int32_t frame = readKeyFrame(key, previous);
        previous = frame;
        const json& vertices = readArray(key.required("vertices"), key.field("vertices"));
        std::vector<glm::vec3> positions = readPositions(key.required("positions"), key.field("positions"));
        if (positions.size() != vertices.size())
            fail(key.field("positions"), std::to_string(positions.size()) + " positions for " +
                                             std::to_string(vertices.size()) + " vertices");
        for (size_t k = 0; k < vertices.size(); ++k) {
            const uint32_t v = readIndex(vertices[k], element(key.field("vertices"), k), "vertex", vertexCount, "vertices");
            if (!tracks[v].empty() && tracks[v].back().first == frame)
                fail(element(key.field("vertices"), k), "vertex " + std::to_string(v) + " is keyed twice at frame " +
                                                            std::to_string(frame));
            tracks[v].push_back({frame, positions[k]});
        }
        key.warnAboutUnknownFields(ctx.source, ctx.warnings);
    }
    VertexKeys keys;
    keys.offsets.assign(size_t(vertexCount) + 1, 0);
    for (uint32_t v = 0; v < vertexCount; ++v) {
        for (const auto& [frame, position] : tracks[v]) {
            keys.frames.push_back(frame);
            keys.positions.push_back(position);
        }
        keys.offsets[v + 1] = uint32_t(keys.frames.size());
    }
    if (keys.frames.empty()) keys.offsets.clear();
    return keys;
}

// Every frame of the sequence, read now: a bad frame fails the whole scene.
VertexKeys readSequence(const std::string& pattern, const std::string& field, const Cage& cage) {
    Result<VertexKeys> keys = loadSequenceKeys(pattern, cage);
    if (!keys) fail(field, keys.error().message);
    return std::move(keys).value();
}

std::vector<TransformKey> readTransformKeys(const json& value, const std::string& field, const Context& ctx) {
    std::vector<TransformKey> keys;
    std::optional<int32_t> previous;
    for (size_t i = 0; i < readArray(value, field).size(); ++i) {
        ObjectReader key(value[i], element(field, i));
        TransformKey k;
        k.frame = readKeyFrame(key, previous);
        previous = k.frame;
        if (const json* t = key.optional("transform")) k.transform = readTransform(*t, key.field("transform"), ctx);
        keys.push_back(k);
        key.warnAboutUnknownFields(ctx.source, ctx.warnings);
    }
    return keys;
}

// `cage`: the object's own (null for an instance, which may key its transform only).
ObjectAnimation readAnimation(const json& value, const std::string& field, const Cage* cage, const Context& ctx) {
    ObjectReader object(value, field);
    ObjectAnimation a;
    if (const json* v = object.optional("interpolation"))
        a.interpolation = readEnum<Interpolation>(*v, object.field("interpolation"), kInterpolationNames);
    const json* sequence = object.optional("sequence");
    const json* keys = object.optional("keys");
    if ((sequence || keys) && !cage)
        fail(object.field(sequence ? "sequence" : "keys"), "an instance follows its source's cage; it can key its transform only");
    if (sequence && keys) fail(object.field("keys"), "not allowed with \"sequence\": the positions come from one or the other");
    if (sequence) {
        // Kept absolute, so the scene can be saved to any folder (saveScene writes it relative
        // to the scene file again).
        const fs::path pattern = fs::path(ctx.baseDir) / readName(*sequence, object.field("sequence"));
        std::error_code error;
        const fs::path absolute = fs::absolute(pattern, error);
        a.sequencePattern = (error ? pattern : absolute).lexically_normal().string();
        a.vertexKeys = readSequence(a.sequencePattern, object.field("sequence"), *cage);
    }
    if (keys) a.vertexKeys = readVertexKeys(*keys, object.field("keys"), uint32_t(cage->positions.size()), ctx);
    if (const json* v = object.optional("transform_keys"))
        a.transformKeys = readTransformKeys(*v, object.field("transform_keys"), ctx);
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return a;
}

Timeline readTimeline(const json& value, const Context& ctx) {
    ObjectReader object(value, "timeline");
    Timeline t;
    if (const json* v = object.optional("fps")) {
        t.framesPerSecond = readPositiveFloat(*v, object.field("fps"));
        if (t.framesPerSecond > 1000.0) fail(object.field("fps"), "must be at most 1000, got " + v->dump());
    }
    t.firstFrame = readFrame(object.required("first_frame"), object.field("first_frame"));
    t.lastFrame = readFrame(object.required("last_frame"), object.field("last_frame"));
    if (t.lastFrame < t.firstFrame)
        fail(object.field("last_frame"), "the last frame " + std::to_string(t.lastFrame) + " comes before the first, " +
                                             std::to_string(t.firstFrame));
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return t;
}

SceneObject readObject(const json& value, const std::string& field, const Context& ctx) {
    ObjectReader object(value, field);
    SceneObject o;
    o.name = readName(object.required("name"), object.field("name"));
    if (const json* v = object.optional("instance_of")) {
        o.instanceOf = readName(*v, object.field("instance_of"));
        for (const char* own : {"cage", "displacement"})
            if (object.has(own))
                fail(object.field(own), "not allowed with \"instance_of\": an instance draws its source's " +
                                            std::string(own));
    } else {
        o.cage = readCage(object.required("cage"), object.field("cage"), ctx, o.cagePath);
        if (const json* v = object.optional("displacement"))
            o.displacement = readDisplacement(*v, o.cage, field + ".", ctx);
    }
    if (const json* v = object.optional("transform")) o.transform = readTransform(*v, object.field("transform"), ctx);
    if (const json* v = object.optional("visible")) o.visible = readBool(*v, object.field("visible"));
    if (const json* v = object.optional("animation"))
        o.animation = readAnimation(*v, object.field("animation"), o.isInstance() ? nullptr : &o.cage, ctx);
    object.warnAboutUnknownFields(ctx.source, ctx.warnings);
    return o;
}

std::vector<SceneObject> readObjects(const json& value, const Context& ctx) {
    std::vector<SceneObject> objects;
    for (size_t i = 0; i < readArray(value, "objects").size(); ++i) {
        objects.push_back(readObject(value[i], element("objects", i), ctx));
        for (size_t j = 0; j + 1 < objects.size(); ++j)
            if (objects[j].name == objects.back().name)
                fail(element("objects", i) + ".name", "\"" + objects.back().name + "\" is also the name of objects[" +
                                                          std::to_string(j) + "]; object names must be unique");
    }
    if (objects.empty()) fail("objects", "must list at least one object");
    if (Result<std::vector<uint32_t>> owners = cageOwners(objects); !owners) fail("objects", owners.error().message);
    return objects;
}

// Version 1 held one cage and its displacement at the top level: they become one object, named
// after the referenced OBJ (or "cage" when inline).
SceneObject readVersion1Object(ObjectReader& top, const Context& ctx) {
    SceneObject o;
    o.cage = readCage(top.required("cage"), "cage", ctx, o.cagePath);
    o.name = o.cagePath.empty() ? "cage" : fs::path(o.cagePath).stem().string();
    if (o.name.empty()) o.name = "cage";
    if (const json* v = top.optional("displacement")) o.displacement = readDisplacement(*v, o.cage, "", ctx);
    return o;
}

int checkFormatAndVersion(ObjectReader& top) {
    const json& format = top.required("format");
    if (!format.is_string() || format.get<std::string>() != kFormatName)
        fail("format", "expected \"" + std::string(kFormatName) + "\", got " + format.dump() +
                           " (this is not a Quadplan scene)");
    int64_t version = readInteger(top.required("version"), "version");
    if (version > kSceneVersion)
        fail("version", "scene version " + std::to_string(version) + " was written by a newer Quadplan; this build "
                        "reads versions up to " + std::to_string(kSceneVersion));
    if (version < 1) fail("version", "scene version " + std::to_string(version) + " is not valid (versions start at 1)");
    return int(version);
}

Scene readScene(const json& root, const Context& ctx) {
    if (!root.is_object()) fail("", "expected a JSON object at the top level, got " + describe(root));
    ObjectReader top(root, "");
    // Version first: a newer file may be laid out differently, and "newer version" is the
    // only useful message for it.
    const int version = checkFormatAndVersion(top);
    Scene scene;
    if (version == 1) scene.objects.push_back(readVersion1Object(top, ctx));
    else scene.objects = readObjects(top.required("objects"), ctx);
    if (const json* v = top.optional("camera")) scene.camera = readCamera(*v, ctx);
    if (const json* v = top.optional("viewports")) scene.viewports = readViewports(*v, ctx);
    if (const json* v = top.optional("tessellation")) scene.tessellation = readTessellation(*v, ctx);
    if (const json* v = top.optional("display")) scene.display = readDisplay(*v, ctx);
    if (const json* v = top.optional("timeline")) scene.timeline = readTimeline(*v, ctx);
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

Scene sceneOfCage(Cage cage, const std::string& name) {
    Scene scene;
    SceneObject object;
    object.name = name.empty() ? "cage" : name;
    object.cage = std::move(cage);
    scene.objects.push_back(std::move(object));
    return scene;
}

Bounds sceneBounds(const Scene& scene) {
    Result<std::vector<uint32_t>> owners = cageOwners(scene.objects);
    assert(owners && "sceneBounds needs resolvable instance links (validateObjects)");
    const bool anyVisible =
        std::any_of(scene.objects.begin(), scene.objects.end(), [](const SceneObject& o) { return o.visible; });
    Bounds out{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        if (anyVisible && !scene.objects[i].visible) continue;
        const Bounds b = objectBounds(scene.objects[i], scene.objects[(*owners)[i]].cage);
        out.min = glm::min(out.min, b.min);
        out.max = glm::max(out.max, b.max);
    }
    if (scene.objects.empty()) return Bounds{};
    return out;
}

Timeline timelineOf(const Scene& scene) {
    if (scene.timeline) return *scene.timeline;
    Timeline timeline;
    bool any = false;
    for (const SceneObject& o : scene.objects) {
        int32_t first = 0, last = 0;
        if (!keyedFrameRange(o.animation, first, last)) continue;
        timeline.firstFrame = any ? std::min(timeline.firstFrame, first) : first;
        timeline.lastFrame = any ? std::max(timeline.lastFrame, last) : last;
        any = true;
    }
    return timeline;
}

bool isAnimated(const Scene& scene) {
    return std::any_of(scene.objects.begin(), scene.objects.end(), [](const SceneObject& o) { return !o.animation.empty(); });
}

Result<Scene> loadSceneOrCage(const std::string& path, std::vector<std::string>* warnings) {
    std::string ext = lowercaseExtension(path);
    if (ext == ".json") return loadScene(path, warnings);
    if (ext == ".obj") {
        Result<Cage> cage = loadObj(path, warnings);
        if (!cage) return cage.error();
        return sceneOfCage(std::move(cage).value(), fs::path(path).stem().string());
    }
    if (isMeshCageExtension(ext)) {
        Result<Cage> cage = loadMeshCage(path, warnings);
        if (!cage) return cage.error();
        return sceneOfCage(std::move(cage).value(), fs::path(path).stem().string());
    }
    return Error{path + ": cannot open a file of type \"" + ext +
                 "\"; Quadplan opens scenes (.json) and cages (.obj, .ply, .off, .stl)"};
}

}  // namespace qp
