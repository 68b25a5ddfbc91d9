// Conversion of a Cage to OpenSubdiv's Far::TopologyRefiner, the reference for the limit
// surface and the engine behind subdivision plans.
#pragma once

#include <memory>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/topologyRefiner.h>
#include <opensubdiv/sdc/options.h>

#include "mesh/cage.h"

namespace qp {

OpenSubdiv::Sdc::Options toSdcOptions(const SubdivisionOptions& options);

// The Far patch options subdivision plans are built with (plan_builder.cpp): adaptive to `depth`,
// infinitely sharp patches, single-crease patches when `useCreaseNodes`, Gregory-basis end caps.
// Benchmarks build Far with them too, so both sides do the same work.
OpenSubdiv::Far::PatchTableFactory::Options planPatchOptions(uint32_t depth, bool useCreaseNodes);

// Builds a Catmull-Clark refiner with the cage's topology, creases, corners, holes and UVs
// (as face-varying channel 0). OpenSubdiv's own topology complaints become the error message.
Result<std::unique_ptr<OpenSubdiv::Far::TopologyRefiner>> createRefiner(const Cage& cage,
                                                                         const std::string& source);

}  // namespace qp
