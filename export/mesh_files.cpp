#include "mesh_files.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <sstream>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <tiny_gltf.h>

#include "mesh/file_io.h"

namespace qp {

namespace {

static_assert(std::endian::native == std::endian::little, "the binary PLY and STL writers assume a little-endian host");

// Text output without locale or stream overhead (100k-face exports write millions of numbers).
struct Text {
    std::string out;
    void number(float x) {
        char buffer[32];
        out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
    }
    void number(uint32_t x) {
        char buffer[16];
        out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
    }
    void vec(const glm::vec3& v) {
        number(v.x), out += ' ', number(v.y), out += ' ', number(v.z);
    }
};

template <class T>
void appendBytes(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

std::string objText(const LimitMesh& mesh) {
    Text t;
    t.out = "# Quadplan limit surface: " + std::to_string(mesh.vertexCount()) + " vertices, " +
            std::to_string(mesh.triangleCount()) + " triangles\n";
    for (const glm::vec3& p : mesh.positions) t.out += "v ", t.vec(p), t.out += '\n';
    for (const glm::vec3& n : mesh.normals) t.out += "vn ", t.vec(n), t.out += '\n';
    for (const glm::vec2& uv : mesh.uvs) t.out += "vt ", t.number(uv.x), t.out += ' ', t.number(uv.y), t.out += '\n';
    const bool uvs = !mesh.uvs.empty();
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
        t.out += 'f';
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = mesh.indices[i + k] + 1;
            t.out += ' ', t.number(v), t.out += '/';
            if (uvs) t.number(v);
            t.out += '/', t.number(v);
        }
        t.out += '\n';
    }
    return t.out;
}

std::string offText(const LimitMesh& mesh) {
    Text t;
    t.out = "OFF\n" + std::to_string(mesh.vertexCount()) + " " + std::to_string(mesh.triangleCount()) + " 0\n";
    for (const glm::vec3& p : mesh.positions) t.vec(p), t.out += '\n';
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
        t.out += '3';
        for (int k = 0; k < 3; ++k) t.out += ' ', t.number(mesh.indices[i + k]);
        t.out += '\n';
    }
    return t.out;
}

std::string plyBytes(const LimitMesh& mesh) {
    std::string out = "ply\nformat binary_little_endian 1.0\ncomment Quadplan limit surface\nelement vertex " +
                      std::to_string(mesh.vertexCount()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                      "property float nz\n" + (mesh.uvs.empty() ? "" : "property float s\nproperty float t\n") +
                      // For pipelines: where each vertex was evaluated (readers skip properties they do not know).
                      "property uint subface\nproperty float subface_u\nproperty float subface_v\nelement face " +
                      std::to_string(mesh.triangleCount()) + "\nproperty list uchar uint vertex_indices\nend_header\n";
    out.reserve(out.size() + mesh.vertexCount() * 44 + mesh.triangleCount() * 13);
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
        appendBytes(out, mesh.positions[v]), appendBytes(out, mesh.normals[v]);
        if (!mesh.uvs.empty()) appendBytes(out, mesh.uvs[v]);
        appendBytes(out, mesh.subfaces[v]), appendBytes(out, mesh.parameters[v]);
    }
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
        appendBytes(out, uint8_t(3));
        for (int k = 0; k < 3; ++k) appendBytes(out, mesh.indices[i + k]);
    }
    return out;
}

std::string stlBytes(const LimitMesh& mesh) {
    std::string out(80, ' ');
    std::memcpy(out.data(), "Quadplan limit surface (binary STL)", 35);
    appendBytes(out, uint32_t(mesh.triangleCount()));
    for (size_t i = 0; i < mesh.indices.size(); i += 3) {
        const glm::vec3 &a = mesh.positions[mesh.indices[i]], &b = mesh.positions[mesh.indices[i + 1]],
                        &c = mesh.positions[mesh.indices[i + 2]];
        const glm::vec3 cross = glm::cross(b - a, c - a);
        const float length = glm::length(cross);
        appendBytes(out, length > 0.0f ? cross / length : glm::vec3(0.0f));
        appendBytes(out, a), appendBytes(out, b), appendBytes(out, c);
        appendBytes(out, uint16_t(0));
    }
    return out;
}

