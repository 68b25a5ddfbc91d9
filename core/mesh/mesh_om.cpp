#include "mesh/mesh_om.h"

#include <sstream>

// OpenMesh's headers are slow to compile: this and mesh_import.cpp are the only translation
// units that read them.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/reader/OMReader.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "mesh/mesh_file_check.h"
#include "mesh/mesh_importer_base.h"

namespace qp {

namespace {

namespace om = OpenMesh;
using OmMesh = om::PolyMesh_ArrayKernelT<>;

constexpr const char* kCrease = "quadplan:crease";
constexpr const char* kCorner = "quadplan:corner";
constexpr const char* kHole = "quadplan:hole";
constexpr const char* kUv = "quadplan:uv";
constexpr const char* kUvIndex = "quadplan:uv_index";
constexpr const char* kHasUvs = "quadplan:uvs";
constexpr const char* kBoundary = "quadplan:boundary";
constexpr const char* kCreaseMethod = "quadplan:crease_method";
constexpr const char* kTriangles = "quadplan:triangles";
constexpr const char* kFVar = "quadplan:fvar";
constexpr const char* kFVarCorners = "quadplan:fvar_corners";

struct OmProperties {
    om::EPropHandleT<float> crease;
    om::VPropHandleT<float> corner;
    om::FPropHandleT<int> hole;
    om::HPropHandleT<om::Vec2f> uv;
    om::HPropHandleT<int> uvIndex;
    om::MPropHandleT<int> hasUvs, boundary, creaseMethod, triangles, fvar, fvarCorners;

    // Adds them to `mesh`, persistent, with the default options as values.
    void addTo(OmMesh& mesh) {
        mesh.add_property(crease, kCrease), mesh.add_property(corner, kCorner), mesh.add_property(hole, kHole);
        mesh.add_property(uv, kUv), mesh.add_property(uvIndex, kUvIndex);
        const SubdivisionOptions defaults;
        const std::pair<om::MPropHandleT<int>*, std::pair<const char*, int>> meshProperties[] = {
            {&hasUvs, {kHasUvs, 0}},
            {&boundary, {kBoundary, int(defaults.boundary)}},
            {&creaseMethod, {kCreaseMethod, int(defaults.creaseMethod)}},
            {&triangles, {kTriangles, int(defaults.triangleSubdivision)}},
            {&fvar, {kFVar, int(defaults.fvarInterpolation)}},
            {&fvarCorners, {kFVarCorners, int(defaults.fvarPropagateCorners)}}};
        for (const auto& [handle, nameAndValue] : meshProperties) {
            mesh.add_property(*handle, nameAndValue.first);
            mesh.property(*handle) = nameAndValue.second;
        }
    }
    void makePersistent(OmMesh& mesh, bool uvs) {
        mesh.property(crease).set_persistent(true), mesh.property(corner).set_persistent(true);
        mesh.property(hole).set_persistent(true);
        mesh.property(uv).set_persistent(uvs), mesh.property(uvIndex).set_persistent(uvs);
        for (auto* handle : {&hasUvs, &boundary, &creaseMethod, &triangles, &fvar, &fvarCorners})
            mesh.mproperty(*handle).set_persistent(true);
    }
};

// OpenMesh's .om reader builds its mesh through an importer. This one keeps the records as they
// come (positions, each half-edge's target, next and face, each face's first half-edge) and lets
// the reader restore named properties into `host`, a kernel sized to the header's counts that
// holds nothing else; the faces are rebuilt afterwards with every index checked.
class OmRecords final : public AttributeFreeImporter {
public:
    OmMesh host;
    OmProperties properties;
    std::vector<glm::vec3> positions;
    std::vector<int> target, next, faceOf;  // per half-edge
    std::vector<int> faceHalfedge;         // per face (version 2 files)
    std::vector<std::vector<int>> faceLists;  // per face (older files: vertex lists)
    uint32_t outOfRange = 0;                // records naming a half-edge that does not exist

    OmRecords(const OmCounts& counts) {
        for (uint32_t v = 0; v < counts.vertices; ++v) host.new_vertex();
        for (uint32_t e = 0; e < counts.edges; ++e) host.new_edge(om::VertexHandle(0), om::VertexHandle(0));
        for (uint32_t f = 0; f < counts.faces; ++f) host.new_face();
        properties.addTo(host);
    }

