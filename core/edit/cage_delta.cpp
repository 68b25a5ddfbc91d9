#include "edit/cage_delta.h"

#include <algorithm>

namespace qp {

namespace {

template <class T>
size_t vectorBytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}

bool sameCrease(const EdgeCrease& a, const EdgeCrease& b) {
    return a.v0 == b.v0 && a.v1 == b.v1 && a.sharpness == b.sharpness;
}

bool contains(const std::vector<uint32_t>& sorted, uint32_t x) { return std::binary_search(sorted.begin(), sorted.end(), x); }

// Maps between the two numberings, given the elements only each side has (sorted): kept
// elements pair up in order.
std::vector<uint32_t> keptMap(uint32_t fromCount, const std::vector<uint32_t>& fromOnly, uint32_t toCount,
                              const std::vector<uint32_t>& toOnly) {
    std::vector<uint32_t> map(fromCount, kNewElement);
    uint32_t to = 0;
    for (uint32_t from = 0; from < fromCount; ++from) {
        if (contains(fromOnly, from)) continue;
        while (to < toCount && contains(toOnly, to)) ++to;
        if (to < toCount) map[from] = to++;
    }
    return map;
}

// Fills `side` with the tags of `cage` that the other cage lacks; toOther maps this side's
// vertices (or faces, for holes) to the other's.
void onlyTags(const Cage& cage, const Cage& other, const std::vector<uint32_t>& vertexToOther,
              const std::vector<uint32_t>& faceToOther, CageDeltaSide& side) {
    for (const EdgeCrease& c : cage.creases) {
        const uint32_t a = vertexToOther[c.v0], b = vertexToOther[c.v1];
        if (a == kNewElement || b == kNewElement || other.edgeSharpness(a, b) != c.sharpness) side.creases.push_back(c);
    }
    for (const VertexCorner& c : cage.corners) {
        const uint32_t v = vertexToOther[c.vertex];
        if (v == kNewElement || other.vertexSharpness(v) != c.sharpness) side.corners.push_back(c);
    }
    for (uint32_t h : cage.holes)
        if (faceToOther[h] == kNewElement || !other.isHole(faceToOther[h])) side.holes.push_back(h);
}

void addFace(CageDeltaSide& side, const Cage& cage, uint32_t f) {
    side.faces.push_back(f);
    side.faceVertices.insert(side.faceVertices.end(), cage.faceBegin(f), cage.faceBegin(f) + cage.faceSize(f));
    side.faceOffsets.push_back(uint32_t(side.faceVertices.size()));
    if (!cage.faceUVIndices.empty())
        side.faceUVIndices.insert(side.faceUVIndices.end(), cage.faceUVIndices.begin() + cage.faceOffsets[f],
                                  cage.faceUVIndices.begin() + cage.faceOffsets[f + 1]);
}

}  // namespace

size_t CageDeltaSide::bytes() const {
    return vectorBytes(faces) + vectorBytes(faceOffsets) + vectorBytes(faceVertices) + vectorBytes(faceUVIndices) +
           vectorBytes(vertices) + vectorBytes(vertexPositions) + vectorBytes(movedVertices) +
           vectorBytes(movedPositions) + vectorBytes(creases) + vectorBytes(corners) + vectorBytes(holes) +
           vectorBytes(uvTail);
}

TopologyDelta makeTopologyDelta(const Cage& before, const TopologyEdit& edit) {
    const Cage& after = edit.cage;
    TopologyDelta delta;
    CageDeltaSide& b = delta.before;
    CageDeltaSide& a = delta.after;
    b.faceCount = before.faceCount();
    b.vertexCount = before.vertexCount();
    a.faceCount = after.faceCount();
    a.vertexCount = after.vertexCount();
    b.options = before.options;
    a.options = after.options;

    // Faces: a changed face counts as removed on one side and created on the other.
    std::vector<uint32_t> beforeFaces = edit.removedFaces;
    for (uint32_t f : edit.changedFaces)
        if (edit.oldFaceOf[f] != kNewElement) beforeFaces.push_back(edit.oldFaceOf[f]);
    std::sort(beforeFaces.begin(), beforeFaces.end());
    for (uint32_t g : beforeFaces) addFace(b, before, g);
    for (uint32_t f : edit.changedFaces) addFace(a, after, f);

    std::vector<uint32_t> beforeToAfter(before.vertexCount(), kNewElement), afterToBefore = edit.oldVertexOf;
    for (uint32_t v = 0; v < after.vertexCount(); ++v)
        if (edit.oldVertexOf[v] != kNewElement) beforeToAfter[edit.oldVertexOf[v]] = v;
    for (uint32_t v = 0; v < before.vertexCount(); ++v) {
        if (beforeToAfter[v] == kNewElement) {
            b.vertices.push_back(v);
            b.vertexPositions.push_back(before.positions[v]);
        } else if (before.positions[v] != after.positions[beforeToAfter[v]]) {
            b.movedVertices.push_back(v);
            b.movedPositions.push_back(before.positions[v]);
            a.movedVertices.push_back(beforeToAfter[v]);
            a.movedPositions.push_back(after.positions[beforeToAfter[v]]);
        }
    }
    for (uint32_t v = 0; v < after.vertexCount(); ++v)
        if (edit.oldVertexOf[v] == kNewElement) {
            a.vertices.push_back(v);
            a.vertexPositions.push_back(after.positions[v]);
        }

    std::vector<uint32_t> beforeFaceToAfter = keptMap(b.faceCount, b.faces, a.faceCount, a.faces);
    std::vector<uint32_t> afterFaceToBefore = keptMap(a.faceCount, a.faces, b.faceCount, b.faces);
    onlyTags(before, after, beforeToAfter, beforeFaceToAfter, b);
    onlyTags(after, before, afterToBefore, afterFaceToBefore, a);

    const size_t common = std::min(before.uvs.size(), after.uvs.size());
    size_t prefix = 0;
    while (prefix < common && before.uvs[prefix] == after.uvs[prefix]) ++prefix;
    delta.commonUVs = uint32_t(prefix);
    b.uvTail.assign(before.uvs.begin() + prefix, before.uvs.end());
    a.uvTail.assign(after.uvs.begin() + prefix, after.uvs.end());
    return delta;
}

