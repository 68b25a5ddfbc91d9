#include "edit/selection.h"

#include <algorithm>
#include <cassert>

namespace qp {

namespace {

template <class T>
void sortUnique(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

template <class T>
void combine(std::vector<T>& current, SelectOp op, std::span<const T> picked) {
    std::vector<T> p(picked.begin(), picked.end());
    sortUnique(p);
    std::vector<T> out;
    switch (op) {
    case SelectOp::Replace: out = std::move(p); break;
    case SelectOp::Add: std::set_union(current.begin(), current.end(), p.begin(), p.end(), std::back_inserter(out)); break;
    case SelectOp::Toggle:
        std::set_symmetric_difference(current.begin(), current.end(), p.begin(), p.end(), std::back_inserter(out));
        break;
    case SelectOp::Remove:
        std::set_difference(current.begin(), current.end(), p.begin(), p.end(), std::back_inserter(out));
        break;
    }
    current = std::move(out);
}

EdgeKey edgeAt(const Topology& t, uint32_t e) { return {t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1]}; }

template <class T>
bool has(const std::vector<T>& sorted, const T& x) {
    return std::binary_search(sorted.begin(), sorted.end(), x);
}

std::vector<bool> vertexMask(const std::vector<uint32_t>& vertices, uint32_t count) {
    std::vector<bool> mask(count, false);
    for (uint32_t v : vertices) mask[v] = true;
    return mask;
}

}  // namespace

size_t Selection::size() const {
    switch (mode) {
    case SelectionMode::Vertex: return vertices.size();
    case SelectionMode::Edge: return edges.size();
    case SelectionMode::Face: return faces.size();
    }
    return 0;
}

void applyPick(Selection& selection, SelectOp op, std::span<const uint32_t> elements) {
    assert(selection.mode != SelectionMode::Edge && "edges are picked as EdgeKeys");
    combine(selection.mode == SelectionMode::Face ? selection.faces : selection.vertices, op, elements);
}

void applyPick(Selection& selection, SelectOp op, std::span<const EdgeKey> edges) {
    std::vector<EdgeKey> normalised;
    for (const EdgeKey& e : edges) normalised.push_back(makeEdgeKey(e.v0, e.v1));
    combine(selection.edges, op, std::span<const EdgeKey>(normalised));
}

Selection selectAll(const Cage& cage, const Topology& topology, SelectionMode mode) {
    Selection s;
    s.mode = mode;
    if (mode == SelectionMode::Vertex) {
        // Only vertices that some face uses: bare vertices are not part of the surface.
        for (uint32_t v = 0; v < cage.vertexCount(); ++v)
            if (topology.vertexFaceCount(v) > 0) s.vertices.push_back(v);
    } else if (mode == SelectionMode::Edge) {
        for (uint32_t e = 0; e < topology.edgeCount(); ++e) s.edges.push_back(edgeAt(topology, e));
    } else {
        for (uint32_t f = 0; f < cage.faceCount(); ++f) s.faces.push_back(f);
    }
    return s;
}

Selection invertSelection(const Selection& selection, const Cage& cage, const Topology& topology) {
    Selection all = selectAll(cage, topology, selection.mode);
    Selection out;
    out.mode = selection.mode;
    std::set_difference(all.vertices.begin(), all.vertices.end(), selection.vertices.begin(), selection.vertices.end(),
                        std::back_inserter(out.vertices));
    std::set_difference(all.edges.begin(), all.edges.end(), selection.edges.begin(), selection.edges.end(),
                        std::back_inserter(out.edges));
    std::set_difference(all.faces.begin(), all.faces.end(), selection.faces.begin(), selection.faces.end(),
                        std::back_inserter(out.faces));
    return out;
}

Selection convertSelection(const Selection& selection, SelectionMode mode, const Cage& cage, const Topology& topology) {
    if (mode == selection.mode) return selection;
    Selection out;
    out.mode = mode;
    // Through vertices for vertex/edge sources; faces convert directly.
    std::vector<uint32_t> vertices = selectedVertices(selection, cage);
    switch (mode) {
    case SelectionMode::Vertex: out.vertices = std::move(vertices); break;
    case SelectionMode::Edge:
        if (selection.mode == SelectionMode::Face) {
            for (uint32_t f : selection.faces)
                for (uint32_t i = cage.faceOffsets[f]; i < cage.faceOffsets[f + 1]; ++i)
                    out.edges.push_back(edgeAt(topology, topology.faceEdges[i]));
        } else {
            std::vector<bool> mask = vertexMask(vertices, cage.vertexCount());
            for (uint32_t e = 0; e < topology.edgeCount(); ++e)
                if (mask[topology.edgeVertices[2 * e]] && mask[topology.edgeVertices[2 * e + 1]])
                    out.edges.push_back(edgeAt(topology, e));
        }
        break;
    case SelectionMode::Face:
        for (uint32_t f = 0; f < cage.faceCount(); ++f) {
            bool all = true;
            for (uint32_t i = cage.faceOffsets[f]; i < cage.faceOffsets[f + 1] && all; ++i)
                all = selection.mode == SelectionMode::Edge ? has(selection.edges, edgeAt(topology, topology.faceEdges[i]))
                                                            : has(vertices, cage.faceVertices[i]);
            if (all) out.faces.push_back(f);
        }
        break;
    }
    sortUnique(out.edges);
    return out;
}

std::vector<uint32_t> selectedVertices(const Selection& selection, const Cage& cage) {
    std::vector<uint32_t> out;
    switch (selection.mode) {
    case SelectionMode::Vertex: out = selection.vertices; break;
    case SelectionMode::Edge:
        for (const EdgeKey& e : selection.edges) {
            out.push_back(e.v0);
            out.push_back(e.v1);
        }
        break;
    case SelectionMode::Face:
        for (uint32_t f : selection.faces) out.insert(out.end(), cage.faceBegin(f), cage.faceBegin(f) + cage.faceSize(f));
        break;
    }
    sortUnique(out);
    return out;
}

Selection growSelection(const Selection& selection, const Cage& cage, const Topology& topology) {
    Selection out = selection;
    switch (selection.mode) {
    case SelectionMode::Vertex:
        for (uint32_t v : selection.vertices)
            for (uint32_t k = topology.vertexEdgeOffsets[v]; k < topology.vertexEdgeOffsets[v + 1]; ++k) {
                const uint32_t e = topology.vertexEdges[k];
                out.vertices.push_back(topology.edgeVertices[2 * e] + topology.edgeVertices[2 * e + 1] - v);
            }
        sortUnique(out.vertices);
        break;
    case SelectionMode::Edge:
        for (uint32_t v : selectedVertices(selection, cage))
            for (uint32_t k = topology.vertexEdgeOffsets[v]; k < topology.vertexEdgeOffsets[v + 1]; ++k)
                out.edges.push_back(edgeAt(topology, topology.vertexEdges[k]));
        sortUnique(out.edges);
        break;
    case SelectionMode::Face:
        for (uint32_t v : selectedVertices(selection, cage))
            for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k)
                out.faces.push_back(topology.vertexFaces[k]);
        sortUnique(out.faces);
        break;
    }
    return out;
}

