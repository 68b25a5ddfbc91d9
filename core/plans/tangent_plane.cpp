#include "plans/tangent_plane.h"

#include <algorithm>
#include <complex>
#include <numeric>

#include <Eigen/Dense>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyLevel.h>
#include <opensubdiv/sdc/crease.h>

#include "plans/face_config.h"
#include "plans/osd_refiner.h"

namespace qp {

using namespace OpenSubdiv;

namespace {

bool sharpInTheLimit(const Far::TopologyLevel& level, Far::Index edge) {
    return level.IsEdgeInfSharp(edge) || level.IsEdgeBoundary(edge) || level.IsEdgeNonManifold(edge);
}

// The corner rule holds at every level: semi-sharp tags decay, infinitely sharp ones stay.
bool cornerRuleInTheLimit(const Far::TopologyLevel& level, Far::Index vertex) {
    if (level.IsVertexInfSharp(vertex) || level.GetVertexSharpness(vertex) >= Sdc::Crease::SHARPNESS_INFINITE) return true;
    int sharpEdges = 0;
    for (Far::Index e : level.GetVertexEdges(vertex)) sharpEdges += sharpInTheLimit(level, e) ? 1 : 0;
    return sharpEdges > 2;
}

// Per face at `vertex` (GetVertexFaces order), the number of faces of its sector: faces joined
// across edges at the vertex that are not sharp in the limit.
std::vector<int> sectorSizes(const Far::TopologyLevel& level, Far::Index vertex) {
    const Far::ConstIndexArray faces = level.GetVertexFaces(vertex);
    std::vector<int> parent(size_t(faces.size()));
    std::iota(parent.begin(), parent.end(), 0);
    auto root = [&](int i) {
        while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
        return i;
    };
    auto slot = [&](Far::Index face) { return int(std::find(faces.begin(), faces.end(), face) - faces.begin()); };
    for (Far::Index e : level.GetVertexEdges(vertex)) {
        if (sharpInTheLimit(level, e)) continue;
        const Far::ConstIndexArray edgeFaces = level.GetEdgeFaces(e);
        for (int k = 1; k < edgeFaces.size(); ++k) parent[size_t(root(slot(edgeFaces[k])))] = root(slot(edgeFaces[0]));
    }
    std::vector<int> size(faces.size(), 0);
    for (int i = 0; i < faces.size(); ++i) ++size[size_t(root(i))];
    std::vector<int> sizes(faces.size());
    for (int i = 0; i < faces.size(); ++i) sizes[size_t(i)] = size[size_t(root(i))];
    return sizes;
}

}  // namespace

Result<std::vector<SubfaceCorner>> cornersWithoutTangentPlane(const Cage& cage, const std::string& source) {
    Result<std::unique_ptr<Far::TopologyRefiner>> refiner = createRefiner(cage, source);
    if (!refiner) return refiner.error();
    const Far::TopologyLevel& level = (*refiner)->GetLevel(0);
    std::vector<uint32_t> firstSubface(size_t(level.GetNumFaces()));
    for (uint32_t f = 0, next = 0; f < firstSubface.size(); ++f) {
        firstSubface[f] = next;
        next += subfaceCount(uint32_t(level.GetFaceVertices(Far::Index(f)).size()));
    }
    std::vector<SubfaceCorner> corners;
    for (Far::Index v = 0; v < level.GetNumVertices(); ++v) {
        if (!cornerRuleInTheLimit(level, v)) continue;
        const Far::ConstIndexArray faces = level.GetVertexFaces(v);
        const Far::ConstLocalIndexArray inFace = level.GetVertexFaceLocalIndices(v);
        const std::vector<int> sizes = sectorSizes(level, v);
        for (int i = 0; i < faces.size(); ++i) {
            if (sizes[size_t(i)] < 2) continue;  // a regular corner
            const uint32_t face = uint32_t(faces[i]), k = uint32_t(inFace[i]);
            if (level.GetFaceVertices(faces[i]).size() == 4) corners.push_back({firstSubface[face], k});
            else corners.push_back({firstSubface[face] + k, 0});
        }
    }
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    return corners;
}

namespace {

// kColumns doubles per vertex: that many impulse responses through Far's refinement at once.
constexpr size_t kColumns = 16;
struct Impulses {
    double w[kColumns];
    void Clear(void* = nullptr) { std::fill(std::begin(w), std::end(w), 0.0); }
    void AddWithWeight(const Impulses& source, float weight) {
        for (size_t i = 0; i < kColumns; ++i) w[i] += double(weight) * source.w[i];
    }
};

// Infinitely sharp edges at an interior manifold vertex without other tags; -1 for any other.
int plainSharpEdges(const Far::TopologyLevel& level, Far::Index vertex) {
    if (level.IsVertexBoundary(vertex) || level.IsVertexNonManifold(vertex) || level.GetVertexSharpness(vertex) > 0.0f)
        return -1;
    int sharp = 0;
    for (Far::Index e : level.GetVertexEdges(vertex)) {
        if (sharpInTheLimit(level, e)) ++sharp;
        else if (level.GetEdgeSharpness(e) > 0.0f) return -1;
    }
    return sharp;
}

// `vertex` and every other vertex of the faces at it, each once.
std::vector<Far::Index> ringOf(const Far::TopologyLevel& level, Far::Index vertex) {
    std::vector<Far::Index> ring{vertex};
    for (Far::Index f : level.GetVertexFaces(vertex))
        for (Far::Index p : level.GetFaceVertices(f))
            if (std::find(ring.begin(), ring.end(), p) == ring.end()) ring.push_back(p);
    return ring;
}

// rows: `below` (vertices of level `to`) as combinations of `ring` (vertices of level to - 1);
// nothing when a row takes weight from outside the ring.
std::optional<Eigen::MatrixXd> refinementRows(const Far::TopologyRefiner& refiner, int to, std::span<const Far::Index> ring,
                                              std::span<const Far::Index> below) {
    const Far::PrimvarRefiner primvar(refiner);
    std::vector<Impulses> source(size_t(refiner.GetLevel(to - 1).GetNumVertices())),
        destination(size_t(refiner.GetLevel(to).GetNumVertices()));
    // Column ring.size(): every vertex outside the ring at once (the closure test).
    const size_t columns = ring.size() + 1;
    Eigen::MatrixXd rows(Eigen::Index(below.size()), Eigen::Index(columns));
    for (size_t firstColumn = 0; firstColumn < columns; firstColumn += kColumns) {
        const size_t count = std::min(kColumns, columns - firstColumn);
        const bool closure = firstColumn + count == columns;
        for (Impulses& impulse : source) {
            impulse.Clear();
            if (closure) impulse.w[count - 1] = 1.0;
        }
        for (size_t j = 0; j < ring.size(); ++j) {
            Impulses& impulse = source[size_t(ring[j])];
            if (closure) impulse.w[count - 1] = 0.0;
            if (j >= firstColumn && j < firstColumn + count) impulse.w[j - firstColumn] = 1.0;
        }
        const Impulses* from = source.data();
        Impulses* to_ = destination.data();
        primvar.Interpolate(to, from, to_);
        for (size_t i = 0; i < below.size(); ++i)
            for (size_t k = 0; k < count; ++k) rows(Eigen::Index(i), Eigen::Index(firstColumn + k)) = destination[size_t(below[i])].w[k];
    }
    if (rows.col(Eigen::Index(ring.size())).cwiseAbs().maxCoeff() > 1e-9) return std::nullopt;
    return Eigen::MatrixXd(rows.leftCols(Eigen::Index(ring.size())));
}

// The ring of a quad-only vertex at `level` one level down, point for point: the vertex's
// child, the edges' and the faces' children.
std::optional<std::vector<Far::Index>> childRing(const Far::TopologyLevel& level, std::span<const Far::Index> ring) {
    std::vector<Far::Index> below{level.GetVertexChildVertex(ring[0])};
    for (size_t i = 1; i < ring.size(); ++i) {
        const Far::Index edge = level.FindEdge(ring[0], ring[i]);
        if (edge >= 0) {
            below.push_back(level.GetEdgeChildVertex(edge));
            continue;
        }
        Far::Index face = -1;  // the face where ring[i] is the opposite corner
        for (Far::Index f : level.GetVertexFaces(ring[0])) {
            const Far::ConstIndexArray v = level.GetFaceVertices(f);
            if (v.size() == 4 && std::find(v.begin(), v.end(), ring[i]) != v.end()) face = f;
        }
        if (face < 0) return std::nullopt;
        below.push_back(level.GetFaceChildVertex(face));
    }
    for (Far::Index b : below)
        if (b < 0) return std::nullopt;  // not refined there
    return below;
}

}  // namespace

std::vector<double> ExactTangents::project(std::span<const double> mask) const {
    std::vector<double> out(ring.size(), 0.0);
    for (size_t k = 0; k < 2; ++k) {
        double along = 0.0;
        for (size_t j = 0; j < ring.size(); ++j) along += mask[j] * right[k][j];
        for (size_t j = 0; j < ring.size(); ++j) out[j] += along * left[k][j];
    }
    return out;
}

namespace {

// The exact tangent masks of level-1 vertex `child` over the level-0 vertices `ring0` it and its
// ring come from: level 1 -> 2, where every face is a quad (the same matrix at every level below
// when no tag there decays), then back to level 0 through the refinement.
std::optional<ExactTangents> tangentsOf(const Far::TopologyRefiner& refiner, Far::Index child, std::vector<Far::Index> ring0,
                                       bool dart) {
    if (refiner.GetNumLevels() < 3 || child < 0) return std::nullopt;
    const Far::TopologyLevel& first = refiner.GetLevel(1);
    const std::vector<Far::Index> ring1 = ringOf(first, child);
    std::optional<std::vector<Far::Index>> ring2 = childRing(first, ring1);
    if (!ring2 || ring1.size() != 1 + 2 * size_t(first.GetVertexFaces(child).size())) return std::nullopt;
    std::optional<Eigen::MatrixXd> down = refinementRows(refiner, 1, ring0, ring1);  // ring1 from ring0
    std::optional<Eigen::MatrixXd> map = refinementRows(refiner, 2, ring1, *ring2);
    if (!down || !map) return std::nullopt;

    Eigen::EigenSolver<Eigen::MatrixXd> solver(*map);
    const Eigen::VectorXcd values = solver.eigenvalues();
    std::vector<int> order(size_t(values.size()));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return std::abs(values[a]) > std::abs(values[b]); });
    if (order.size() < 4 || std::abs(values[order[0]] - 1.0) > 1e-5) return std::nullopt;
    const double gap = std::abs(values[order[2]]) - std::abs(values[order[3]]);
    if (std::abs(values[order[1]].imag()) > 1e-7 || std::abs(values[order[2]].imag()) > 1e-7 || gap < 1e-4) return std::nullopt;
    const Eigen::MatrixXcd right = solver.eigenvectors();
    Eigen::FullPivLU<Eigen::MatrixXcd> lu(right);
    if (!lu.isInvertible()) return std::nullopt;
    const Eigen::MatrixXcd left = lu.inverse();  // rows: left eigenvectors, left * right = I

