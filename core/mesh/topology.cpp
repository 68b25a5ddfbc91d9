#include "mesh/topology.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include <tbb/parallel_invoke.h>

namespace qp {

namespace {

// Builds CSR arrays from the (key, value) pairs, keys < keyCount, that forEachPair(emit) emits
// (it is called twice: to count, then to fill), values of a key in emission order.
template <class ForEachPair>
void buildCsr(uint32_t keyCount, const ForEachPair& forEachPair, std::vector<uint32_t>& offsets, std::vector<uint32_t>& values) {
    offsets.assign(keyCount + 1, 0);
    forEachPair([&](uint32_t key, uint32_t) { ++offsets[key + 1]; });
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    values.resize(offsets.back());
    std::vector<uint32_t> cursor(offsets.begin(), offsets.end() - 1);
    forEachPair([&](uint32_t key, uint32_t value) { values[cursor[key]++] = value; });
}

// Smallest representative of x in a union-find forest.
uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

}  // namespace

uint32_t Topology::findEdge(uint32_t a, uint32_t b) const {
    if (a == b || a + 1 >= vertexEdgeOffsets.size()) return UINT32_MAX;
    for (uint32_t i = vertexEdgeOffsets[a]; i < vertexEdgeOffsets[a + 1]; ++i) {
        uint32_t e = vertexEdges[i];
        if (edgeVertices[2 * e] + edgeVertices[2 * e + 1] - a == b) return e;
    }
    return UINT32_MAX;
}

Topology buildTopology(const Cage& cage) {
    Topology t;
    const uint32_t faceVertexCount = uint32_t(cage.faceVertices.size());

    // Face-edge slots in (vertex pair, slot) order; equal pairs are one edge. Slots grouped by the
    // smaller vertex (a counting sort), then each vertex's few by the larger one: linear in the
    // cage, where one sort of every slot was not.
    auto forEachSlot = [&](auto&& visit) {  // visit(smaller vertex, larger vertex, slot)
        for (uint32_t f = 0; f < cage.faceCount(); ++f) {
            const uint32_t base = cage.faceOffsets[f], n = cage.faceSize(f);
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t a = cage.faceVertices[base + i], b = cage.faceVertices[base + (i + 1 < n ? i + 1 : 0)];
                visit(std::min(a, b), std::max(a, b), base + i);
            }
        }
    };
    std::vector<uint32_t> bucketOffsets(cage.vertexCount() + 1, 0);
    forEachSlot([&](uint32_t lo, uint32_t, uint32_t) { ++bucketOffsets[lo + 1]; });
    std::partial_sum(bucketOffsets.begin(), bucketOffsets.end(), bucketOffsets.begin());
    std::vector<std::pair<uint32_t, uint32_t>> slots(faceVertexCount);  // (larger vertex, slot) per bucket
    {
        std::vector<uint32_t> cursor(bucketOffsets.begin(), bucketOffsets.end() - 1);
        forEachSlot([&](uint32_t lo, uint32_t hi, uint32_t slot) { slots[cursor[lo]++] = {hi, slot}; });
    }

    t.faceEdges.resize(faceVertexCount);
    t.edgeVertices.reserve(faceVertexCount);  // two per edge: exact for a closed cage
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        const auto first = slots.begin() + bucketOffsets[v], last = slots.begin() + bucketOffsets[v + 1];
        // A bucket holds a vertex's few face corners: sorted by insertion, where std::sort's set-up
        // cost more than the sorting (this runs on every topology edit).
        if (last - first > 16) std::sort(first, last);
        else
            for (auto it = first + (first != last); it < last; ++it)
                for (auto at = it; at != first && *at < *(at - 1); --at) std::iter_swap(at, at - 1);
        for (auto it = first; it != last; ++it) {
            if (it == first || it->first != (it - 1)->first) {
                t.edgeVertices.push_back(v);
                t.edgeVertices.push_back(it->first);
            }
            t.faceEdges[it->second] = t.edgeCount() - 1;
        }
    }

    // The three adjacencies read only what is built above: one per core (a topology edit builds
    // them on every edit, in the frame that shows it).
    tbb::parallel_invoke(
        [&] {
            buildCsr(t.edgeCount(), [&](auto&& emit) {
                for (uint32_t f = 0; f < cage.faceCount(); ++f)
                    for (uint32_t i = cage.faceOffsets[f]; i < cage.faceOffsets[f + 1]; ++i) emit(t.faceEdges[i], f);
            }, t.edgeFaceOffsets, t.edgeFaces);
        },
        [&] {
            buildCsr(cage.vertexCount(), [&](auto&& emit) {
                for (uint32_t f = 0; f < cage.faceCount(); ++f)
                    for (uint32_t i = cage.faceOffsets[f]; i < cage.faceOffsets[f + 1]; ++i) emit(cage.faceVertices[i], f);
            }, t.vertexFaceOffsets, t.vertexFaces);
        },
        [&] {
            buildCsr(cage.vertexCount(), [&](auto&& emit) {
                for (uint32_t e = 0; e < t.edgeCount(); ++e) {
                    emit(t.edgeVertices[2 * e], e);
                    emit(t.edgeVertices[2 * e + 1], e);
                }
            }, t.vertexEdgeOffsets, t.vertexEdges);
        });
    return t;
}

