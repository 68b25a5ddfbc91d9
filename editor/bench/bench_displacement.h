// The measurements behind `quadplan bench displacement` (benchDisplacement turns them into
// rows): one brush dab on a cage, CPU time to update the samples, then the GPU buffers of the plans
// renderer (render/plan_pass.h, recordDisplacementChange): the changed sample ranges copied
// into the mapped Vulkan sample buffer and the grid of the CPU grid path (the default on
// lavapipe) re-evaluated for the sub-faces that read them, in the mapped vertex buffer. The
// baseline, in the same process: re-evaluating the whole grid and uploading every sample.
// Medians of repeated dabs at different places of the surface.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "displacement/brush.h"
#include "mesh/cage.h"
#include "vk_context.h"

namespace qp::cli {

struct DabMeasurement {
    BrushKind brush;
    float radius = 0.0f;
    uint32_t repeats = 0;
    double updateMs = 0.0;     // Sculptor::dab: query, new values, write, undo bookkeeping
    double uploadMs = 0.0;     // copy ranges, samples into the Vulkan buffer, grid re-evaluation
    double totalMs = 0.0;      // per dab, median of the sums
    double bytes = 0.0;        // median sample bytes copied per dab
    double gridSubfaces = 0.0; // median sub-faces whose grid slots were re-evaluated
    double gridSlots = 0.0;    // median grid slots re-displaced (those whose D reads a changed sample)
    double samplesReached = 0.0;  // median samples within the radius
};

struct DisplacementBenchResult {
    std::string error;         // set when the cage could not be planned
    uint32_t resolution = 0, samples = 0;
    double cacheBuildMs = 0.0;      // SculptSamples::build, once per layout
    double fullUploadMs = 0.0;      // baseline: every sample uploaded and the whole grid re-evaluated
    uint32_t gridFactor = 0, gridSubfaces = 0;
    std::vector<DabMeasurement> dabs;
};

DisplacementBenchResult measureDisplacementDabs(const VulkanContext& context, const Cage& cage, uint32_t resolution,
                                                uint32_t repeats, uint32_t seed);

}  // namespace qp::cli
