// Writing scene files: the JSON of scene.h's schema, pretty-printed with short leaves on one line,
// and saving it (atomically, with the objects' OBJs first when cages are referenced).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <span>

#include "displacement/displacement_io.h"
#include "mesh/file_io.h"
#include "mesh/mesh_cage_write.h"
#include "mesh/obj_io.h"
#include "scene/scene.h"
#include "scene/scene_names.h"

namespace qp {

namespace {

using ordered_json = nlohmann::ordered_json;
namespace fs = std::filesystem;
using namespace scene_names;

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
    out["dense_cage_lines"] = d.denseCageLines;
    return out;
}

ordered_json transformJson(const ObjectTransform& t) {
    return {{"translation", vec3Json(t.translation)},
            {"rotation_degrees", vec3Json(t.rotationDegrees)},
            {"scale", vec3Json(t.scale)}};
}

// Vertex keys are written grouped by frame, as an animator keys them.
ordered_json vertexKeysJson(const VertexKeys& keys) {
    std::map<int32_t, std::pair<std::vector<uint32_t>, ordered_json>> byFrame;
    for (uint32_t v = 0; v + 1 < keys.offsets.size(); ++v)
        for (uint32_t k = keys.offsets[v]; k < keys.offsets[v + 1]; ++k) {
            auto& [vertices, positions] = byFrame[keys.frames[k]];
            vertices.push_back(v);
            positions.push_back(vec3Json(keys.positions[k]));
        }
    ordered_json out = ordered_json::array();
    for (auto& [frame, key] : byFrame)
        out.push_back({{"frame", frame}, {"vertices", key.first}, {"positions", std::move(key.second)}});
    return out;
}

ordered_json animationJson(const ObjectAnimation& a) {
    ordered_json out;
    out["interpolation"] = enumName<Interpolation>(kInterpolationNames, a.interpolation);
    if (!a.sequencePattern.empty()) out["sequence"] = a.sequencePattern;
    else if (!a.vertexKeys.empty()) out["keys"] = vertexKeysJson(a.vertexKeys);
    if (!a.transformKeys.empty()) {
        ordered_json keys = ordered_json::array();
        for (const TransformKey& k : a.transformKeys) keys.push_back({{"frame", k.frame}, {"transform", transformJson(k.transform)}});
        out["transform_keys"] = std::move(keys);
    }
    return out;
}

// `cagePath`: the OBJ the object's cage is referenced by; null or empty: inline.
ordered_json objectJson(const SceneObject& o, const std::string* cagePath) {
    ordered_json out;
    out["name"] = o.name;
    if (o.isInstance()) {
        out["instance_of"] = o.instanceOf;
    } else {
        const bool referenced = cagePath && !cagePath->empty();
        out["cage"] = referenced ? ordered_json{{"path", *cagePath}} : inlineCageJson(o.cage);
        out["displacement"] = displacementJson(o.displacement);
    }
    out["transform"] = transformJson(o.transform);
    out["visible"] = o.visible;
    if (!o.animation.empty()) out["animation"] = animationJson(o.animation);
    return out;
}

ordered_json sceneJson(const Scene& scene, const std::vector<std::string>* cagePaths) {
    ordered_json root;
    root["format"] = kFormatName;
    root["version"] = kSceneVersion;
    root["objects"] = ordered_json::array();
    for (size_t i = 0; i < scene.objects.size(); ++i)
        root["objects"].push_back(objectJson(scene.objects[i], cagePaths ? &(*cagePaths)[i] : nullptr));
    if (scene.camera) root["camera"] = cameraJson(*scene.camera);
    root["viewports"] = viewportsJson(scene.viewports);
    root["tessellation"] = tessellationJson(scene.tessellation);
    root["display"] = displayJson(scene.display);
    if (scene.timeline)
        root["timeline"] = {{"fps", scene.timeline->framesPerSecond},
                            {"first_frame", scene.timeline->firstFrame},
                            {"last_frame", scene.timeline->lastFrame}};
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

std::string formatSceneWith(const Scene& scene, const std::vector<std::string>* cagePaths) {
    std::string out;
    writePretty(sceneJson(scene, cagePaths), 0, out);
    return out + "\n";
}

}  // namespace

std::string formatScene(const Scene& scene, CageStorage storage) {
    if (storage == CageStorage::Inline) return formatSceneWith(scene, nullptr);
    std::vector<std::string> cagePaths;
    for (const SceneObject& o : scene.objects) {
        assert((storage == CageStorage::AsLoaded || o.isInstance() || !o.cagePath.empty()) &&
               "a referenced cage needs its object's cagePath");
        cagePaths.push_back(o.cagePath);
    }
    return formatSceneWith(scene, &cagePaths);
}

namespace {

// "<scene name>.obj" for the only object, else "<scene name>_<object name>.obj" (characters
// awkward in file names, object names being free text, become '_').
std::string objectCageFile(const std::string& scenePath, const std::string& objectName, bool onlyObject) {
    const std::string stem = fs::path(scenePath).stem().string();
    if (onlyObject) return stem + ".obj";
    std::string name = objectName;
    for (char& c : name)
        if (!(std::isalnum((unsigned char)c) || c == '-' || c == '_' || c == '.')) c = '_';
    return stem + "_" + name + ".obj";
}

}  // namespace

std::string savedCagePath(const Scene& scene, const std::string& scenePath, uint32_t index) {
    const SceneObject& o = scene.objects[index];
    if (!o.cagePath.empty()) return o.cagePath;
    return objectCageFile(scenePath, o.name, scene.objects.size() == 1);
}

bool nameCagesAfterNewScene(Scene& scene, const std::string& readFrom, const std::string& path) {
    std::error_code error;
    if (!readFrom.empty() && fs::weakly_canonical(readFrom, error) == fs::weakly_canonical(path, error) && !error) return false;
    bool renamed = false;
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        SceneObject& o = scene.objects[i];
        if (o.isInstance() || o.cagePath.empty()) continue;
        o.cagePath.clear();
        o.cagePath = savedCagePath(scene, path, i);
        renamed = true;
    }
    return renamed;
}