// ---- glTF -----------------------------------------------------------------------------------

// Appends `count` elements at a 4-byte boundary as a buffer view and an accessor; returns the
// accessor's index.
int addAccessor(tinygltf::Model& model, const void* data, size_t count, size_t elementBytes, int componentType,
                int type, int target) {
    std::vector<unsigned char>& bytes = model.buffers[0].data;
    bytes.resize((bytes.size() + 3) & ~size_t(3));
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bytes.size();
    view.byteLength = count * elementBytes;
    view.target = target;
    const auto* begin = static_cast<const unsigned char*>(data);
    bytes.insert(bytes.end(), begin, begin + count * elementBytes);
    model.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = int(model.bufferViews.size() - 1);
    accessor.componentType = componentType;
    accessor.count = count;
    accessor.type = type;
    model.accessors.push_back(accessor);
    return int(model.accessors.size() - 1);
}

int addMesh(tinygltf::Model& model, const LimitMesh& mesh, const std::string& name) {
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    const int position = addAccessor(model, mesh.positions.data(), mesh.vertexCount(), sizeof(glm::vec3),
                                     TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    model.accessors[position].minValues = {lo.x, lo.y, lo.z};
    model.accessors[position].maxValues = {hi.x, hi.y, hi.z};
    primitive.attributes["POSITION"] = position;
    primitive.attributes["NORMAL"] = addAccessor(model, mesh.normals.data(), mesh.vertexCount(), sizeof(glm::vec3),
                                                 TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
    // glTF allows 32-bit integers only for indices: the sub-face goes as a float (exact below 2^24).
    std::vector<float> subfaces(mesh.subfaces.begin(), mesh.subfaces.end());
    primitive.attributes["_SUBFACE"] = addAccessor(model, subfaces.data(), subfaces.size(), sizeof(float),
                                                   TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.attributes["_SUBFACE_UV"] = addAccessor(model, mesh.parameters.data(), mesh.parameters.size(), sizeof(glm::vec2),
                                                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
    // glTF's texture coordinates start at the image's top left, OBJ's (the cage's) at its bottom left.
    std::vector<glm::vec2> texcoords;
    for (const glm::vec2& uv : mesh.uvs) texcoords.push_back({uv.x, 1.0f - uv.y});
    if (!mesh.uvs.empty())
        primitive.attributes["TEXCOORD_0"] = addAccessor(model, texcoords.data(), texcoords.size(), sizeof(glm::vec2),
                                                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.indices = addAccessor(model, mesh.indices.data(), mesh.indices.size(), sizeof(uint32_t),
                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                    TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    tinygltf::Mesh out;
    out.name = name;
    out.primitives.push_back(primitive);
    model.meshes.push_back(out);
    return int(model.meshes.size() - 1);
}

Result<std::string> gltfBytes(const ExportScene& scene, bool binary) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "Quadplan";
    model.buffers.emplace_back();
    std::vector<int> meshIndex;
    for (size_t m = 0; m < scene.meshes.size(); ++m) meshIndex.push_back(addMesh(model, scene.meshes[m], scene.meshNames[m]));
    tinygltf::Scene gltfScene;
    for (const ExportObject& object : scene.objects) {
        tinygltf::Node node;
        node.name = object.name;
        node.mesh = meshIndex.at(object.mesh);
        const ObjectTransform& t = object.transform;
        if (t.translation != glm::vec3(0.0f)) node.translation = {t.translation.x, t.translation.y, t.translation.z};
        if (t.rotationDegrees != glm::vec3(0.0f)) {
            ObjectTransform rotationOnly;
            rotationOnly.rotationDegrees = t.rotationDegrees;
            const glm::quat q = glm::quat_cast(glm::mat3(rotationOnly.matrix()));
            node.rotation = {q.x, q.y, q.z, q.w};
        }
        if (t.scale != glm::vec3(1.0f)) node.scale = {t.scale.x, t.scale.y, t.scale.z};
        model.nodes.push_back(node);
        gltfScene.nodes.push_back(int(model.nodes.size() - 1));
    }
    model.scenes.push_back(gltfScene);
    model.defaultScene = 0;
    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, out, !binary, binary)) return Error{"tinygltf could not write the glTF"};
    return out.str();
}

}  // namespace

Result<MeshFormat> meshFormatOf(const std::string& path) {
    const std::string ext = lowercaseExtension(path);
    if (ext == ".glb") return MeshFormat::Glb;
    if (ext == ".gltf") return MeshFormat::Gltf;
    if (ext == ".obj") return MeshFormat::Obj;
    if (ext == ".ply") return MeshFormat::Ply;
    if (ext == ".off") return MeshFormat::Off;
    if (ext == ".stl") return MeshFormat::Stl;
    return Error{"cannot export to '" + path + "': the name must end in .glb, .gltf, .obj, .ply, .off or .stl"};
}

const char* meshFormatName(MeshFormat format) {
    switch (format) {
    case MeshFormat::Glb: return "glb";
    case MeshFormat::Gltf: return "gltf";
    case MeshFormat::Obj: return "obj";
    case MeshFormat::Ply: return "ply";
    case MeshFormat::Off: return "off";
    case MeshFormat::Stl: return "stl";
    }
    return "";
}

bool hasNodes(MeshFormat format) { return format == MeshFormat::Glb || format == MeshFormat::Gltf; }

LimitMesh mergedInWorld(const ExportScene& scene) {
    LimitMesh merged;
    // UVs only when every object's mesh has them (a file has them for all its vertices or none).
    const bool uvs = std::all_of(scene.objects.begin(), scene.objects.end(),
                                 [&](const ExportObject& o) { return !scene.meshes.at(o.mesh).uvs.empty(); });
    for (const ExportObject& object : scene.objects) {
        const LimitMesh& mesh = scene.meshes.at(object.mesh);
        const glm::mat4 matrix = object.transform.matrix();
        const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(matrix)));
        const bool mirrored = glm::determinant(glm::mat3(matrix)) < 0.0f;  // keep the outside outside
        const uint32_t base = merged.vertexCount();
        for (uint32_t v = 0; v < mesh.vertexCount(); ++v) {
            merged.positions.push_back(glm::vec3(matrix * glm::vec4(mesh.positions[v], 1.0f)));
            const glm::vec3 n = normalMatrix * mesh.normals[v];
            merged.normals.push_back(glm::length(n) > 0.0f ? glm::normalize(n) : n);
        }
        merged.subfaces.insert(merged.subfaces.end(), mesh.subfaces.begin(), mesh.subfaces.end());
        merged.parameters.insert(merged.parameters.end(), mesh.parameters.begin(), mesh.parameters.end());
        if (uvs) merged.uvs.insert(merged.uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
        for (size_t i = 0; i < mesh.indices.size(); i += 3) {
            const uint32_t a = base + mesh.indices[i], b = base + mesh.indices[i + 1], c = base + mesh.indices[i + 2];
            if (mirrored) merged.indices.insert(merged.indices.end(), {a, c, b});
            else merged.indices.insert(merged.indices.end(), {a, b, c});
        }
    }
    return merged;
}

Status writeMeshFile(const ExportScene& scene, const std::string& path, MeshFormat format) {
    if (scene.objects.empty()) return Error{"nothing to export to '" + path + "': no visible object"};
    std::string bytes;
    if (hasNodes(format)) {
        Result<std::string> gltf = gltfBytes(scene, format == MeshFormat::Glb);
        if (!gltf) return Error{"exporting '" + path + "': " + gltf.error().message};
        bytes = std::move(gltf).value();
    } else {
        const LimitMesh merged = mergedInWorld(scene);
        switch (format) {
        case MeshFormat::Obj: bytes = objText(merged); break;
        case MeshFormat::Ply: bytes = plyBytes(merged); break;
        case MeshFormat::Off: bytes = offText(merged); break;
        case MeshFormat::Stl: bytes = stlBytes(merged); break;
        case MeshFormat::Glb:
        case MeshFormat::Gltf: break;
        }
    }
    return writeFileAtomically(path, bytes);
}

}  // namespace qp
