#include "plans/dense_stencils.h"

#include <algorithm>
#include <cassert>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTable.h>

namespace qp {

using namespace OpenSubdiv;

namespace {

// One point's row, the primvar Far::PrimvarRefiner::Interpolate accumulates.
struct Row {
    float* weights;
    uint32_t size;

    void Clear() { std::fill_n(weights, size, 0.0f); }
    void AddWithWeight(const Row& source, float weight) {
        for (uint32_t i = 0; i < size; ++i) weights[i] += weight * source.weights[i];
    }
};

// A level's rows, indexed by the level's vertex numbers.
struct LevelRows {
    float* first;
    uint32_t size;

    Row operator[](int vertex) const { return {first + size_t(vertex) * size, size}; }
};

}  // namespace

void computeDenseStencils(const Far::TopologyRefiner& refiner, const Far::PatchTable& patches,
                          DenseStencils& stencils) {
    stencils.ringSize = uint32_t(refiner.GetLevel(0).GetNumVertices());
    const uint32_t refinedCount = uint32_t(refiner.GetNumVerticesTotal());
    const Far::StencilTable* local = patches.GetLocalPointStencilTable();
    const uint32_t localCount = local ? uint32_t(local->GetNumStencils()) : 0;
    stencils.pointCount = refinedCount + localCount;
    const uint32_t n = stencils.ringSize;
    stencils.weights.assign(size_t(stencils.pointCount) * n, 0.0f);
    float* weights = stencils.weights.data();

    for (uint32_t i = 0; i < n; ++i) weights[size_t(i) * n + i] = 1.0f;
    const Far::PrimvarRefiner primvars(refiner);
    size_t levelStart = 0;
    for (int level = 1; level <= refiner.GetMaxLevel(); ++level) {
        const size_t parentCount = size_t(refiner.GetLevel(level - 1).GetNumVertices());
        const LevelRows parent{weights + levelStart * n, n};
        LevelRows child{weights + (levelStart + parentCount) * n, n};
        primvars.Interpolate(level, parent, child);
        levelStart += parentCount;
    }

    for (uint32_t p = 0; p < localCount; ++p) {
        const Far::Stencil stencil = local->GetStencil(Far::Index(p));
        Row row{weights + size_t(refinedCount + p) * n, n};
        for (int k = 0; k < stencil.GetSize(); ++k) {
            const uint32_t source = uint32_t(stencil.GetVertexIndices()[k]);
            assert(source < refinedCount + p);
            row.AddWithWeight({weights + size_t(source) * n, n}, stencil.GetWeights()[k]);
        }
    }
}

}  // namespace qp
