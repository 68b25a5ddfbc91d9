// Plan: the subdivision plan of one (sub-)face configuration (Brainerd et al. 2016, §4).
//
// A quadtree over the face's (u,v) domain whose leaves are patches, plus the dense stencils
// that produce every patch control point from the face's 1-ring (FaceConfig::ring order).
// Everything is flat arrays of plain values, so a plan can be copied into GPU buffers as is.
//
// Quadtree: nodes[0] is the root. An internal node's four children are consecutive, starting
// at `first`; child c covers the quadrant with u-half (c & 1) and v-half (c >> 1).
// Leaf kinds, with the control points they read from `points` (indices into the stencils):
//   Regular        16 points, bicubic B-spline, row-major 4x4 (row = v). `boundaryMask` marks
//                  patch edges that are boundaries or infinitely sharp: the points beyond them
//                  are phantoms whose weight is folded into the real points.
//   Crease         16 points as Regular plus one semi-sharp crease of constant `sharpness`
//                  along patch edge `edge` (0: v=0, 1: u=1, 2: v=1, 3: u=0), evaluated
//                  directly instead of being subdivided further.
//   Terminal       the repeating pattern around an extraordinary vertex at corner `corner`
//                  (0:(0,0) 1:(1,0) 2:(1,1) 3:(0,1)) for `levels` levels: per level 24 points
//                  on a 5x5 grid (mirrored so the EV sits at grid (1,1); the unused grid
//                  corner (0,0) is skipped), then the 20 points of the Extraordinary leaf at
//                  the bottom of the chain.
//   Extraordinary  20 points of a Gregory patch at the deepest level; its corner at the EV
//                  interpolates the exact limit position and tangent plane.
//
// Stencils are sorted by the lowest tessellation level that needs them; stencilCountByLevel[n]
// stencils serve every tessellation factor f <= 2^n, so the GPU applies only a prefix.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "plans/face_config.h"

namespace qp {

enum class NodeKind : uint8_t { Internal = 0, Regular = 1, Crease = 2, Terminal = 3, Extraordinary = 4 };
constexpr uint32_t kNodeKindCount = 5;
const char* nodeKindName(NodeKind kind);

struct PlanNode {
    NodeKind kind = NodeKind::Internal;
    uint8_t boundaryMask = 0;  // Regular, Crease
    uint8_t edge = 0;          // Crease: the creased patch edge; Terminal: the EV corner
    uint8_t levels = 0;        // Terminal
    uint32_t first = 0;        // Internal: first child node; leaves: offset into points
    float sharpness = 0.0f;    // Crease

    bool operator==(const PlanNode&) const = default;
};
static_assert(sizeof(PlanNode) == 12);

constexpr uint32_t kTerminalPointsPerLevel = 24;
constexpr uint32_t kGregoryPoints = 20;

struct Plan {
    uint32_t ringSize = 0;  // stencil width: vertices in the configuration's 1-ring
    uint32_t maxDepth = 0;
    std::vector<PlanNode> nodes;
    std::vector<uint32_t> points;          // stencil indices read by the leaves
    std::vector<float> stencilWeights;     // stencilCount() rows of ringSize weights
    std::array<uint32_t, kMaxPlanDepth + 1> stencilCountByLevel{};
    // Bit c: the plan-frame corner c ((0,0), (1,0), (1,1), (0,1)) is an extraordinary vertex
    // whose limit tangent plane the plan carries exactly: stencils 2k and 2k + 1 (k = the bits
    // set below c, so they come first and serve every level) are two tangents there, from the
    // vertex's exact masks (tangent_plane.h), and evaluatePlan puts du and dv onto that plane at
    // the corner. The end cap's own corner tangents are differences of rows 2^-depth apart, which
    // float leaves hundredths of a degree off at depth 8.
    uint32_t cornerTangents = 0;

    uint32_t stencilCount() const { return ringSize ? uint32_t(stencilWeights.size() / ringSize) : 0; }
    bool hasSurface() const { return !nodes.empty(); }
    size_t byteSize() const {
        return nodes.size() * sizeof(PlanNode) + points.size() * sizeof(uint32_t) +
               stencilWeights.size() * sizeof(float) + sizeof(stencilCountByLevel) + 3 * sizeof(uint32_t);
    }
    bool operator==(const Plan&) const = default;
};

// Which corner of a (sub-)face's domain (u, v) is: 0 (0,0), 1 (1,0), 2 (1,1), 3 (0,1); -1 for
// none (Plan::cornerTangents numbers its corners so).
inline int domainCorner(double u, double v) {
    if (u == 0.0 && v == 0.0) return 0;
    if (u == 1.0 && v == 0.0) return 1;
    if (u == 1.0 && v == 1.0) return 2;
    if (u == 0.0 && v == 1.0) return 3;
    return -1;
}
// The same for corner i of the patch at integer position (u, v) of a domain `cells` patches wide.
inline int patchCornerOfDomain(uint32_t u, uint32_t v, uint32_t cells, uint32_t i) {
    const uint32_t x = u + (i == 1 || i == 2 ? 1 : 0), y = v + (i >= 2 ? 1 : 0);
    return domainCorner(double(x) / double(cells), double(y) / double(cells));
}

// Limit position and first derivatives.
struct LimitSample {
    glm::vec3 position{0.0f}, du{0.0f}, dv{0.0f};
};

// controlPoints[i] = sum_j stencil(i, j) * ringPositions[j] for the first `count` stencils.
void applyStencils(const Plan& plan, const glm::vec3* ringPositions, uint32_t count, glm::vec3* controlPoints);

// The level whose stencil prefix (Plan::stencilCountByLevel) serves tessellation factor
// `factor`: the least n with 2^n >= factor.
inline uint32_t stencilLevelFor(uint32_t factor) {
    uint32_t level = 0;
    while ((1u << level) < factor) ++level;
    return level;
}

// Evaluates the plan at (u, v) in its own frame, given all its control points.
LimitSample evaluatePlan(const Plan& plan, const glm::vec3* controlPoints, float u, float v);

// Counts of nodes by kind (index = NodeKind).
std::array<uint32_t, kNodeKindCount> countNodes(const Plan& plan);

}  // namespace qp
