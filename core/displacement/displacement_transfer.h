// Carrying sculpted displacement across a topology edit (issue 19 part 3; docs/displacement.md,
// "Topology edits"). The samples follow the sub-faces, so an edit that adds, removes or rewires
// faces needs a displacement for the new cage (same R). What the user sculpted must survive it:
//
//   - KEPT sub-faces, those whose limit surface the edit leaves alone (they map to a sub-face
//     before the edit and the edit report does not list them as updated), keep the samples of
//     their own cells bit for bit. Their D is the same function as before except within a cell
//     of an edge to a changed neighbour, whose overlap samples are the neighbour's.
//   - CHANGED sub-faces (new, rewired, or with a changed 1-ring) take the old D by projection:
//     at each point of a half-cell grid over the tile, the limit point p with unit normal N,
//     the nearest point where the line p + t N meets the old limit surface (within reach: half
//     the changed faces' mean edge length, about the most an edit moves the limit surface) gives
//     the place whose old D (and mask) the point takes; the tile's samples are fitted to those
//     values (fitSamples' quasi-interpolant). So the sculpted relief stays where it was on the
//     surface, riding on the limit surface the edit made (which is what the edit shows without
//     sculpt too); where nothing was sculpted D stays exactly 0. A point with no old surface in
//     reach (a face filling a hole) counts 0.
// The mask is carried the same way.
#pragma once

#include <cstdint>

#include "displacement/displacement.h"
#include "plans/planned_cage.h"

namespace qp {

struct DisplacementTransfer {
    Displacement displacement;  // for `after`'s cage
    uint32_t keptSubfaces = 0, changedSubfaces = 0;
    uint32_t projectedSamples = 0;  // set from the old D by projection
    uint32_t unreachedSamples = 0;  // no old surface within reach: 0
    float reach = 0.0f;
};

// `before` and `old`: the planned cage and its (non-empty) displacement before the edit;
// `after`: the planned cage after it; `report`: the edit's report (topologyChanged, with
// previousSubfaceOf and updatedSubfaceList in after's numbering).
DisplacementTransfer transferDisplacement(const PlannedCage& before, const Displacement& old, const PlannedCage& after,
                                          const EditReport& report);

}  // namespace qp
