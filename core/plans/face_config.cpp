#include "plans/face_config.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

constexpr uint32_t kKeyVersion = 1;

// The face across the edge (prev, vertex) of `f` (backwards) or (vertex, next): UINT32_MAX at a
// boundary or a non-manifold edge.
uint32_t faceAcross(const Cage& cage, const Topology& t, uint32_t vertex, uint32_t f, bool backwards) {
    const uint32_t* fv = cage.faceBegin(f);
    const uint32_t n = cage.faceSize(f), i = uint32_t(std::find(fv, fv + n, vertex) - fv);
    const uint32_t edge = t.faceEdges[cage.faceOffsets[f] + (backwards ? (i + n - 1) % n : i)];
    if (edge == UINT32_MAX || t.edgeFaceCount(edge) != 2) return UINT32_MAX;
    const uint32_t f0 = t.edgeFaces[t.edgeFaceOffsets[edge]], f1 = t.edgeFaces[t.edgeFaceOffsets[edge] + 1];
    return f0 == f ? f1 : f0;
}

// Faces around `vertex`, starting with `face`, rotating across manifold edges: first one way
// until a boundary (or back at the start), then the other way; faces reached only through
// non-manifold connections follow in adjacency order. Returns whether none did: the order then
// follows from the faces' connectivity alone.
bool facesAroundVertex(const Cage& cage, const Topology& t, uint32_t vertex, uint32_t face,
                       std::vector<uint32_t>& out) {
    out.clear();
    const uint32_t* all = &t.vertexFaces[t.vertexFaceOffsets[vertex]];
    const uint32_t count = t.vertexFaceCount(vertex);

    auto walk = [&](bool backwards) {
        uint32_t f = face;
        for (uint32_t step = 0; step < count; ++step) {
            const uint32_t next = faceAcross(cage, t, vertex, f, backwards);
            if (next == UINT32_MAX || next == face || std::find(out.begin(), out.end(), next) != out.end()) return;
            out.push_back(next);
            f = next;
        }
    };
    out.push_back(face);
    walk(true);
    walk(false);
    if (out.size() == count) return true;
    for (uint32_t i = 0; i < count; ++i)
        if (std::find(out.begin(), out.end(), all[i]) == out.end()) out.push_back(all[i]);
    return false;
}

// Whether `orbit` (facesAroundVertex from its first face, all of the vertex's faces) is one
// cycle of backward steps: the last face steps back to the first.
bool closesBackwards(const Cage& cage, const Topology& t, uint32_t vertex, const std::vector<uint32_t>& orbit) {
    for (size_t k = 0; k < orbit.size(); ++k)
        if (faceAcross(cage, t, vertex, orbit[k], true) != orbit[(k + 1) % orbit.size()]) return false;
    return true;
}

void pushFloat(std::vector<uint32_t>& key, float value) { key.push_back(std::bit_cast<uint32_t>(value)); }

uint32_t optionWord(const SubdivisionOptions& o) {
    return uint32_t(o.boundary) | uint32_t(o.creaseMethod) << 4 | uint32_t(o.triangleSubdivision) << 8;
}

// What gathering needs from each corner of the face, computed once for all start corners.
struct CornerInfo {
    uint32_t vertex;
    std::vector<uint32_t> orbit;                    // faces around it, starting at the face
    std::vector<std::pair<uint32_t, float>> sharp;  // (other end, sharpness) of creased edges at it
    float cornerSharpness;
    bool ordered;  // the orbit's order follows from connectivity (facesAroundVertex)
};

// The orbit of a cyclic vertex (GatherIndex) from `face`: its walk from any face is a rotation of
// the walk from its first face, so the stored cycle is rotated instead of walked again.
bool rotatedOrbit(const Topology& t, const GatherIndex& index, uint32_t vertex, uint32_t face,
                  std::vector<uint32_t>& out) {
    if (index.cyclic.empty() || !index.cyclic[vertex]) return false;
    const uint32_t* cycle = &index.orbitFaces[t.vertexFaceOffsets[vertex]];
    const uint32_t count = t.vertexFaceCount(vertex);
    const uint32_t at = uint32_t(std::find(cycle, cycle + count, face) - cycle);
    assert(at < count);
    out.assign(cycle + at, cycle + count);
    out.insert(out.end(), cycle, cycle + at);
    return true;
}