std::vector<float> edgeSharpnesses(const Cage& cage, const Topology& topology) {
    std::vector<float> out(topology.edgeCount(), 0.0f);
    auto crease = cage.creases.begin();
    for (uint32_t e = 0; e < topology.edgeCount() && crease != cage.creases.end(); ++e) {
        const uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
        while (crease != cage.creases.end() && std::pair(crease->v0, crease->v1) < std::pair(a, b)) ++crease;
        if (crease != cage.creases.end() && crease->v0 == a && crease->v1 == b) out[e] = crease->sharpness;
    }
    return out;
}

CageStats computeStats(const Cage& cage, const Topology& t) {
    CageStats s;
    s.vertices = cage.vertexCount();
    s.faces = cage.faceCount();
    s.edges = t.edgeCount();
    for (uint32_t f = 0; f < cage.faceCount(); ++f) ++s.faceSizeHistogram[cage.faceSize(f)];

    // An edge is manifold when it has at most two faces that traverse it in opposite directions.
    std::vector<bool> manifoldEdge(t.edgeCount(), true);
    for (uint32_t e = 0; e < t.edgeCount(); ++e) {
        uint32_t count = t.edgeFaceCount(e);
        if (count == 1) ++s.boundaryEdges;
        if (count > 2) manifoldEdge[e] = false;
        if (count == 2) {
            int direction = 0;  // +1 per face running first->second, -1 per face running back
            for (uint32_t k = t.edgeFaceOffsets[e]; k < t.edgeFaceOffsets[e + 1]; ++k) {
                uint32_t f = t.edgeFaces[k], n = cage.faceSize(f);
                const uint32_t* fv = cage.faceBegin(f);
                for (uint32_t i = 0; i < n; ++i)
                    if (t.faceEdges[cage.faceOffsets[f] + i] == e)
                        direction += fv[i] == t.edgeVertices[2 * e] ? 1 : -1;
            }
            if (direction != 0) manifoldEdge[e] = false;
        }
        if (!manifoldEdge[e]) ++s.nonManifoldEdges;
    }

    // A vertex is manifold when its faces, joined across manifold edges at it, form one fan.
    std::vector<uint32_t> parent;
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        uint32_t valence = t.vertexEdgeCount(v);
        ++s.valenceHistogram[valence];
        uint32_t faceCount = t.vertexFaceCount(v);
        if (faceCount == 0) {
            ++s.isolatedVertices;
            continue;
        }
        bool manifold = true, boundary = false;
        const uint32_t* faces = &t.vertexFaces[t.vertexFaceOffsets[v]];
        parent.resize(faceCount);
        std::iota(parent.begin(), parent.end(), 0u);
        uint32_t components = faceCount;
        for (uint32_t k = t.vertexEdgeOffsets[v]; k < t.vertexEdgeOffsets[v + 1]; ++k) {
            uint32_t e = t.vertexEdges[k];
            if (!manifoldEdge[e]) manifold = false;
            if (t.edgeFaceCount(e) == 1) boundary = true;
            if (t.edgeFaceCount(e) != 2) continue;
            uint32_t f0 = t.edgeFaces[t.edgeFaceOffsets[e]], f1 = t.edgeFaces[t.edgeFaceOffsets[e] + 1];
            uint32_t i0 = uint32_t(std::find(faces, faces + faceCount, f0) - faces);
            uint32_t i1 = uint32_t(std::find(faces, faces + faceCount, f1) - faces);
            uint32_t r0 = findRoot(parent, i0), r1 = findRoot(parent, i1);
            if (r0 != r1) {
                parent[r0] = r1;
                --components;
            }
        }
        if (components != 1) manifold = false;
        if (!manifold) ++s.nonManifoldVertices;
        if (manifold && valence != (boundary ? 3u : 4u) && !(boundary && valence == 2)) ++s.extraordinaryVertices;
    }

    s.creasedEdges = uint32_t(cage.creases.size());
    for (const EdgeCrease& c : cage.creases)
        if (c.sharpness >= kInfiniteSharpness) ++s.infinitelySharpEdges;
    s.cornerVertices = uint32_t(cage.corners.size());
    s.holes = uint32_t(cage.holes.size());
    return s;
}

}  // namespace qp
