// OpenSubdiv Far as the benchmarks' baseline: a full rebuild with the plan builder's options
// (adaptive refinement to the plans' depth, Gregory-basis end caps, infinitely sharp patches),
// its stencil table (refined and local points) and the vertex type UpdateValues needs. Shared by
// the plans suite (bench_plans.cpp) and the animation suite (bench_animation.cpp).
#pragma once

#include <memory>

#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "plans/face_config.h"

namespace qp::cli {

struct FarBuild {
    std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refiner;
    std::unique_ptr<OpenSubdiv::Far::PatchTable> patches;
    std::unique_ptr<const OpenSubdiv::Far::StencilTable> stencils;  // refined + local points
    double patchesMs = 0.0, stencilsMs = 0.0;                        // both from the start
};

// One full rebuild; the patch-table time is taken on the way to the stencil tables, so one run
// gives both baselines.
FarBuild buildFar(const Cage& cage, const PlanOptions& options);

// The vertex type Far::StencilTable::UpdateValues needs: a glm::vec3's layout.
struct FarPoint {
    float x, y, z;
    void Clear(void* = nullptr) { x = y = z = 0.0f; }
    void AddWithWeight(const FarPoint& p, float w) { x += w * p.x; y += w * p.y; z += w * p.z; }
};
static_assert(sizeof(FarPoint) == sizeof(glm::vec3));

}  // namespace qp::cli