void gatherCorners(const Cage& cage, const Topology& t, uint32_t face, const GatherIndex* index,
                   std::vector<CornerInfo>& corners) {
    const uint32_t n = cage.faceSize(face);
    const uint32_t* fv = cage.faceBegin(face);
    corners.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
        CornerInfo& c = corners[i];
        c.vertex = fv[i];
        c.ordered = (index && rotatedOrbit(t, *index, c.vertex, face, c.orbit)) ||
                    facesAroundVertex(cage, t, c.vertex, face, c.orbit);
        c.sharp.clear();
        if (!cage.creases.empty() && (!index || index->withCreases.empty() || index->withCreases[c.vertex]))
            for (uint32_t k = t.vertexEdgeOffsets[c.vertex]; k < t.vertexEdgeOffsets[c.vertex + 1]; ++k) {
                uint32_t e = t.vertexEdges[k], a = t.edgeVertices[2 * e], b = t.edgeVertices[2 * e + 1];
                float sharpness = cage.edgeSharpness(a, b);
                if (sharpness > 0.0f) c.sharp.push_back({a + b - c.vertex, sharpness});
            }
        c.cornerSharpness = cage.vertexSharpness(c.vertex);
    }
}

}  // namespace

// Working arrays of one thread's gathering, kept from face to face (face_config.h).
struct GatherThread {
    std::vector<CornerInfo> corners;
    std::vector<uint32_t> added;
    std::vector<std::pair<uint64_t, float>> creases;
    FaceConfig best, candidate;
    // Quads whose orbits' order follows from connectivity: the hash of the key from corner 0 ->
    // the corner of the smallest key. A 64-bit collision would give a key from another corner:
    // a plan of that very configuration all the same, only not shared with its rotations.
    std::unordered_map<uint64_t, uint8_t> smallestFrom;
    uint64_t remembering = 0;  // forgetRememberedCorners' count when smallestFrom began
};

