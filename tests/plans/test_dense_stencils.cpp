// Dense stencils against Far::StencilTableFactory, the sparse tables they replaced in the plan
// builder: the same sums in the same order, so every weight must match bit for bit.
#include <gtest/gtest.h>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include "mesh/generated_cage.h"
#include "plans/dense_stencils.h"
#include "plans/osd_refiner.h"
#include "test_cages.h"

namespace {

using namespace OpenSubdiv;

// Refines the whole cage adaptively as plans do and compares every point's row.
void expectSameAsFar(const qp::Cage& cage, uint32_t depth, bool useCreaseNodes) {
    auto refiner = qp::createRefiner(cage, "test cage");
    ASSERT_TRUE(refiner.ok()) << refiner.error().message;
    const Far::PatchTableFactory::Options patchOptions = qp::planPatchOptions(depth, useCreaseNodes);
    (*refiner)->RefineAdaptive(patchOptions.GetRefineAdaptiveOptions());
    std::unique_ptr<Far::PatchTable> patches(Far::PatchTableFactory::Create(**refiner, patchOptions));

    Far::StencilTableFactory::Options options;
    options.generateControlVerts = true;
    options.generateIntermediateLevels = true;
    options.factorizeIntermediateLevels = true;
    std::unique_ptr<const Far::StencilTable> far(Far::StencilTableFactory::Create(**refiner, options));
    if (const Far::StencilTable* local = patches->GetLocalPointStencilTable(); local && local->GetNumStencils() > 0)
        far.reset(Far::StencilTableFactory::AppendLocalPointStencilTable(**refiner, far.get(), local, true));

    qp::DenseStencils dense;
    qp::computeDenseStencils(**refiner, *patches, dense);
    ASSERT_EQ(dense.ringSize, cage.positions.size());
    ASSERT_EQ(dense.pointCount, uint32_t(far->GetNumStencils()));
    ASSERT_GT(dense.pointCount, (*refiner)->GetLevel(0).GetNumVertices()) << "nothing was refined";
    std::vector<float> expected(dense.ringSize);
    for (uint32_t p = 0; p < dense.pointCount; ++p) {
        std::fill(expected.begin(), expected.end(), 0.0f);
        const Far::Stencil stencil = far->GetStencil(Far::Index(p));
        for (int k = 0; k < stencil.GetSize(); ++k) expected[size_t(stencil.GetVertexIndices()[k])] += stencil.GetWeights()[k];
        const std::span<const float> row = dense.row(p);
        for (uint32_t j = 0; j < dense.ringSize; ++j)
            ASSERT_EQ(row[j], expected[j]) << "point " << p << " of " << dense.pointCount << ", control point " << j;
    }
}

TEST(DenseStencils, MatchFarOnExtraordinaryAndMixedFaces) {
    expectSameAsFar(qp::test::makeMixedGrid(), 4, true);
    expectSameAsFar(qp::test::makeCube(), 6, true);
}

TEST(DenseStencils, MatchFarWithSemiSharpCreasesAndCorners) {
    qp::Cage cage = qp::test::makeSubdividedCube(3);
    cage.setEdgeSharpness(cage.faceBegin(0)[0], cage.faceBegin(0)[1], 2.5f);
    cage.setEdgeSharpness(cage.faceBegin(0)[1], cage.faceBegin(0)[2], 0.7f);
    cage.setVertexSharpness(cage.faceBegin(5)[2], 1.5f);
    expectSameAsFar(cage, 5, true);
    expectSameAsFar(cage, 5, false);
}

TEST(DenseStencils, MatchFarOnAGeneratedCage) { expectSameAsFar(qp::makeBenchmarkCage(200, 3), 4, true); }

}  // namespace
