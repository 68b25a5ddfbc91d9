#include "mesh/cage.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

namespace qp {

namespace {

bool edgeLess(const EdgeCrease& a, const EdgeCrease& b) {
    return a.v0 != b.v0 ? a.v0 < b.v0 : a.v1 < b.v1;
}

std::string faceName(const std::string& source, uint32_t face) {
    return source + ": face " + std::to_string(face + 1);
}

}  // namespace

void Cage::addFace(const uint32_t* vertices, uint32_t count) {
    faceVertices.insert(faceVertices.end(), vertices, vertices + count);
    faceOffsets.push_back(uint32_t(faceVertices.size()));
}

float Cage::edgeSharpness(uint32_t a, uint32_t b) const {
    EdgeCrease key{std::min(a, b), std::max(a, b), 0.0f};
    auto it = std::lower_bound(creases.begin(), creases.end(), key, edgeLess);
    return (it != creases.end() && it->v0 == key.v0 && it->v1 == key.v1) ? it->sharpness : 0.0f;
}

float Cage::vertexSharpness(uint32_t v) const {
    auto it = std::lower_bound(corners.begin(), corners.end(), v,
                               [](const VertexCorner& c, uint32_t x) { return c.vertex < x; });
    return (it != corners.end() && it->vertex == v) ? it->sharpness : 0.0f;
}

bool Cage::isHole(uint32_t face) const {
    return std::binary_search(holes.begin(), holes.end(), face);
}

void Cage::setEdgeSharpness(uint32_t a, uint32_t b, float sharpness) {
    EdgeCrease key{std::min(a, b), std::max(a, b), sharpness};
    auto it = std::lower_bound(creases.begin(), creases.end(), key, edgeLess);
    bool found = it != creases.end() && it->v0 == key.v0 && it->v1 == key.v1;
    if (sharpness <= 0.0f) {
        if (found) creases.erase(it);
    } else if (found) {
        it->sharpness = sharpness;
    } else {
        creases.insert(it, key);
    }
}

void Cage::setVertexSharpness(uint32_t v, float sharpness) {
    auto it = std::lower_bound(corners.begin(), corners.end(), v,
                               [](const VertexCorner& c, uint32_t x) { return c.vertex < x; });
    bool found = it != corners.end() && it->vertex == v;
    if (sharpness <= 0.0f) {
        if (found) corners.erase(it);
    } else if (found) {
        it->sharpness = sharpness;
    } else {
        corners.insert(it, VertexCorner{v, sharpness});
    }
}

void Cage::setHole(uint32_t face, bool hole) {
    auto it = std::lower_bound(holes.begin(), holes.end(), face);
    bool found = it != holes.end() && *it == face;
    if (hole && !found) holes.insert(it, face);
    if (!hole && found) holes.erase(it);
}

void normalizeTags(Cage& cage) {
    for (EdgeCrease& c : cage.creases)
        if (c.v0 > c.v1) std::swap(c.v0, c.v1);
    // Stable sort + keep the last of equal keys: a later tag line overrides an earlier one.
    std::stable_sort(cage.creases.begin(), cage.creases.end(), edgeLess);
    std::vector<EdgeCrease> creases;
    for (const EdgeCrease& c : cage.creases) {
        if (!creases.empty() && creases.back().v0 == c.v0 && creases.back().v1 == c.v1)
            creases.back() = c;
        else
            creases.push_back(c);
    }
    std::erase_if(creases, [](const EdgeCrease& c) { return c.sharpness == 0.0f; });
    cage.creases = std::move(creases);

    std::stable_sort(cage.corners.begin(), cage.corners.end(),
                     [](const VertexCorner& a, const VertexCorner& b) { return a.vertex < b.vertex; });
    std::vector<VertexCorner> corners;
    for (const VertexCorner& c : cage.corners) {
        if (!corners.empty() && corners.back().vertex == c.vertex)
            corners.back() = c;
        else
            corners.push_back(c);
    }
    std::erase_if(corners, [](const VertexCorner& c) { return c.sharpness == 0.0f; });
    cage.corners = std::move(corners);

    std::sort(cage.holes.begin(), cage.holes.end());
    cage.holes.erase(std::unique(cage.holes.begin(), cage.holes.end()), cage.holes.end());
}

Status validateCage(const Cage& cage, const std::string& source) {
    if (cage.faceOffsets.empty() || cage.faceOffsets.front() != 0 ||
        cage.faceOffsets.back() != cage.faceVertices.size())
        return Error{source + ": face offsets are inconsistent with the face-vertex list"};

    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        const glm::vec3& p = cage.positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return Error{source + ": vertex " + std::to_string(v + 1) +
                         " has a NaN or infinite coordinate"};
    }

    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        if (cage.faceOffsets[f + 1] < cage.faceOffsets[f])
            return Error{source + ": face offsets are not increasing at face " + std::to_string(f + 1)};
        uint32_t n = cage.faceSize(f);
        const uint32_t* fv = cage.faceBegin(f);
        if (n < 3)
            return Error{faceName(source, f) + " has " + std::to_string(n) +
                         " vertices; a face needs at least 3"};
        for (uint32_t i = 0; i < n; ++i) {
            if (fv[i] >= cage.vertexCount())
                return Error{faceName(source, f) + " refers to vertex " + std::to_string(fv[i] + 1) +
                             " but the cage has " + std::to_string(cage.vertexCount()) + " vertices"};
            uint32_t a = fv[i], b = fv[i + 1 < n ? i + 1 : 0];  // no division: this runs on every edit
            if (a == b)
                return Error{faceName(source, f) + " repeats vertex " + std::to_string(a + 1) +
                             " consecutively (zero-length edge)"};
        }
    }

    // The faces' edges at the creases' first vertices, sorted, for the creases to name: only
    // those, so validation stays linear in the cage (it runs on every topology edit).
    std::vector<uint64_t> creaseEdges;  // (v0 << 32 | v1), v0 < v1
    if (!cage.creases.empty()) {
        std::vector<char> creaseStart(cage.vertexCount(), 0);
        for (const EdgeCrease& c : cage.creases)
            if (c.v0 < cage.vertexCount()) creaseStart[c.v0] = 1;
        for (uint32_t f = 0; f < cage.faceCount(); ++f)
            for (uint32_t i = 0, n = cage.faceSize(f); i < n; ++i) {
                const uint32_t a = cage.faceBegin(f)[i], b = cage.faceBegin(f)[i + 1 < n ? i + 1 : 0];
                if (creaseStart[std::min(a, b)]) creaseEdges.push_back(uint64_t(std::min(a, b)) << 32 | std::max(a, b));
            }
        std::sort(creaseEdges.begin(), creaseEdges.end());
    }

    auto badSharpness = [](float s) { return !std::isfinite(s) || s <= 0.0f || s > kInfiniteSharpness; };
    for (size_t i = 0; i < cage.creases.size(); ++i) {
        const EdgeCrease& c = cage.creases[i];
        std::string name = source + ": crease on edge " + std::to_string(c.v0 + 1) + "-" + std::to_string(c.v1 + 1);
        if (c.v0 >= c.v1 || (i > 0 && !edgeLess(cage.creases[i - 1], c)))
            return Error{name + " is not sorted or is duplicated (call normalizeTags)"};
        if (!std::binary_search(creaseEdges.begin(), creaseEdges.end(), uint64_t(c.v0) << 32 | c.v1))
            return Error{name + " names an edge that no face has"};
        if (badSharpness(c.sharpness))
            return Error{name + " has sharpness " + std::to_string(c.sharpness) +
                         "; sharpness must be a number in (0, 10]"};
    }
    for (size_t i = 0; i < cage.corners.size(); ++i) {
        const VertexCorner& c = cage.corners[i];
        std::string name = source + ": corner on vertex " + std::to_string(c.vertex + 1);
        if (i > 0 && cage.corners[i - 1].vertex >= c.vertex)
            return Error{name + " is not sorted or is duplicated (call normalizeTags)"};
        if (c.vertex >= cage.vertexCount())
            return Error{name + " is out of range (the cage has " + std::to_string(cage.vertexCount()) + " vertices)"};
        if (badSharpness(c.sharpness))
            return Error{name + " has sharpness " + std::to_string(c.sharpness) +
                         "; sharpness must be a number in (0, 10]"};
    }
    for (size_t i = 0; i < cage.holes.size(); ++i) {
        if (cage.holes[i] >= cage.faceCount())
            return Error{source + ": hole names face " + std::to_string(cage.holes[i] + 1) +
                         " but the cage has " + std::to_string(cage.faceCount()) + " faces"};
        if (i > 0 && cage.holes[i - 1] >= cage.holes[i])
            return Error{source + ": hole list is not sorted or has duplicates (call normalizeTags)"};
    }

    if (!cage.faceUVIndices.empty()) {
        if (cage.faceUVIndices.size() != cage.faceVertices.size())
            return Error{source + ": texture coordinates are given for some faces but not all"};
        for (uint32_t i : cage.faceUVIndices)
            if (i >= cage.uvs.size())
                return Error{source + ": texture coordinate index " + std::to_string(i + 1) +
                             " is out of range (there are " + std::to_string(cage.uvs.size()) + ")"};
    }
    return success();
}

