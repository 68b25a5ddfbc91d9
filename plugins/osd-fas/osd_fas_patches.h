// OpenSubdiv's feature-adaptive patches (Nießner et al. 2012) and their CPU tessellation, the
// math behind `osd-fas` (osd_fas_scheme.cpp is the plugin glue).
//
// Far refines adaptively to `depth` around extraordinary vertices and creases and builds a
// PatchTable: bicubic B-spline patches (boundary and infinitely sharp variants) where the
// surface is regular, single-crease patches where a regular face has one semi-sharp crease
// (as OpenSubdiv's GPU path uses them), Gregory-basis end caps at the deepest level. Far's own
// EvaluateBasis ignores a single-crease patch's sharpness (platform notes), so those are
// evaluated with the crease basis of core/plans/patch_basis.h, which is exact for the uniform crease
// rule: the patches stay within the plans' accuracy while semi-sharp creases cost no isolation.
//
// Tessellation, as OpenSubdiv's uniform tessellation does it: a patch at depth d gets
// F / 2^d segments per side (at least 1; F the factor rounded down to a power of two), so the
// density matches the plans' grid; a one-segment patch whose edge borders a finer patch
// (PatchParam transition bit, edges 0: v=0, 1: u=1, 2: v=1, 3: u=0) gets that patch's
// midpoint on the edge and is fanned around its centre, so triangles meet without T-junctions.
// The tessellator path (osd_fas_gpu.h) follows OpenSubdiv's GLSL rule instead: transition edges
// are split in two halves, each with the finer patch's factor.
//
// Edge points: the screen-space factor of a patch edge is measured on refined vertices (not on
// evaluated limit points), so both patches of an edge read the same two values and agree on its
// factor bit for bit. A plain edge is measured between the patch's corner vertices at its own
// level; a transition edge, in two halves, between the corners' and the edge's child vertices
// one level deeper, which are exactly the finer neighbours' corners.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/stencilTable.h>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

struct FasPatchLayout {
    OpenSubdiv::Far::PatchTable::PatchHandle handle;
    uint32_t firstVertex, vertexCount, firstIndex, indexCount;
    uint32_t factor, transitions;  // transitions only on one-segment patches
    // Per edge (Far's order, 0: v=0, 1: u=1, 2: v=1, 3: u=0): start, midpoint, end as indices
    // into FasPatches::points; the midpoint is kNoEdgeMidpoint unless the edge is a transition.
    uint32_t edgePoints[4][3];
};

inline constexpr uint32_t kNoEdgeMidpoint = UINT32_MAX;

struct FasPatches {
    std::unique_ptr<OpenSubdiv::Far::PatchTable> table;
    std::unique_ptr<OpenSubdiv::Far::PatchMap> map;
    // Cage -> every point patches read, in double (OpenSubdiv's StencilTableReal<double>): at an
    // extraordinary corner the tangents are differences of rows that shrink like
    // lambda^depth, and float tables left their round-off in the normals (a cube's corners
    // 0.001 / 0.002 / 0.036 degrees off at depths 4 / 6 / 8; none in double). The tess path
    // takes the weights as floats, as OpenSubdiv's GPU evaluators do.
    std::unique_ptr<const OpenSubdiv::Far::StencilTableReal<double>> stencils;
    uint32_t factor = 1;                  // F, a power of two
    uint32_t singleCreasePatches = 0;     // patches evaluated with their crease sharpness
    std::vector<FasPatchLayout> layout;   // one per patch
    std::vector<glm::vec2> domain;        // patch-local (u, v) of every tessellation vertex
    std::vector<uint32_t> indices;        // three per triangle, into domain
    std::vector<glm::dvec3> points;       // stencils applied to the current positions (double:
                                          // evaluatePatch differences them at depth)
};

struct FasSample {
    glm::vec3 position{0.0f}, du{0.0f}, dv{0.0f};
};

// Topology-dependent work: refinement, patch table, stencils, tessellation layout.
Result<FasPatches> buildFasPatches(const Cage& cage, uint32_t depth, uint32_t tessFactor);

// Applies the stencils to new cage positions (parallel).
void updateFasPoints(FasPatches& patches, std::span<const glm::vec3> cagePositions);

// Position and derivatives at (u, v) of sub-face `subface` (its own frame); zero when no patch
// covers it.
FasSample evaluateFas(const FasPatches& patches, uint32_t subface, float u, float v);

// The same at patch `patch`'s own (u, v) in [0, 1]^2 (what its tessellation coordinates are).
FasSample evaluateFasPatch(const FasPatches& patches, uint32_t patch, float u, float v);

// Every tessellation vertex (parallel over patches): positions and unit normals.
void tessellateFas(const FasPatches& patches, std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals);

}  // namespace qp
