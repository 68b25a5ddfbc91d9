// The measurements behind `quadplan bench displacement` (cmd_bench.cpp turns them into rows):
// one brush dab on a cage, CPU time to update the samples, the bytes a GPU buffer update
// needs, and the time to copy those ranges into a host-visible buffer (a std::vector stands
// in for the mapped Vulkan buffer: the copy is the same memcpy). Medians of repeated dabs at
// different places of the surface.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cage.h"
#include "brush.h"

namespace qp::cli {

struct DabMeasurement {
    BrushKind brush;
    float radius = 0.0f;
    uint32_t repeats = 0;
    double updateMs = 0.0;     // Sculptor::dab: query, new values, write, undo bookkeeping
    double uploadMs = 0.0;     // building the copy ranges and copying them
    double totalMs = 0.0;      // per dab, median of the sums
    double bytes = 0.0;        // median bytes copied per dab
    double samplesReached = 0.0;  // median samples within the radius
};

struct DisplacementBenchResult {
    std::string error;         // set when the cage could not be planned
    uint32_t resolution = 0, samples = 0;
    double cacheBuildMs = 0.0;      // SculptSamples::build, once per layout
    double fullUploadMs = 0.0;      // copying every sample (what a whole-buffer update costs)
    std::vector<DabMeasurement> dabs;
};

DisplacementBenchResult measureDisplacementDabs(const Cage& cage, uint32_t resolution, uint32_t repeats, uint32_t seed);

}  // namespace qp::cli