// The scene with its OBJ sequences named relative to `folder`, where the scene file resolves them.
Scene withSequencesRelativeTo(const Scene& scene, const fs::path& folder) {
    Scene out = scene;
    for (SceneObject& o : out.objects) {
        if (o.animation.sequencePattern.empty() || !fs::path(o.animation.sequencePattern).is_absolute()) continue;
        const fs::path relative = fs::path(o.animation.sequencePattern).lexically_relative(folder);
        if (!relative.empty()) o.animation.sequencePattern = relative.string();
    }
    return out;
}

Status saveScene(const Scene& original, const std::string& path, CageStorage storage) {
    // A displacement laid out for another topology, or a broken instance link, would save fine
    // and then not load.
    if (Status valid = validateObjects(original.objects, ""); !valid) return Error{path + ": not saved: " + valid.error().message};
    std::error_code error;
    const fs::path folder = fs::absolute(path, error).lexically_normal().parent_path();
    const Scene scene = error ? original : withSequencesRelativeTo(original, folder);
    if (storage == CageStorage::Inline) return writeFileAtomically(path, formatSceneWith(scene, nullptr));
    std::vector<std::string> cagePaths(scene.objects.size());
    // Objects may reference one OBJ (the same file opened twice): it is written once while their
    // cages agree; a cage that differs gets a file of its own instead of overwriting the other's.
    std::map<std::string, uint32_t> writerOf;
    // The OBJs go first so that the scene never refers to a cage that is not there yet.
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        const SceneObject& o = scene.objects[i];
        if (o.isInstance() || (storage == CageStorage::AsLoaded && o.cagePath.empty())) continue;
        cagePaths[i] = savedCagePath(scene, path, i);
        if (auto it = writerOf.find(cagePaths[i]); it != writerOf.end()) {
            const Cage& first = scene.objects[it->second].cage;
            if (sameTopologyAndTags(first, o.cage) && first.positions == o.cage.positions && first.uvs == o.cage.uvs) continue;
            cagePaths[i] = objectCageFile(path, o.name, false);
            if (writerOf.count(cagePaths[i]))
                return Error{path + ": not saved: objects \"" + scene.objects[writerOf[cagePaths[i]]].name + "\" and \"" +
                             o.name + "\" would both be written to " + cagePaths[i]};
        }
        // A cage file that cannot hold what the cage has now (PLY, OFF and STL carry no tags or UVs)
        // is left as it is: the cage goes to an OBJ beside it, and the scene points there.
        if (!meshFormatLosses(o.cage, cagePaths[i]).empty()) cagePaths[i] = (fs::path(cagePaths[i]).replace_extension(".obj")).string();
        writerOf[cagePaths[i]] = i;
        if (Status saved = saveMeshCage(o.cage, (fs::path(path).parent_path() / cagePaths[i]).string()); !saved) return saved;
    }
    return writeFileAtomically(path, formatSceneWith(scene, &cagePaths));
}

}  // namespace qp
