// Grid factors for drawing sculpted displacement (plan_pass.h's grid paths): every cell of a
// tile whose D is not zero must be a grid cell, or its detail is lost to under-sampling.
//
// Only where the displacement is not identically zero does the grid follow the tiles: a drawn
// sub-face whose padded block (its cells and the overlap around them) is not all zero gets a
// factor of at least requiredTessellationFactor (its cells per side), and an edge whose strip
// (the own row and the overlap along it) is not all zero gets that many pieces (half of them on
// each half of a split cage edge; the tile across has cells of the same size, so it asks for
// the same). Elsewhere D is exactly 0, so the factors asked for (uniform, or screen-adaptive)
// are kept, and a sculpted region costs triangles only where it is. All factors stay powers of
// two (the base's are rounded up), so a sub-face's factor is a multiple of each of its edges'
// pieces.
//
// The tessellated path cannot vary its factors per sub-face this way; it draws displacement at
// a uniform factor (scheme_support.h, displacedGridFactor).
#pragma once

#include "displacement/displacement.h"
#include "gpu_plans.h"
#include "grid_layout.h"

namespace qp {

// `base` raised for `displacement` (which must belong to the cage `data` was made from).
// `screen` (adaptive factors for a few pixels per segment, grid_layout.h) caps the raise: a tile
// whose cells lie closer together on screen than that is drawn at the screen's pieces (a power
// of two below its cells), so detail smaller than a few pixels costs no triangles; samples
// then fall between vertices (D is evaluated exactly at every vertex drawn).
GridFactors displacedGridFactors(const GpuPlanData& data, const Displacement& displacement, GridFactors base,
                                 const GridFactors* screen = nullptr);

}  // namespace qp
