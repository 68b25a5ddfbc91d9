#include "mesh/mesh_import.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

// OpenMesh's headers are slow to compile: this is the one translation unit that reads them.
#include <OpenMesh/Core/IO/MeshIO.hh>

#include "mesh/file_io.h"
#include "mesh/mesh_file_check.h"
#include "mesh/mesh_importer_base.h"
#include "mesh/mesh_om.h"

namespace qp {

namespace {

namespace om = OpenMesh;

// What OpenMesh's readers hand over, kept as they give it: vertices and faces (index lists).
// Every other attribute is ignored; handles are the indices themselves.
class CageImporter final : public AttributeFreeImporter {
public:
    std::vector<glm::vec3> positions;
    std::vector<std::vector<int>> faces;
    uint32_t badFaces = 0;  // faces whose corners name no vertex read

    om::VertexHandle add_vertex(const om::Vec3f& p) override {
        positions.push_back({p[0], p[1], p[2]});
        return om::VertexHandle(int(positions.size() - 1));
    }
    om::VertexHandle add_vertex() override { return add_vertex(om::Vec3f(0.0f, 0.0f, 0.0f)); }
    om::FaceHandle add_face(const VHandles& corners) override {
        std::vector<int> face;
        for (const om::VertexHandle& h : corners) {
            if (h.idx() < 0 || size_t(h.idx()) >= positions.size()) {
                ++badFaces;
                return om::FaceHandle();
            }
            face.push_back(h.idx());
        }
        faces.push_back(std::move(face));
        return om::FaceHandle(int(faces.size() - 1));
    }
    void set_point(om::VertexHandle h, const om::Vec3f& p) override {
        if (h.idx() >= 0 && size_t(h.idx()) < positions.size()) positions[size_t(h.idx())] = {p[0], p[1], p[2]};
    }
    size_t n_vertices() const override { return positions.size(); }
    size_t n_faces() const override { return faces.size(); }
    size_t n_edges() const override { return 0; }

    // Not kept: the half-edge structure (attributes: AttributeFreeImporter).
    om::HalfedgeHandle add_edge(om::VertexHandle, om::VertexHandle) override { return om::HalfedgeHandle(); }
    om::FaceHandle add_face(om::HalfedgeHandle) override { return om::FaceHandle(); }
    void set_next(om::HalfedgeHandle, om::HalfedgeHandle) override {}
    void set_face(om::HalfedgeHandle, om::FaceHandle) override {}
};

}  // namespace

bool isMeshCageExtension(const std::string& extension) {
    return extension == ".ply" || extension == ".off" || extension == ".stl" || extension == ".om";
}

Result<Cage> loadMeshCage(const std::string& path, std::vector<std::string>* warnings) {
    const std::string ext = lowercaseExtension(path);
    if (!isMeshCageExtension(ext)) return Error{path + ": not a PLY, OFF, STL or OM file"};
    Result<std::string> bytes = readFile(path);
    if (!bytes) return bytes.error();
    if (ext == ".om") return loadOmCage(path, *bytes);
    // OpenMesh's readers trust the file: it is walked first (mesh_file_check.h).
    Result<DeclaredCounts> declared = ext == ".ply" ? checkPlyFile(*bytes, path)
                                      : ext == ".off" ? checkOffFile(*bytes, path)
                                                      : checkStlFile(*bytes, path);
    if (!declared) return declared.error();

    CageImporter importer;
    om::IO::Options options;
    bool read = false;
    try {
        QuietOpenMesh quiet;
        read = om::IO::IOManager().read(path, importer, options);
    } catch (const std::exception& e) {
        return Error{path + ": the file could not be read (" + e.what() + ")"};
    }
    if (!read) return Error{path + ": OpenMesh could not parse it as " + ext.substr(1) + " (a corrupt or truncated file?)"};
    if (declared->vertices >= 0 && (long long)importer.positions.size() != declared->vertices)
        return Error{path + ": the header declares " + std::to_string(declared->vertices) + " vertices but " +
                     std::to_string(importer.positions.size()) + " could be read (a truncated file, or comments "
                     "where the reader does not take them?)"};
    if (importer.badFaces > 0)
        return Error{path + ": " + std::to_string(importer.badFaces) + " faces name vertices the file does not have "
                     "(or a number before them could not be read: 'nan', a stray word)"};
    if (declared->faces >= 0 && ext != ".stl" && (long long)importer.faces.size() != declared->faces)
        return Error{path + ": the header declares " + std::to_string(declared->faces) + " faces but the reader gave " +
                     std::to_string(importer.faces.size()) + ": faces with fewer than three corners or out-of-range "
                     "indices were skipped, so the file is refused rather than read in part"};
    if (ext == ".stl" && declared->faces >= 0 && (long long)importer.faces.size() != declared->faces)
        return Error{path + ": the binary STL declares " + std::to_string(declared->faces) + " triangles but " +
                     std::to_string(importer.faces.size()) + " could be read (degenerate triangles?)"};

    Cage cage;
    cage.positions = std::move(importer.positions);
    for (size_t f = 0; f < importer.faces.size(); ++f) {
        const std::vector<int>& face = importer.faces[f];
        if (face.size() < 3) return Error{path + ": face " + std::to_string(f + 1) + " has fewer than three corners"};
        std::vector<uint32_t> corners(face.begin(), face.end());
        cage.addFace(corners.data(), uint32_t(corners.size()));
    }
    if (Status valid = validateCage(cage, path); !valid) return valid.error();
    if (warnings && ext == ".stl")
        warnings->push_back(path + ": STL holds triangles only; its repeated corners were welded where equal");
    return cage;
}

}  // namespace qp
