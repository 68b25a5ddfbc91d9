// The tessellator path of `osd-fas`, laid out as OpenSubdiv's own GPU path draws: the cage's
// positions go to the device, a compute pass applies Far's stencil table to them (every refined
// vertex and every Gregory-basis point, osd_fas_stencils.comp), and each Far patch is one patch
// primitive whose control stage reads its control vertices by index and whose evaluation stage
// evaluates it: bicubic B-spline (boundary folded), single-crease with its sharpness, or
// Gregory basis (osd_fas.tesc, osd_fas.tese).
//
// Tessellation levels, OpenSubdiv's rule (its GLSL OsdGetTessLevelsUniform and the transition
// split of OsdComputeTessLevels) in integer form:
//   - uniform factor F: an edge of a patch at depth d gets max(1, ceil(F / 2^d)) segments, so a
//     patch covers as many segments of its base face as the plans' grid gives the face;
//   - screen-adaptive: the edge-sphere rule of the plans, measured on the patch's edge points
//     (osd_fas_patches.h), at most 32 per edge (a half of a transition edge must fit in 64);
//   - a transition edge (the neighbour is one level finer) is two halves, each with the finer
//     patch's level; the evaluation stage moves the edge's vertices so that each half is cut
//     evenly, and the neighbours' vertices fall on them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "osd_fas_patches.h"

namespace qp {

// Mirrors osd_fas_data.glsl. Offsets are in 32-bit words from the start of the buffer.
struct FasGpuHeader {
    uint32_t patchCount, patchOffset;
    uint32_t pointCount, pointOffset;     // vec4 per point, written by the compute pass
    uint32_t cageOffset;                  // three floats per cage vertex
    uint32_t stencilOffsets;              // pointCount + 1 prefix offsets into indices and weights
    uint32_t stencilIndices, stencilWeights;
};

enum class FasPatchKind : uint32_t { BSpline = 0, SingleCrease = 1, GregoryBasis = 2 };

struct FasGpuPatch {
    FasPatchKind kind;
    uint32_t param0, param1;   // Far::PatchParam's two words
    float sharpness;           // single-crease patches
    uint32_t controlVertices[20];  // 16 used by B-spline and single-crease patches
    uint32_t edgePoints[12];       // FasPatchLayout::edgePoints
};
static_assert(sizeof(FasGpuPatch) == 36 * 4, "osd_fas_data.glsl reads 36 words a patch");

struct FasGpuData {
    FasGpuHeader header;
    std::vector<uint32_t> words;  // the whole buffer, header first
};

// The buffer for `patches` (topology only: the cage's positions go at header.cageOffset, as
// fasCagePositions packs them; the points are the compute pass's).
FasGpuData packFasPatches(const FasPatches& patches, uint32_t cageVertices);
std::vector<float> fasCagePositions(std::span<const glm::vec3> positions);  // three floats a vertex

// Segments on each edge of a patch at the uniform factor (Vulkan's outer order: u=0, v=0, u=1,
// v=1; as osd_fas.tesc computes them) and the triangles the tessellator makes of them.
void fasUniformLevels(const OpenSubdiv::Far::PatchParam& param, uint32_t factor, float outer[4]);
uint64_t quadTessTriangles(const float outer[4]);
uint64_t fasUniformTriangles(const FasPatches& patches, uint32_t factor);

}  // namespace qp
