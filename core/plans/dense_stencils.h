// DenseStencils: every point of a locally refined mesh as weights over its control points.
//
// A plan's stencils are dense rows over its 1-ring (16 points on average), so they are
// computed dense from the start: one row of ringSize floats per point, filled level by level
// through Far::PrimvarRefiner with rows as the primvar, then one row per patch-table local point
// (the Gregory end caps' points) from the local-point stencils. The sums are those
// Far::StencilTableFactory forms with factorized intermediate levels, in the same order, without
// its sparse bookkeeping (which allocated for every point and was a quarter of cold planning):
// the weights are Far's to the bit (tests/plans/test_dense_stencils.cpp) as long as neither side
// is compiled to fuse the multiply-adds (no -march with FMA here, nor in Debian's OpenSubdiv).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/topologyRefiner.h>

namespace qp {

struct DenseStencils {
    uint32_t ringSize = 0;    // control points: the refiner's level-0 vertices
    uint32_t pointCount = 0;  // the refiner's vertices of every level, then the local points
    std::vector<float> weights;  // pointCount rows of ringSize

    std::span<const float> row(uint32_t point) const {
        return {weights.data() + size_t(point) * ringSize, ringSize};
    }
};

// Points are numbered as Far's patch tables number them: the control points, each refined
// level's vertices in turn, then `patches`' local points. `stencils` is overwritten; its
// storage is reused (the plan builder keeps one per thread).
void computeDenseStencils(const OpenSubdiv::Far::TopologyRefiner& refiner, const OpenSubdiv::Far::PatchTable& patches,
                          DenseStencils& stencils);

}  // namespace qp
