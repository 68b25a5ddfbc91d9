#include "limit_reference.h"

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include "osd_refiner.h"

namespace qp {

using namespace OpenSubdiv;

LimitReference::~LimitReference() = default;
LimitReference::LimitReference(LimitReference&&) noexcept = default;
LimitReference& LimitReference::operator=(LimitReference&&) noexcept = default;

Result<LimitReference> LimitReference::create(const Cage& cage, uint32_t depth, const std::string& source) {
    auto refiner = createRefiner(cage, source);
    if (!refiner) return refiner.error();
    Far::TopologyRefiner& r = **refiner;

    Far::PatchTableFactory::Options options(depth);
    options.useInfSharpPatch = true;
    options.useSingleCreasePatch = false;
    options.generateLegacySharpCornerPatches = false;
    options.generateVaryingTables = false;
    options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    // Double-precision local points: near an extraordinary vertex the deepest end cap's points
    // nearly coincide, and float stencil weights would leave their differences (the
    // derivatives) to round-off (10-20 degrees of normal at depth 10 next to a valence-3 vertex).
    options.SetPatchPrecision<double>();
    r.RefineAdaptive(options.GetRefineAdaptiveOptions());

    LimitReference ref;
    ref.patches_.reset(Far::PatchTableFactory::Create(r, options));
    ref.map_ = std::make_unique<Far::PatchMap>(*ref.patches_);
    ref.subfaces_ = uint32_t(Far::PtexIndices(r).GetNumFaces());

    using Factory = Far::StencilTableFactoryReal<double>;
    Factory::Options stencilOptions;
    stencilOptions.generateIntermediateLevels = true;
    stencilOptions.generateControlVerts = true;
    stencilOptions.generateOffsets = true;
    std::unique_ptr<const Far::StencilTableReal<double>> stencils(Factory::Create(r, stencilOptions));
    if (const auto* local = ref.patches_->GetLocalPointStencilTable<double>(); local && local->GetNumStencils() > 0)
        stencils.reset(Factory::AppendLocalPointStencilTable(r, stencils.get(), local, true));

    ref.points_.resize(size_t(stencils->GetNumStencils()));
    for (int i = 0; i < stencils->GetNumStencils(); ++i) {
        Far::StencilReal<double> s = stencils->GetStencil(i);
        glm::dvec3 p(0.0);
        for (int k = 0; k < s.GetSize(); ++k) p += s.GetWeights()[k] * glm::dvec3(cage.positions[s.GetVertexIndices()[k]]);
        ref.points_[size_t(i)] = p;
    }
    return ref;
}

ReferenceSample LimitReference::evaluate(uint32_t subface, double u, double v) const {
    ReferenceSample sample;
    const Far::PatchTable::PatchHandle* handle = map_->FindPatch(int(subface), u, v);
    if (!handle) return sample;
    double w[20], wu[20], wv[20];
    patches_->EvaluateBasis(*handle, u, v, w, wu, wv);
    Far::ConstIndexArray cvs = patches_->GetPatchVertices(*handle);
    for (int k = 0; k < cvs.size(); ++k) {
        const glm::dvec3& p = points_[size_t(cvs[k])];
        sample.position += w[k] * p;
        sample.du += wu[k] * p;
        sample.dv += wv[k] * p;
    }
    // For the sub-faces of a non-quad, EvaluateBasis differentiates with respect to the
    // parent face's parameterisation, in which a sub-face spans 1/2; finite differences in
    // the sub-face's own (u, v) are half as large (tests/test_plan.cpp checks this).
    if (patches_->GetPatchParam(*handle).NonQuadRoot()) {
        sample.du *= 0.5;
        sample.dv *= 0.5;
    }
    return sample;
}

}  // namespace qp
