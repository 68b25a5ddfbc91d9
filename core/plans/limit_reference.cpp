#include "plans/limit_reference.h"

#include <algorithm>
#include <optional>

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include "plans/osd_refiner.h"
#include "plans/plan.h"
#include "plans/tangent_plane.h"

namespace qp {

using namespace OpenSubdiv;

LimitReference::~LimitReference() = default;
LimitReference::LimitReference(LimitReference&&) noexcept = default;
LimitReference& LimitReference::operator=(LimitReference&&) noexcept = default;

namespace {

// As the plans do (core/plans/plan_builder.cpp): at each Gregory end-cap corner on a dart corner of
// its base (sub-)face, the edge points Ep and Em are moved onto the exact tangent plane, their
// tangent masks projected onto the dart's dominant eigenvectors (tangent_plane.h), because
// Sdc's masks, which Far's end caps use, are the smooth rule's there.
void exactDartCorners(const Far::TopologyRefiner& r, const Far::PatchTable& patches, const Far::StencilTableReal<double>& stencils,
                      const Cage& cage, std::vector<glm::dvec3>& points) {
    const Far::TopologyLevel& base = r.GetLevel(0);
    std::vector<std::optional<ExactTangents>> darts(size_t(base.GetNumVertices()));
    bool any = false;
    for (Far::Index v = 0; v < base.GetNumVertices(); ++v) any |= (darts[size_t(v)] = exactTangents(r, v)).has_value();
    if (!any) return;
    std::vector<Far::Index> ptexVertex;  // per ptex face, its base vertex at (0, 0) and the next three (quads)
    for (Far::Index f = 0; f < base.GetNumFaces(); ++f) {
        const Far::ConstIndexArray fv = base.GetFaceVertices(f);
        if (fv.size() == 4) ptexVertex.insert(ptexVertex.end(), fv.begin(), fv.end());
        else
            for (int k = 0; k < fv.size(); ++k) ptexVertex.insert(ptexVertex.end(), {fv[k], -1, -1, -1});
    }
    std::vector<char> done(points.size(), 0);
    for (int array = 0; array < patches.GetNumPatchArrays(); ++array) {
        if (patches.GetPatchArrayDescriptor(array).GetType() != Far::PatchDescriptor::GREGORY_BASIS) continue;
        for (int p = 0; p < patches.GetNumPatches(array); ++p) {
            const Far::PatchParam param = patches.GetPatchParam(array, p);
            const Far::ConstIndexArray cvs = patches.GetPatchVertices(array, p);
            const uint32_t cells = 1u << (param.GetDepth() - (param.NonQuadRoot() ? 1 : 0));
            for (uint32_t i = 0; i < 4; ++i) {
                const int c = patchCornerOfDomain(uint32_t(param.GetU()), uint32_t(param.GetV()), cells, i);
                if (c < 0) continue;
                const Far::Index vertex = ptexVertex[size_t(4 * param.GetFaceId() + c)];
                if (vertex < 0 || !darts[size_t(vertex)]) continue;
                const ExactTangents& t = *darts[size_t(vertex)];
                auto maskOver = [&](Far::Index point) {
                    std::vector<double> mask(t.ring.size(), 0.0);
                    const Far::StencilReal<double> s = stencils.GetStencil(point);
                    for (int k = 0; k < s.GetSize(); ++k) {
                        auto at = std::find(t.ring.begin(), t.ring.end(), s.GetVertexIndices()[k]);
                        if (at != t.ring.end()) mask[size_t(at - t.ring.begin())] += s.GetWeights()[k];
                    }
                    return mask;
                };
                const std::vector<double> corner = maskOver(cvs[5 * i]);
                for (Far::Index edgePoint : {cvs[5 * i + 1], cvs[5 * i + 2]}) {
                    if (done[size_t(edgePoint)]) continue;  // shared with the neighbouring end cap
                    done[size_t(edgePoint)] = 1;
                    std::vector<double> tangent = maskOver(edgePoint);
                    for (size_t j = 0; j < tangent.size(); ++j) tangent[j] -= corner[j];
                    const std::vector<double> exact = t.project(tangent);
                    glm::dvec3 moved = points[size_t(cvs[5 * i])];
                    for (size_t j = 0; j < exact.size(); ++j) moved += exact[j] * glm::dvec3(cage.positions[size_t(t.ring[j])]);
                    points[size_t(edgePoint)] = moved;
                }
            }
        }
    }
}

}  // namespace

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
    exactDartCorners(r, *ref.patches_, *stencils, cage, ref.points_);
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
    // the sub-face's own (u, v) are half as large (tests/plans/test_plan.cpp checks this).
    if (patches_->GetPatchParam(*handle).NonQuadRoot()) {
        sample.du *= 0.5;
        sample.dv *= 0.5;
    }
    return sample;
}

}  // namespace qp