float Bounds::diagonal() const { return glm::length(max - min); }

Bounds computeBounds(const Cage& cage) {
    Bounds b;
    if (cage.positions.empty()) return b;
    b.min = b.max = cage.positions[0];
    for (const glm::vec3& p : cage.positions) {
        b.min = glm::min(b.min, p);
        b.max = glm::max(b.max, p);
    }
    return b;
}

bool sameTopologyAndTags(const Cage& a, const Cage& b) {
    auto sameCreases = [&] {
        if (a.creases.size() != b.creases.size()) return false;
        for (size_t i = 0; i < a.creases.size(); ++i)
            if (a.creases[i].v0 != b.creases[i].v0 || a.creases[i].v1 != b.creases[i].v1 ||
                a.creases[i].sharpness != b.creases[i].sharpness)
                return false;
        return true;
    };
    auto sameCorners = [&] {
        if (a.corners.size() != b.corners.size()) return false;
        for (size_t i = 0; i < a.corners.size(); ++i)
            if (a.corners[i].vertex != b.corners[i].vertex || a.corners[i].sharpness != b.corners[i].sharpness)
                return false;
        return true;
    };
    return a.positions.size() == b.positions.size() && a.faceOffsets == b.faceOffsets &&
           a.faceVertices == b.faceVertices && a.holes == b.holes && a.options == b.options &&
           a.faceUVIndices == b.faceUVIndices && a.uvs.size() == b.uvs.size() && sameCreases() &&
           sameCorners();
}

}  // namespace qp