namespace {

std::atomic<uint64_t> forgottenCorners{0};
// A bound on smallestFrom, about 40 bytes an entry (a thread that reaches it starts over).
constexpr size_t kMaxRememberedFirstKeys = size_t(1) << 20;

// Key and ring for one choice of start corner.
void gatherFromCorner(const Cage& cage, uint32_t face, uint32_t start, const PlanOptions& options,
                      GatherThread& scratch, FaceConfig& out) {
    const std::vector<CornerInfo>& corners = scratch.corners;
    const uint32_t n = uint32_t(corners.size());
    std::vector<uint32_t>& ring = out.ring;
    ring.clear();
    auto localIndex = [&](uint32_t v) -> uint32_t {
        for (uint32_t i = 0; i < ring.size(); ++i)
            if (ring[i] == v) return i;
        ring.push_back(v);
        return uint32_t(ring.size() - 1);
    };
    for (uint32_t i = 0; i < n; ++i) localIndex(corners[(start + i) % n].vertex);

    std::vector<uint32_t>& key = out.key;
    key.assign({kKeyVersion, options.maxDepth, options.useCreaseNodes ? 1u : 0u, optionWord(cage.options), 0, 0});
    uint32_t faceCount = 0;
    auto appendFace = [&](uint32_t g, uint32_t from) {
        const uint32_t m = cage.faceSize(g);
        const uint32_t* gv = cage.faceBegin(g);
        const uint32_t offset = uint32_t(std::find(gv, gv + m, from) - gv);
        key.push_back(m);
        for (uint32_t j = 0; j < m; ++j) key.push_back(localIndex(gv[(offset + j) % m]));
        ++faceCount;
    };
    appendFace(face, corners[start].vertex);
    std::vector<uint32_t>& added = scratch.added;
    added.assign(1, face);
    for (uint32_t i = 0; i < n; ++i) {
        const CornerInfo& c = corners[(start + i) % n];
        for (uint32_t g : c.orbit) {
            if (std::find(added.begin(), added.end(), g) != added.end()) continue;
            added.push_back(g);
            appendFace(g, c.vertex);
        }
    }
    key[4] = uint32_t(ring.size());
    key[5] = faceCount;

    // Sharpness of the edges at the face's corners, by local vertex pair.
    std::vector<std::pair<uint64_t, float>>& creases = scratch.creases;
    creases.clear();
    for (uint32_t i = 0; i < n; ++i) {
        const CornerInfo& c = corners[(start + i) % n];
        for (const auto& [other, sharpness] : c.sharp) {
            uint32_t a = localIndex(c.vertex), b = localIndex(other);
            creases.push_back({uint64_t(std::min(a, b)) << 32 | std::max(a, b), sharpness});
        }
    }
    std::sort(creases.begin(), creases.end(), [](auto& x, auto& y) { return x.first < y.first; });
    creases.erase(std::unique(creases.begin(), creases.end(), [](auto& x, auto& y) { return x.first == y.first; }),
                  creases.end());
    key.push_back(uint32_t(creases.size()));
    for (const auto& [pair, sharpness] : creases) {
        key.push_back(uint32_t(pair >> 32));
        key.push_back(uint32_t(pair));
        pushFloat(key, sharpness);
    }

    uint32_t cornerCount = 0;
    size_t countAt = key.size();
    key.push_back(0);
    for (uint32_t i = 0; i < n; ++i) {
        float sharpness = corners[(start + i) % n].cornerSharpness;
        if (sharpness <= 0.0f) continue;
        key.push_back(i);
        pushFloat(key, sharpness);
        ++cornerCount;
    }
    key[countAt] = cornerCount;
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

void forgetRememberedCorners() { forgottenCorners.fetch_add(1, std::memory_order_relaxed); }

std::vector<uint8_t> verticesWithCreases(const Cage& cage) {
    std::vector<uint8_t> with(cage.vertexCount(), 0);
    for (const EdgeCrease& c : cage.creases)
        if (c.sharpness > 0.0f && c.v0 < with.size() && c.v1 < with.size()) with[c.v0] = with[c.v1] = 1;
    return with;
}

GatherIndex buildGatherIndex(const Cage& cage, const Topology& topology, bool withOrbits) {
    GatherIndex index;
    if (!cage.creases.empty()) index.withCreases = verticesWithCreases(cage);
    if (!withOrbits) return index;
    index.orbitFaces.resize(topology.vertexFaces.size());
    index.cyclic.assign(cage.vertexCount(), 0);
    const tbb::blocked_range<uint32_t> vertices(0, cage.vertexCount(), 4096);
    tbb::parallel_for(vertices, [&](const tbb::blocked_range<uint32_t>& range) {
        std::vector<uint32_t> orbit;
        for (uint32_t v = range.begin(); v != range.end(); ++v) {
            const uint32_t count = topology.vertexFaceCount(v);
            if (count == 0) continue;
            // The walk from the first face is a rotation of the walk from any other exactly when
            // stepping backwards face to face goes round once through all of them: each step
            // depends on the face alone, so from any face it follows the same cycle.
            const uint32_t first = topology.vertexFaces[topology.vertexFaceOffsets[v]];
            if (!facesAroundVertex(cage, topology, v, first, orbit) || !closesBackwards(cage, topology, v, orbit)) continue;
            std::copy(orbit.begin(), orbit.end(), index.orbitFaces.begin() + topology.vertexFaceOffsets[v]);
            index.cyclic[v] = 1;
        }
    });
    return index;
}

GatherThread& gatherThread() {
    thread_local GatherThread thread;
    return thread;
}

const FaceConfig& gatherFaceConfig(GatherThread& scratch, const Cage& cage, const Topology& topology, uint32_t face,
                                   uint32_t subface, const PlanOptions& options, const GatherIndex* index) {
    if (const uint64_t now = forgottenCorners.load(std::memory_order_relaxed); scratch.remembering != now) {
        scratch.smallestFrom.clear();
        scratch.remembering = now;
    }
    gatherCorners(cage, topology, face, index, scratch.corners);
    // Gathered into the thread's arrays, which keep their capacity from face to face (growing
    // fresh ones took several allocations a face).
    FaceConfig& best = scratch.best;
    auto result = [&](uint64_t hash) -> const FaceConfig& {
        best.hash = hash;
        return best;
    };
    if (cage.faceSize(face) != 4) {
        gatherFromCorner(cage, face, subface, options, scratch, best);
        best.rotation = 0;
        return result(hashKey(best.key));
    }
    // A quad's key from corner 0 tells its keys from every corner when its orbits' order follows
    // from connectivity: then a quad seen before with that first key had its smallest key at the
    // same corner, and only that corner is gathered again (most of a warm plan was gathering
    // every quad four times).
    gatherFromCorner(cage, face, 0, options, scratch, best);
    const uint64_t firstHash = hashKey(best.key);
    const bool ordered = std::all_of(scratch.corners.begin(), scratch.corners.end(),
                                     [](const CornerInfo& c) { return c.ordered; });
    if (ordered)
        if (auto seen = scratch.smallestFrom.find(firstHash); seen != scratch.smallestFrom.end()) {
            if (seen->second == 0) return result(firstHash);
            gatherFromCorner(cage, face, seen->second, options, scratch, best);
            return result(hashKey(best.key));
        }
    FaceConfig& candidate = scratch.candidate;
    for (uint32_t start = 1; start < 4; ++start) {
        gatherFromCorner(cage, face, start, options, scratch, candidate);
        if (candidate.key < best.key) std::swap(best, candidate);
    }
    if (ordered) {
        if (scratch.smallestFrom.size() >= kMaxRememberedFirstKeys) scratch.smallestFrom.clear();
        scratch.smallestFrom.emplace(firstHash, uint8_t(best.rotation));
    }
    return result(best.rotation == 0 ? firstHash : hashKey(best.key));
}

FaceConfig gatherFaceConfig(const Cage& cage, const Topology& topology, uint32_t face, uint32_t subface,
                            const PlanOptions& options, const GatherIndex* index) {
    const FaceConfig& gathered = gatherFaceConfig(gatherThread(), cage, topology, face, subface, options, index);
    return gathered;  // a copy in arrays of their exact size
}

}  // namespace qp