    om::BaseKernel* kernel() override { return &host; }
    om::VertexHandle add_vertex(const om::Vec3f& p) override {
        positions.push_back({p[0], p[1], p[2]});
        return om::VertexHandle(int(positions.size() - 1));
    }
    om::VertexHandle add_vertex(const om::Vec3d& p) override { return add_vertex(om::Vec3f(p)); }
    om::VertexHandle add_vertex() override { return add_vertex(om::Vec3f(0.0f, 0.0f, 0.0f)); }
    om::HalfedgeHandle add_edge(om::VertexHandle from, om::VertexHandle to) override {
        target.push_back(to.idx()), target.push_back(from.idx());
        next.push_back(-1), next.push_back(-1);
        faceOf.push_back(-1), faceOf.push_back(-1);
        return om::HalfedgeHandle(int(target.size() - 2));
    }
    void set_next(om::HalfedgeHandle h, om::HalfedgeHandle n) override {
        if (valid(h)) next[size_t(h.idx())] = n.idx();
    }
    void set_face(om::HalfedgeHandle h, om::FaceHandle f) override {
        if (valid(h)) faceOf[size_t(h.idx())] = f.idx();
    }
    om::FaceHandle add_face(om::HalfedgeHandle h) override {
        faceHalfedge.push_back(h.idx());
        return om::FaceHandle(int(faceHalfedge.size() - 1));
    }
    om::FaceHandle add_face(const VHandles& corners) override {
        std::vector<int> face;
        for (const om::VertexHandle& v : corners) face.push_back(v.idx());
        faceLists.push_back(std::move(face));
        return om::FaceHandle(int(faceLists.size() - 1));
    }
    size_t n_vertices() const override { return positions.size(); }
    size_t n_faces() const override { return faceHalfedge.size() + faceLists.size(); }
    size_t n_edges() const override { return target.size() / 2; }

