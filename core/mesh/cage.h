// Cage: the editable control mesh of a Catmull-Clark subdivision surface, with its tags.
//
// Plain flat arrays (see docs/cage-representation.md for why not OpenMesh):
//   - positions: one glm::vec3 per vertex;
//   - faces: faceOffsets[f] .. faceOffsets[f+1] index faceVertices (counter-clockwise);
//   - tags are sparse lists keyed by vertex indices, so topology edits never leave a tag
//     pointing at a stale edge index.
// Invariants established by validateCage() (every loader runs it):
//   - faceOffsets starts at 0, is non-decreasing, ends at faceVertices.size();
//   - every face has >= 3 vertices, all in range, no vertex repeated consecutively (a
//     zero-length edge); a face may visit a vertex twice non-consecutively, as OpenSubdiv's
//     non-manifold regression cages do;
//   - every coordinate is finite;
//   - creases are sorted by (v0, v1) with v0 < v1, unique, name an edge of some face, and have
//     a finite sharpness in (0, kInfiniteSharpness];
//   - corners are sorted by vertex, unique, in range, sharpness in (0, kInfiniteSharpness];
//   - holes are sorted, unique, in range;
//   - uvs, when present, have one index per face-vertex (faceUVIndices parallels faceVertices).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "mesh/result.h"

namespace qp {

// OpenSubdiv treats sharpness >= 10 as infinitely sharp.
constexpr float kInfiniteSharpness = 10.0f;

// Our own values. OBJ files spell them as OpenSubdiv's regression shapes do (see obj_io.h):
// `t interpolateboundary 1/0/0 N` with 0 none, 1 edges and corners, 2 edges only.
enum class BoundaryInterpolation : uint8_t { None = 0, EdgesOnly = 1, EdgesAndCorners = 2 };
enum class CreaseMethod : uint8_t { Normal = 0, Chaikin = 1 };
enum class TriangleSubdivision : uint8_t { Catmark = 0, Smooth = 1 };
// Face-varying linear interpolation (Sdc::Options::FVarLinearInterpolation), kept for UVs.
enum class FVarInterpolation : uint8_t {
    None = 0, CornersOnly = 1, CornersPlus1 = 2, CornersPlus2 = 3, Boundaries = 4, All = 5
};

struct EdgeCrease {
    uint32_t v0, v1;  // v0 < v1
    float sharpness;
};

struct VertexCorner {
    uint32_t vertex;
    float sharpness;
};

struct SubdivisionOptions {
    BoundaryInterpolation boundary = BoundaryInterpolation::EdgesAndCorners;
    CreaseMethod creaseMethod = CreaseMethod::Normal;
    TriangleSubdivision triangleSubdivision = TriangleSubdivision::Catmark;
    FVarInterpolation fvarInterpolation = FVarInterpolation::All;
    bool fvarPropagateCorners = false;

    bool operator==(const SubdivisionOptions&) const = default;
};

struct Cage {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> faceOffsets{0};
    std::vector<uint32_t> faceVertices;

    std::vector<EdgeCrease> creases;
    std::vector<VertexCorner> corners;
    std::vector<uint32_t> holes;
    SubdivisionOptions options;

    // Optional texture coordinates (OBJ `vt`), face-varying: empty, or one index per entry of
    // faceVertices.
    std::vector<glm::vec2> uvs;
    std::vector<uint32_t> faceUVIndices;

    uint32_t vertexCount() const { return uint32_t(positions.size()); }
    uint32_t faceCount() const { return uint32_t(faceOffsets.size() - 1); }
    uint32_t faceSize(uint32_t face) const { return faceOffsets[face + 1] - faceOffsets[face]; }
    const uint32_t* faceBegin(uint32_t face) const { return faceVertices.data() + faceOffsets[face]; }

    void addFace(const uint32_t* vertices, uint32_t count);

    // Sharpness lookups; 0 when untagged. Binary search over the sorted tag lists.
    float edgeSharpness(uint32_t a, uint32_t b) const;
    float vertexSharpness(uint32_t v) const;
    bool isHole(uint32_t face) const;

    // Setters keep the tag lists sorted and unique; sharpness 0 removes the tag.
    void setEdgeSharpness(uint32_t a, uint32_t b, float sharpness);
    void setVertexSharpness(uint32_t v, float sharpness);
    void setHole(uint32_t face, bool hole);
};

// Checks every invariant listed above. `source` names the file or object in the message.
Status validateCage(const Cage& cage, const std::string& source);

// Sorts and de-duplicates tag lists (last value wins) so that validateCage can succeed on
// tags gathered in file order. Does not drop out-of-range data: validation reports it.
void normalizeTags(Cage& cage);

// Axis-aligned bounds of the positions; the diagonal is the scale for relative errors.
struct Bounds {
    glm::vec3 min{0.0f}, max{0.0f};
    float diagonal() const;
};
Bounds computeBounds(const Cage& cage);

bool sameTopologyAndTags(const Cage& a, const Cage& b);

}  // namespace qp
