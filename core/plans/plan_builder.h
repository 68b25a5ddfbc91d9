// PlanBuilder: turns a face configuration into its subdivision plan.
//
// The configuration's local mesh (FaceConfig::key) becomes a small OpenSubdiv refiner that is
// refined adaptively around the face only, to the plan's depth. Far's patches over the face
// become the quadtree leaves (regular B-spline, single-crease, Gregory end caps); chains of
// three regular quadrants around an extraordinary vertex collapse into Terminal nodes; every
// control point becomes a dense stencil over the 1-ring (refinement stencils composed with
// end-cap local-point stencils), sorted by the lowest tessellation level that needs it.
#pragma once

#include "mesh/result.h"
#include "plans/face_config.h"
#include "plans/plan.h"

namespace qp {

// Builds the plan of the configuration described by `key` (see face_config.h). A face without a
// limit surface (a boundary face when the boundary rule is "none") gets a plan with no nodes.
// Fails only when OpenSubdiv rejects the local topology.
Result<Plan> buildPlan(const std::vector<uint32_t>& key);

// Tessellation level (factor <= 2^level) from which a node covering
// [u0, u0 + size] x [v0, v0 + size] of the face domain can be reached.
uint32_t nodeNeededLevel(float u0, float v0, float size, uint32_t maxDepth);

}  // namespace qp