Result<TopologyEdit> applyTopologyDelta(const Cage& cage, const TopologyDelta& delta, DeltaDirection direction) {
    const bool forward = direction == DeltaDirection::Forward;
    const CageDeltaSide& from = forward ? delta.before : delta.after;
    const CageDeltaSide& to = forward ? delta.after : delta.before;
    if (cage.faceCount() != from.faceCount || cage.vertexCount() != from.vertexCount || cage.uvs.size() < delta.commonUVs)
        return Error{"the cage is not the one this history entry was recorded on"};

    std::vector<uint32_t> vertexMap = keptMap(from.vertexCount, from.vertices, to.vertexCount, to.vertices);
    std::vector<uint32_t> faceMap = keptMap(from.faceCount, from.faces, to.faceCount, to.faces);

    TopologyEdit edit;
    Cage& out = edit.cage;
    out.options = to.options;
    out.positions.resize(to.vertexCount);
    edit.oldVertexOf.assign(to.vertexCount, kNewElement);
    for (uint32_t v = 0; v < from.vertexCount; ++v)
        if (vertexMap[v] != kNewElement) {
            out.positions[vertexMap[v]] = cage.positions[v];
            edit.oldVertexOf[vertexMap[v]] = v;
        }
    for (size_t i = 0; i < to.vertices.size(); ++i) out.positions[to.vertices[i]] = to.vertexPositions[i];
    for (size_t i = 0; i < to.movedVertices.size(); ++i) out.positions[to.movedVertices[i]] = to.movedPositions[i];

    out.uvs.assign(cage.uvs.begin(), cage.uvs.begin() + delta.commonUVs);
    out.uvs.insert(out.uvs.end(), to.uvTail.begin(), to.uvTail.end());

    // Faces in the target order: stored ones where `to` has them, kept ones (renumbered) between.
    std::vector<uint32_t> keptFaces;
    for (uint32_t f = 0; f < from.faceCount; ++f)
        if (faceMap[f] != kNewElement) keptFaces.push_back(f);
    const bool uvs = !cage.faceUVIndices.empty() || !to.faceUVIndices.empty();
    size_t stored = 0, kept = 0;
    for (uint32_t f = 0; f < to.faceCount; ++f) {
        if (stored < to.faces.size() && to.faces[stored] == f) {
            const uint32_t begin = to.faceOffsets[stored], end = to.faceOffsets[stored + 1];
            out.faceVertices.insert(out.faceVertices.end(), to.faceVertices.begin() + begin, to.faceVertices.begin() + end);
            if (uvs) out.faceUVIndices.insert(out.faceUVIndices.end(), to.faceUVIndices.begin() + begin, to.faceUVIndices.begin() + end);
            edit.oldFaceOf.push_back(kNewElement);
            ++stored;
        } else {
            if (kept >= keptFaces.size()) return Error{"the history entry does not match the cage's faces"};
            const uint32_t g = keptFaces[kept++];
            for (uint32_t i = 0; i < cage.faceSize(g); ++i) out.faceVertices.push_back(vertexMap[cage.faceBegin(g)[i]]);
            if (uvs)
                out.faceUVIndices.insert(out.faceUVIndices.end(), cage.faceUVIndices.begin() + cage.faceOffsets[g],
                                         cage.faceUVIndices.begin() + cage.faceOffsets[g + 1]);
            edit.oldFaceOf.push_back(g);
        }
        out.faceOffsets.push_back(uint32_t(out.faceVertices.size()));
    }

    // Tags: the starting side's, less what only it has, mapped; plus what only the target has.
    auto onlyFromCrease = [&](const EdgeCrease& c) {
        return std::any_of(from.creases.begin(), from.creases.end(), [&](const EdgeCrease& o) { return sameCrease(o, c); });
    };
    for (const EdgeCrease& c : cage.creases) {
        if (onlyFromCrease(c)) continue;
        EdgeKey k = makeEdgeKey(vertexMap[c.v0], vertexMap[c.v1]);
        out.creases.push_back({k.v0, k.v1, c.sharpness});
    }
    out.creases.insert(out.creases.end(), to.creases.begin(), to.creases.end());
    for (const VertexCorner& c : cage.corners) {
        bool onlyFrom = std::any_of(from.corners.begin(), from.corners.end(),
                                    [&](const VertexCorner& o) { return o.vertex == c.vertex && o.sharpness == c.sharpness; });
        if (!onlyFrom) out.corners.push_back({vertexMap[c.vertex], c.sharpness});
    }
    out.corners.insert(out.corners.end(), to.corners.begin(), to.corners.end());
    for (uint32_t h : cage.holes)
        if (!contains(from.holes, h)) out.holes.push_back(faceMap[h]);
    out.holes.insert(out.holes.end(), to.holes.begin(), to.holes.end());

    if (Status s = finishTopologyEdit(cage, edit, "history"); !s) return s.error();
    return edit;
}

}  // namespace qp
