#include "bench_far.h"

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include "bench_report.h"
#include "plans/osd_refiner.h"

namespace qp::cli {

using namespace OpenSubdiv;

FarBuild buildFar(const Cage& cage, const PlanOptions& options) {
    FarBuild build;
    auto start = Clock::now();
    auto patchOptions = planPatchOptions(options.maxDepth, options.useCreaseNodes);
    build.refiner = std::move(createRefiner(cage, "bench").value());
    build.refiner->RefineAdaptive(patchOptions.GetRefineAdaptiveOptions());
    build.patches.reset(Far::PatchTableFactory::Create(*build.refiner, patchOptions));
    build.patchesMs = msSince(start);

    Far::StencilTableFactory::Options stencilOptions;
    stencilOptions.generateOffsets = true;
    stencilOptions.generateIntermediateLevels = true;
    build.stencils.reset(Far::StencilTableFactory::Create(*build.refiner, stencilOptions));
    if (const Far::StencilTable* local = build.patches->GetLocalPointStencilTable(); local && local->GetNumStencils())
        build.stencils.reset(
            Far::StencilTableFactory::AppendLocalPointStencilTable(*build.refiner, build.stencils.get(), local));
    build.stencilsMs = msSince(start);
    return build;
}

}  // namespace qp::cli
