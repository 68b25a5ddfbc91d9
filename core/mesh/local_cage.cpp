#include "mesh/local_cage.h"

#include <algorithm>

namespace qp {

LocalCage localCage(const Cage& cage, std::span<const uint32_t> faces, bool withUVs) {
    LocalCage out;
    out.cage.options = cage.options;
    withUVs &= !cage.faceUVIndices.empty();
    std::vector<uint32_t> localOf(cage.vertexCount(), UINT32_MAX), localUVOf;
    if (withUVs) localUVOf.assign(cage.uvs.size(), UINT32_MAX);
    std::vector<uint64_t> edges;  // (min, max) of every local face edge, global numbers
    std::vector<uint32_t> local;
    for (uint32_t f : faces) {
        const uint32_t n = cage.faceSize(f);
        const uint32_t* v = cage.faceBegin(f);
        local.resize(n);
        for (uint32_t k = 0; k < n; ++k) {
            if (localOf[v[k]] == UINT32_MAX) {
                localOf[v[k]] = uint32_t(out.globalVertex.size());
                out.globalVertex.push_back(v[k]);
                out.cage.positions.push_back(cage.positions[v[k]]);
            }
            local[k] = localOf[v[k]];
            const uint32_t a = v[k], b = v[(k + 1) % n];
            edges.push_back(uint64_t(std::min(a, b)) << 32 | std::max(a, b));
        }
        out.cage.addFace(local.data(), n);
        if (cage.isHole(f)) out.cage.holes.push_back(out.cage.faceCount() - 1);
        if (!withUVs) continue;
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t uv = cage.faceUVIndices[cage.faceOffsets[f] + k];
            if (localUVOf[uv] == UINT32_MAX) {
                localUVOf[uv] = uint32_t(out.cage.uvs.size());
                out.cage.uvs.push_back(cage.uvs[uv]);
            }
            out.cage.faceUVIndices.push_back(localUVOf[uv]);
        }
    }
    std::sort(edges.begin(), edges.end());
    for (const EdgeCrease& c : cage.creases)
        if (std::binary_search(edges.begin(), edges.end(), uint64_t(c.v0) << 32 | c.v1))
            out.cage.creases.push_back({localOf[c.v0], localOf[c.v1], c.sharpness});
    for (const VertexCorner& c : cage.corners)
        if (localOf[c.vertex] != UINT32_MAX) out.cage.corners.push_back({localOf[c.vertex], c.sharpness});
    for (EdgeCrease& c : out.cage.creases)
        if (c.v0 > c.v1) std::swap(c.v0, c.v1);
    normalizeTags(out.cage);
    return out;
}

}  // namespace qp
