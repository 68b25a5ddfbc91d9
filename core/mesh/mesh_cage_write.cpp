#include "mesh/mesh_cage_write.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <filesystem>

#include <glm/geometric.hpp>

#include "mesh/file_io.h"
#include "mesh/mesh_om.h"
#include "mesh/obj_io.h"

namespace qp {

namespace {

static_assert(std::endian::native == std::endian::little, "the binary PLY and STL writers assume a little-endian host");

template <class T>
void append(std::string& out, const T& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

void appendNumber(std::string& out, float x) {
    char buffer[32];
    out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}

std::string plyBytes(const Cage& cage) {
    std::string out = "ply\nformat binary_little_endian 1.0\ncomment Quadplan cage\nelement vertex " +
                      std::to_string(cage.vertexCount()) + "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(cage.faceCount()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const glm::vec3& p : cage.positions) append(out, p);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        append(out, uint8_t(cage.faceSize(f)));
        for (uint32_t k = 0; k < cage.faceSize(f); ++k) append(out, int32_t(cage.faceBegin(f)[k]));
    }
    return out;
}

std::string offText(const Cage& cage) {
    std::string out = "OFF\n" + std::to_string(cage.vertexCount()) + " " + std::to_string(cage.faceCount()) + " 0\n";
    for (const glm::vec3& p : cage.positions) {
        appendNumber(out, p.x), out += ' ', appendNumber(out, p.y), out += ' ', appendNumber(out, p.z), out += '\n';
    }
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        out += std::to_string(cage.faceSize(f));
        for (uint32_t k = 0; k < cage.faceSize(f); ++k) out += ' ' + std::to_string(cage.faceBegin(f)[k]);
        out += '\n';
    }
    return out;
}

std::string stlBytes(const Cage& cage) {
    uint32_t triangles = 0;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) triangles += cage.faceSize(f) - 2;
    std::string out(80, ' ');
    std::memcpy(out.data(), "Quadplan cage (binary STL, polygons fanned)", 43);
    append(out, triangles);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t* v = cage.faceBegin(f);
        for (uint32_t k = 1; k + 1 < cage.faceSize(f); ++k) {
            const glm::vec3 &a = cage.positions[v[0]], &b = cage.positions[v[k]], &c = cage.positions[v[k + 1]];
            const glm::vec3 n = glm::cross(b - a, c - a);
            append(out, glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f));
            append(out, a), append(out, b), append(out, c);
            append(out, uint16_t(0));
        }
    }
    return out;
}

}  // namespace

std::vector<std::string> meshFormatLosses(const Cage& cage, const std::string& path) {
    const std::string ext = lowercaseExtension(path);
    std::vector<std::string> lost;
    if (ext == ".obj" || ext == ".om") return lost;
    const std::string format = ext.empty() ? "the format" : ext.substr(1);
    auto note = [&](size_t count, const char* what) {
        if (count) lost.push_back(path + ": " + format + " cannot hold the cage's " + std::to_string(count) + " " + what + ": not written");
    };
    note(cage.creases.size(), "creases");
    note(cage.corners.size(), "corners");
    note(cage.holes.size(), "holes (written as faces)");
    note(cage.uvs.empty() ? 0 : cage.faceUVIndices.size(), "face-varying texture coordinates");
    if (!(cage.options == SubdivisionOptions{})) lost.push_back(path + ": " + format + " cannot hold the boundary rule and crease method");
    if (ext == ".stl") {
        uint32_t polygons = 0;
        for (uint32_t f = 0; f < cage.faceCount(); ++f) polygons += cage.faceSize(f) > 3;
        if (polygons) lost.push_back(path + ": STL holds triangles: " + std::to_string(polygons) + " polygons were fanned into triangles");
    }
    return lost;
}

Status saveMeshCage(const Cage& cage, const std::string& path, std::vector<std::string>* lost) {
    const std::string ext = lowercaseExtension(path);
    if (ext == ".obj") return saveObj(cage, path);  // carries every tag
    if (ext == ".om") {  // carries every tag too
        Result<std::string> bytes = omCageBytes(cage, path);
        if (!bytes) return bytes.error();
        return writeFileAtomically(path, *bytes);
    }
    std::string bytes;
    if (ext == ".ply") bytes = plyBytes(cage);
    else if (ext == ".off") bytes = offText(cage);
    else if (ext == ".stl") bytes = stlBytes(cage);
    else return Error{"cannot write a cage as '" + path + "': the name must end in .obj, .om, .ply, .off or .stl"};
    if (lost) *lost = meshFormatLosses(cage, path);
    return writeFileAtomically(path, bytes);
}

}  // namespace qp