    // Positions come from add_vertex; attributes are dropped (AttributeFreeImporter).
    void set_point(om::VertexHandle, const om::Vec3f&) override {}

private:
    bool valid(om::HalfedgeHandle h) {
        if (h.idx() >= 0 && size_t(h.idx()) < target.size()) return true;
        ++outOfRange;
        return false;
    }
};

// Face f's corners from its half-edge loop (each half-edge's start: its twin's target), and
// per corner the half-edge that starts there.
Status walkFace(const OmRecords& r, uint32_t f, std::vector<uint32_t>& corners, std::vector<int>& halfedges,
                std::vector<uint8_t>& used, const std::string& path) {
    const std::string face = path + ": face " + std::to_string(f);
    const int first = r.faceHalfedge[f];
    const int count = int(r.target.size());
    corners.clear(), halfedges.clear();
    int h = first;
    do {
        if (h < 0 || h >= count) return Error{face + ": its loop names half-edge " + std::to_string(h) + ", which does not exist"};
        if (r.faceOf[size_t(h)] != int(f)) return Error{face + ": its loop runs through a half-edge of another face"};
        if (used[size_t(h)]) return Error{face + ": its loop does not close (a half-edge is visited twice)"};
        used[size_t(h)] = 1;
        const int from = r.target[size_t(h ^ 1)];
        if (from < 0 || size_t(from) >= r.host.n_vertices())
            return Error{face + ": a corner names vertex " + std::to_string(from) + ", which does not exist"};
        corners.push_back(uint32_t(from));
        halfedges.push_back(h);
        h = r.next[size_t(h)];
    } while (h != first);
    if (corners.size() < 3) return Error{face + ": it has fewer than three corners"};
    return success();
}

}  // namespace

Result<Cage> loadOmCage(const std::string& path, const std::string& bytes) {
    Result<OmCounts> counts = checkOmFile(bytes, path);
    if (!counts) return counts.error();
    OmRecords records(*counts);
    om::IO::Options options = om::IO::Options::Binary;
    std::string kept;  // the file without its variable-sized custom chunks (OmCounts::skippedChunks)
    size_t from = 0;
    for (auto [first, end] : counts->skippedChunks) kept.append(bytes, from, first - from), from = end;
    kept.append(bytes, from, std::string::npos);
    bool read = false;
    try {
        QuietOpenMesh quiet;
        std::istringstream stream(kept);
        stream.unsetf(std::ios::skipws);
        read = om::IO::OMReader().read(stream, records, options);
    } catch (const std::exception& e) {
        return Error{path + ": the file could not be read (" + e.what() + ")"};
    }
    if (!read) return Error{path + ": OpenMesh could not parse it as .om (a corrupt or truncated file?)"};
    if (records.positions.size() != counts->vertices)
        return Error{path + ": the header declares " + std::to_string(counts->vertices) + " vertices but " +
                     std::to_string(records.positions.size()) + " positions were read"};
    if (records.outOfRange > 0 || records.target.size() != 2 * size_t(counts->edges))
        return Error{path + ": the half-edge records do not match the header's " + std::to_string(counts->edges) + " edges"};
    if (records.n_faces() != counts->faces)
        return Error{path + ": the header declares " + std::to_string(counts->faces) + " faces but " +
                     std::to_string(records.n_faces()) + " were read"};

    const OmProperties& p = records.properties;
    const OmMesh& host = records.host;
    Cage cage;
    cage.positions = std::move(records.positions);
    const bool uvs = host.property(p.hasUvs) != 0;
    std::vector<uint32_t> corners;
    std::vector<int> halfedges;
    std::vector<uint8_t> used(records.target.size(), 0);
    for (uint32_t f = 0; f < counts->faces; ++f) {
        if (!records.faceLists.empty()) {  // before version 2: vertex lists, no half-edge properties
            corners.clear();
            for (int v : records.faceLists[f]) {
                if (v < 0 || size_t(v) >= cage.positions.size())
                    return Error{path + ": face " + std::to_string(f) + " names vertex " + std::to_string(v) + ", which does not exist"};
                corners.push_back(uint32_t(v));
            }
        } else if (Status walked = walkFace(records, f, corners, halfedges, used, path); !walked) {
            return walked.error();
        }
        cage.addFace(corners.data(), uint32_t(corners.size()));
        if (uvs && records.faceLists.empty())
            for (int h : halfedges) {  // each corner's UV, and its index so seams stay seams
                const int index = host.property(p.uvIndex, om::HalfedgeHandle(h));
                if (index < 0 || size_t(index) >= records.target.size())
                    return Error{path + ": face " + std::to_string(f) + " has a texture coordinate index out of range"};
                if (size_t(index) >= cage.uvs.size()) cage.uvs.resize(size_t(index) + 1, glm::vec2(0.0f));
                const om::Vec2f uv = host.property(p.uv, om::HalfedgeHandle(h));
                cage.uvs[size_t(index)] = {uv[0], uv[1]};
                cage.faceUVIndices.push_back(uint32_t(index));
            }
    }
    for (uint32_t e = 0; e < counts->edges && records.faceLists.empty(); ++e) {
        const float sharpness = host.property(p.crease, om::EdgeHandle(int(e)));
        if (sharpness == 0.0f) continue;
        const int a = records.target[2 * e + 1], b = records.target[2 * e];
        if (a < 0 || b < 0 || size_t(a) >= cage.positions.size() || size_t(b) >= cage.positions.size() || a == b)
            return Error{path + ": a crease is on edge " + std::to_string(e) + ", whose ends are not two vertices of the cage"};
        cage.creases.push_back({uint32_t(std::min(a, b)), uint32_t(std::max(a, b)), sharpness});
    }
    for (uint32_t v = 0; v < counts->vertices; ++v)
        if (const float sharpness = host.property(p.corner, om::VertexHandle(int(v))); sharpness != 0.0f)
            cage.corners.push_back({v, sharpness});
    for (uint32_t f = 0; f < counts->faces; ++f)
        if (host.property(p.hole, om::FaceHandle(int(f))) != 0) cage.holes.push_back(f);
    auto option = [&](om::MPropHandleT<int> handle, int count, const char* what) -> Result<int> {
        const int value = host.property(handle);
        if (value < 0 || value >= count) return Error{path + ": the " + std::string(what) + " " + std::to_string(value) + " is unknown"};
        return value;
    };
    Result<int> boundary = option(p.boundary, 3, "boundary rule"), creaseMethod = option(p.creaseMethod, 2, "crease method"),
                triangles = option(p.triangles, 2, "triangle rule"), fvar = option(p.fvar, 6, "face-varying rule");
    for (const Result<int>* r : {&boundary, &creaseMethod, &triangles, &fvar})
        if (!*r) return r->error();
    cage.options.boundary = BoundaryInterpolation(*boundary);
    cage.options.creaseMethod = CreaseMethod(*creaseMethod);
    cage.options.triangleSubdivision = TriangleSubdivision(*triangles);
    cage.options.fvarInterpolation = FVarInterpolation(*fvar);
    cage.options.fvarPropagateCorners = host.property(p.fvarCorners) != 0;
    normalizeTags(cage);
    if (Status valid = validateCage(cage, path); !valid) return valid.error();
    return cage;
}

Result<std::string> omCageBytes(const Cage& cage, const std::string& path) {
    OmMesh mesh;
    OmProperties p;
    p.addTo(mesh);
    for (const glm::vec3& v : cage.positions) mesh.add_vertex(OmMesh::Point(v.x, v.y, v.z));
    std::vector<uint32_t> refused;
    {
        QuietOpenMesh quiet;  // the kernel reports each complex face; the error below names them all
        for (uint32_t f = 0; f < cage.faceCount(); ++f) {
            std::vector<om::VertexHandle> corners;
            for (uint32_t k = 0; k < cage.faceSize(f); ++k) corners.push_back(om::VertexHandle(int(cage.faceBegin(f)[k])));
            const om::FaceHandle face = mesh.add_face(corners);
            if (!face.is_valid()) {
                refused.push_back(f);
                continue;
            }
            // The face's half-edge is the one leaving its first corner, so its loop reads back from there.
            for (om::HalfedgeHandle h : mesh.fh_range(face))
                if (mesh.from_vertex_handle(h) == corners[0]) mesh.set_halfedge_handle(face, h);
        }
    }
    if (!refused.empty()) {
        std::string list;
        for (size_t i = 0; i < refused.size() && i < 8; ++i) list += (i ? ", " : "") + std::to_string(refused[i]);
        if (refused.size() > 8) list += " and " + std::to_string(refused.size() - 8) + " more";
        return Error{"cannot write '" + path + "' as .om: OpenMesh's half-edge mesh cannot hold the non-manifold face" +
                     std::string(refused.size() > 1 ? "s " : " ") + list + " (save it as .obj, which can)"};
    }
    for (const EdgeCrease& c : cage.creases) {
        const om::HalfedgeHandle h = mesh.find_halfedge(om::VertexHandle(int(c.v0)), om::VertexHandle(int(c.v1)));
        if (h.is_valid()) mesh.property(p.crease, mesh.edge_handle(h)) = c.sharpness;
    }
    for (const VertexCorner& c : cage.corners) mesh.property(p.corner, om::VertexHandle(int(c.vertex))) = c.sharpness;
    for (uint32_t f : cage.holes) mesh.property(p.hole, om::FaceHandle(int(f))) = 1;
    const bool uvs = !cage.uvs.empty() && cage.faceUVIndices.size() == cage.faceVertices.size();
    for (om::HalfedgeHandle h : mesh.halfedges()) mesh.property(p.uvIndex, h) = -1;
    if (uvs) {
        for (uint32_t f = 0; f < cage.faceCount(); ++f) {
            om::HalfedgeHandle h = mesh.halfedge_handle(om::FaceHandle(int(f)));
            for (uint32_t k = 0; k < cage.faceSize(f); ++k, h = mesh.next_halfedge_handle(h)) {
                const uint32_t index = cage.faceUVIndices[cage.faceOffsets[f] + k];
                mesh.property(p.uvIndex, h) = int(index);
                mesh.property(p.uv, h) = om::Vec2f(cage.uvs[index].x, cage.uvs[index].y);
            }
        }
    }
    mesh.property(p.hasUvs) = uvs ? 1 : 0;
    mesh.property(p.boundary) = int(cage.options.boundary);
    mesh.property(p.creaseMethod) = int(cage.options.creaseMethod);
    mesh.property(p.triangles) = int(cage.options.triangleSubdivision);
    mesh.property(p.fvar) = int(cage.options.fvarInterpolation);
    mesh.property(p.fvarCorners) = cage.options.fvarPropagateCorners ? 1 : 0;
    p.makePersistent(mesh, uvs);
    std::ostringstream out;
    bool written = false;
    try {
        QuietOpenMesh quiet;
        written = om::IO::write_mesh(mesh, out, ".om", om::IO::Options::Binary);
    } catch (const std::exception& e) {
        return Error{"cannot write '" + path + "' as .om: " + e.what()};
    }
    if (!written) return Error{"cannot write '" + path + "' as .om: OpenMesh's writer failed"};
    return out.str();
}

}  // namespace qp
