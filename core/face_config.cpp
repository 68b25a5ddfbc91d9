#include "face_config.h"

#include <algorithm>
#include <bit>
#include <cassert>

namespace qp {

namespace {

constexpr uint32_t kKeyVersion = 1;

// Faces around `vertex`, starting with `face`, rotating across manifold edges: first one way
// until a boundary (or back at the start), then the other way; faces reached only through
// non-manifold connections follow in adjacency order.
void facesAroundVertex(const Cage& cage, const Topology& t, uint32_t vertex, uint32_t face,
                       std::vector<uint32_t>& out) {
    out.clear();
    const uint32_t* all = &t.vertexFaces[t.vertexFaceOffsets[vertex]];
    const uint32_t count = t.vertexFaceCount(vertex);

    auto positionIn = [&](uint32_t f) {
        const uint32_t* fv = cage.faceBegin(f);
        return uint32_t(std::find(fv, fv + cage.faceSize(f), vertex) - fv);
    };
    auto otherFace = [&](uint32_t edge, uint32_t f) -> uint32_t {
        if (edge == UINT32_MAX || t.edgeFaceCount(edge) != 2) return UINT32_MAX;
        uint32_t f0 = t.edgeFaces[t.edgeFaceOffsets[edge]], f1 = t.edgeFaces[t.edgeFaceOffsets[edge] + 1];
        return f0 == f ? f1 : f0;
    };
    auto walk = [&](bool backwards) {
        uint32_t f = face;
        for (uint32_t step = 0; step < count; ++step) {
            uint32_t n = cage.faceSize(f), i = positionIn(f);
            uint32_t slot = backwards ? (i + n - 1) % n : i;  // edge (prev, v) or (v, next)
            uint32_t next = otherFace(t.faceEdges[cage.faceOffsets[f] + slot], f);
            if (next == UINT32_MAX || next == face || std::find(out.begin(), out.end(), next) != out.end()) return;
            out.push_back(next);
            f = next;
        }
    };
    out.push_back(face);
    walk(true);
    walk(false);
    for (uint32_t i = 0; i < count; ++i)
        if (std::find(out.begin(), out.end(), all[i]) == out.end()) out.push_back(all[i]);
}

void pushFloat(std::vector<uint32_t>& key, float value) { key.push_back(std::bit_cast<uint32_t>(value)); }

uint32_t optionWord(const SubdivisionOptions& o) {
    return uint32_t(o.boundary) | uint32_t(o.creaseMethod) << 4 | uint32_t(o.triangleSubdivision) << 8;
}

// Key and ring for one choice of start corner.
void gatherFromCorner(const Cage& cage, const Topology& t, uint32_t face, uint32_t start, const PlanOptions& options,
                      FaceConfig& out) {
    const uint32_t n = cage.faceSize(face);
    const uint32_t* fv = cage.faceBegin(face);
    std::vector<uint32_t>& ring = out.ring;
    ring.clear();
    std::vector<uint32_t> localFaces;  // faces in local order
    std::vector<uint32_t> localStart;  // the corner each local face starts at

    auto localIndex = [&](uint32_t v) -> uint32_t {
        auto it = std::find(ring.begin(), ring.end(), v);
        if (it != ring.end()) return uint32_t(it - ring.begin());
        ring.push_back(v);
        return uint32_t(ring.size() - 1);
    };

    for (uint32_t i = 0; i < n; ++i) localIndex(fv[(start + i) % n]);
    localFaces.push_back(face);
    localStart.push_back(fv[start]);

    std::vector<uint32_t> around;
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t corner = fv[(start + i) % n];
        facesAroundVertex(cage, t, corner, face, around);
        for (uint32_t g : around) {
            if (std::find(localFaces.begin(), localFaces.end(), g) != localFaces.end()) continue;
            localFaces.push_back(g);
            localStart.push_back(corner);
        }
    }

    std::vector<uint32_t>& key = out.key;
    key = {kKeyVersion, options.maxDepth, options.useCreaseNodes ? 1u : 0u, optionWord(cage.options), 0,
           uint32_t(localFaces.size())};
    for (size_t k = 0; k < localFaces.size(); ++k) {
        uint32_t g = localFaces[k], m = cage.faceSize(g);
        const uint32_t* gv = cage.faceBegin(g);
        uint32_t offset = uint32_t(std::find(gv, gv + m, localStart[k]) - gv);
        key.push_back(m);
        for (uint32_t j = 0; j < m; ++j) key.push_back(localIndex(gv[(offset + j) % m]));
    }
    key[4] = uint32_t(ring.size());

    // Sharpness of the edges at the face's corners (local indices 0..n-1), sorted by local pair.
    std::vector<std::pair<uint64_t, float>> creases;
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t corner = fv[(start + i) % n];
        for (uint32_t k = t.vertexEdgeOffsets[corner]; k < t.vertexEdgeOffsets[corner + 1]; ++k) {
            uint32_t e = t.vertexEdges[k];
            float s = cage.edgeSharpness(t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1]);
            if (s <= 0.0f) continue;
            uint32_t a = localIndex(t.edgeVertices[2 * e]), b = localIndex(t.edgeVertices[2 * e + 1]);
            creases.push_back({uint64_t(std::min(a, b)) << 32 | std::max(a, b), s});
        }
    }
    std::sort(creases.begin(), creases.end(), [](auto& x, auto& y) { return x.first < y.first; });
    creases.erase(std::unique(creases.begin(), creases.end(), [](auto& x, auto& y) { return x.first == y.first; }),
                  creases.end());
    key.push_back(uint32_t(creases.size()));
    for (const auto& [pair, s] : creases) {
        key.push_back(uint32_t(pair >> 32));
        key.push_back(uint32_t(pair));
        pushFloat(key, s);
    }

    std::vector<std::pair<uint32_t, float>> corners;
    for (uint32_t i = 0; i < n; ++i) {
        float s = cage.vertexSharpness(fv[(start + i) % n]);
        if (s > 0.0f) corners.push_back({i, s});
    }
    key.push_back(uint32_t(corners.size()));
    for (const auto& [local, s] : corners) {
        key.push_back(local);
        pushFloat(key, s);
    }
    out.rotation = start;
}

}  // namespace

uint64_t hashKey(const std::vector<uint32_t>& key) {
    uint64_t h = 1469598103934665603ull;  // FNV-1a over the words
    for (uint32_t w : key) {
        h ^= w;
        h *= 1099511628211ull;
    }
    return h;
}

FaceConfig gatherFaceConfig(const Cage& cage, const Topology& topology, uint32_t face, uint32_t subface,
                            const PlanOptions& options) {
    assert(!cage.isHole(face));
    FaceConfig best;
    const uint32_t n = cage.faceSize(face);
    if (n != 4) {
        gatherFromCorner(cage, topology, face, subface, options, best);
        best.rotation = 0;
    } else {
        FaceConfig candidate;
        for (uint32_t start = 0; start < 4; ++start) {
            gatherFromCorner(cage, topology, face, start, options, start == 0 ? best : candidate);
            if (start > 0 && candidate.key < best.key) std::swap(best, candidate);
        }
    }
    best.hash = hashKey(best.key);
    return best;
}

}  // namespace qp