Selection shrinkSelection(const Selection& selection, const Cage& cage, const Topology& topology) {
    Selection out;
    out.mode = selection.mode;
    switch (selection.mode) {
    case SelectionMode::Vertex: {
        std::vector<bool> mask = vertexMask(selection.vertices, cage.vertexCount());
        for (uint32_t v : selection.vertices) {
            bool inner = true;
            for (uint32_t k = topology.vertexEdgeOffsets[v]; k < topology.vertexEdgeOffsets[v + 1] && inner; ++k) {
                const uint32_t e = topology.vertexEdges[k];
                inner = mask[topology.edgeVertices[2 * e] + topology.edgeVertices[2 * e + 1] - v];
            }
            if (inner) out.vertices.push_back(v);
        }
        break;
    }
    case SelectionMode::Edge: {
        // A vertex is inner when every edge at it is selected.
        auto inner = [&](uint32_t v) {
            for (uint32_t k = topology.vertexEdgeOffsets[v]; k < topology.vertexEdgeOffsets[v + 1]; ++k)
                if (!has(selection.edges, edgeAt(topology, topology.vertexEdges[k]))) return false;
            return true;
        };
        for (const EdgeKey& e : selection.edges)
            if (inner(e.v0) && inner(e.v1)) out.edges.push_back(e);
        break;
    }
    case SelectionMode::Face: {
        std::vector<bool> selected(cage.faceCount(), false);
        for (uint32_t f : selection.faces) selected[f] = true;
        for (uint32_t f : selection.faces) {
            bool inner = true;
            for (uint32_t i = 0; i < cage.faceSize(f) && inner; ++i) {
                const uint32_t v = cage.faceBegin(f)[i];
                for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1] && inner; ++k)
                    inner = selected[topology.vertexFaces[k]];
            }
            if (inner) out.faces.push_back(f);
        }
        break;
    }
    }
    return out;
}

Selection remapSelection(const Selection& selection, const TopologyEdit& edit, const Topology& topology) {
    std::vector<uint32_t> newVertexOf, newFaceOf;
    uint32_t oldVertices = 0, oldFaces = 0;
    for (uint32_t old : edit.oldVertexOf)
        if (old != kNewElement) oldVertices = std::max(oldVertices, old + 1);
    for (uint32_t old : edit.oldFaceOf)
        if (old != kNewElement) oldFaces = std::max(oldFaces, old + 1);
    newVertexOf.assign(oldVertices, kNewElement);
    newFaceOf.assign(oldFaces, kNewElement);
    for (uint32_t v = 0; v < edit.oldVertexOf.size(); ++v)
        if (edit.oldVertexOf[v] != kNewElement) newVertexOf[edit.oldVertexOf[v]] = v;
    for (uint32_t f = 0; f < edit.oldFaceOf.size(); ++f)
        if (edit.oldFaceOf[f] != kNewElement) newFaceOf[edit.oldFaceOf[f]] = f;
    auto mapVertex = [&](uint32_t v) { return v < newVertexOf.size() ? newVertexOf[v] : kNewElement; };

    Selection out;
    out.mode = selection.mode;
    for (uint32_t v : selection.vertices)
        if (mapVertex(v) != kNewElement) out.vertices.push_back(mapVertex(v));
    for (uint32_t f : selection.faces)
        if (f < newFaceOf.size() && newFaceOf[f] != kNewElement) out.faces.push_back(newFaceOf[f]);
    for (const EdgeKey& e : selection.edges) {
        const uint32_t a = mapVertex(e.v0), b = mapVertex(e.v1);
        if (a != kNewElement && b != kNewElement && topology.findEdge(a, b) != UINT32_MAX) out.edges.push_back(makeEdgeKey(a, b));
    }
    sortUnique(out.vertices);
    sortUnique(out.faces);
    sortUnique(out.edges);
    return out;
}

}  // namespace qp
