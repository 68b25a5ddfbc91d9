// Whether a cage's limit surface hides its own back side: every pipeline draws back sides (open
// cages show their inside), so a back-facing patch is hidden only when the surface in front of
// it must cover it. That holds for a closed, consistently oriented surface whose normals point
// outward, seen from outside: a ray from the eye to a back-facing point leaves the solid there,
// so it entered it before, through a front-facing point (self-intersections included: the
// winding number along the ray must be positive just before the point).
#pragma once

#include "mesh/cage.h"
#include "mesh/topology.h"

namespace qp {

// True when every edge lies between two faces that traverse it in opposite directions (closed,
// consistently oriented), no face is a hole, and every connected piece encloses a positive
// volume (the cage's signed volume, at least 1e-4 of its box's diagonal cubed: a piece turned
// inside out, or one too flat to tell, is not cullable).
bool closedOutwardSurface(const Cage& cage, const Topology& topology);

}  // namespace qp
