#include "mesh/closed_surface.h"

#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>

namespace qp {

namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

}  // namespace

bool closedOutwardSurface(const Cage& cage, const Topology& topology) {
    if (!cage.holes.empty() || cage.faceCount() == 0) return false;
    std::vector<uint32_t> piece(cage.faceCount());
    std::iota(piece.begin(), piece.end(), 0u);
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
        if (topology.edgeFaceCount(e) != 2) return false;
        const uint32_t f0 = topology.edgeFaces[topology.edgeFaceOffsets[e]];
        const uint32_t f1 = topology.edgeFaces[topology.edgeFaceOffsets[e] + 1];
        // The direction each face walks the edge: consistent orientation has them opposite.
        auto forward = [&](uint32_t face) {
            const uint32_t n = cage.faceSize(face), *v = cage.faceBegin(face);
            for (uint32_t k = 0; k < n; ++k)
                if (topology.faceEdges[cage.faceOffsets[face] + k] == e) return v[k] == topology.edgeVertices[2 * e];
            return false;
        };
        if (f0 == f1 || forward(f0) == forward(f1)) return false;
        piece[findRoot(piece, f0)] = findRoot(piece, f1);
    }
    // Signed volumes per piece (the divergence theorem over each face's fan of triangles).
    std::vector<double> volume(cage.faceCount(), 0.0);
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& p : cage.positions) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t n = cage.faceSize(f), *v = cage.faceBegin(f);
        const glm::dvec3 a(cage.positions[v[0]]);
        double sum = 0.0;
        for (uint32_t k = 1; k + 1 < n; ++k)
            sum += glm::dot(a, glm::cross(glm::dvec3(cage.positions[v[k]]), glm::dvec3(cage.positions[v[k + 1]])));
        volume[findRoot(piece, f)] += sum / 6.0;
    }
    const double diagonal = glm::length(hi - lo);
    const double least = 1e-4 * diagonal * diagonal * diagonal;
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        if (findRoot(piece, f) == f && !(volume[f] > least)) return false;
    return true;
}

}  // namespace qp
