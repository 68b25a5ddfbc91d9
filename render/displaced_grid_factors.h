// Grid factors for drawing sculpted displacement (plan_pass.h's grid paths): every stored
// sample that is not zero must be a grid vertex, or its detail is lost to under-sampling.
//
// Only where the displacement is not identically zero does the grid follow the tiles: a drawn
// sub-face whose grid samples (interior, corners and edges at its resolution R) are not all
// zero gets a factor of at least R, a segment whose samples are not all zero at least its
// resolution S pieces (both halves of a split cage edge alike). Elsewhere D is exactly 0, so
// the factors asked for (uniform, or screen-adaptive) are kept, and a sculpted region costs
// triangles only where it is. All factors stay powers of two (the base's are rounded up), so a
// sub-face's factor is a multiple of each of its edges' pieces.
//
// The tessellated path cannot vary its factors per sub-face this way; it draws displacement at
// a uniform factor (scheme_support.h, displacedGridFactor).
#pragma once

#include "displacement.h"
#include "gpu_plans.h"
#include "grid_layout.h"

namespace qp {

// `base` raised for `displacement` (which must belong to the cage `data` was made from).
// `screen` (adaptive factors for a few pixels per segment, grid_layout.h) caps the raise: a tile
// whose samples lie closer together on screen than that is drawn at the screen's pieces (a power
// of two below its resolution), so detail smaller than a few pixels costs no triangles; samples
// then fall between vertices (D is evaluated exactly at every vertex drawn).
GridFactors displacedGridFactors(const GpuPlanData& data, const Displacement& displacement, GridFactors base,
                                 const GridFactors* screen = nullptr);

}  // namespace qp