    ExactTangents t;
    t.dart = dart;
    t.ring = std::move(ring0);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> pseudo(*down);
    for (size_t k = 0; k < 2; ++k) {
        const int mode = order[k + 1];
        const Eigen::RowVectorXd l1 = left.row(mode).real();
        const Eigen::VectorXd r1 = right.col(mode).real();
        // At level 0: left through the refinement (l A), right through its pseudo-inverse
        // (A A+ = I), so left . right stays the identity and Far's masks, which are level-1
        // masks composed with A, project as they would at level 1.
        const Eigen::RowVectorXd l0 = l1 * *down;
        const Eigen::VectorXd r0 = pseudo.solve(r1);
        t.left[k].assign(l0.data(), l0.data() + l0.size());
        t.right[k].assign(r0.data(), r0.data() + r0.size());
    }
    return t;
}

}  // namespace

std::optional<ExactTangents> exactTangents(const Far::TopologyRefiner& refiner, Far::Index vertex, bool smoothToo) {
    const Far::TopologyLevel& base = refiner.GetLevel(0);
    const int sharp = plainSharpEdges(base, vertex);
    if (sharp != 1 && !(smoothToo && sharp == 0)) return std::nullopt;
    return tangentsOf(refiner, base.GetVertexChildVertex(vertex), ringOf(base, vertex), sharp == 1);
}

std::optional<ExactTangents> faceCentreTangents(const Far::TopologyRefiner& refiner, Far::Index face) {
    const Far::TopologyLevel& base = refiner.GetLevel(0);
    std::vector<Far::Index> ring0;  // every vertex of the faces sharing a vertex with the face
    for (Far::Index v : base.GetFaceVertices(face))
        for (Far::Index f : base.GetVertexFaces(v))
            for (Far::Index p : base.GetFaceVertices(f))
                if (std::find(ring0.begin(), ring0.end(), p) == ring0.end()) ring0.push_back(p);
    return tangentsOf(refiner, base.GetFaceChildVertex(face), std::move(ring0), false);
}

}  // namespace qp
