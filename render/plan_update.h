// Plan updates in place: after a tag edit re-planned some sub-faces (edge or vertex sharpness,
// the crease method, holes), bring a cage's GPU copies (plan_pass.h PlanBuffers) up to date for just
// those sub-faces instead of uploading the cage again.
//
// What changes and how it is kept:
//   - plan tables (headers, nodes, points, weights) only grow: plans new to the database are
//     appended (gpu_plans.h appendPlanTables), the buffers grown by half again when full;
//   - the re-planned sub-faces' records (plan, rotation) and rings are rewritten where they are;
//   - control points are sub-allocated: a sub-face keeps its range while its new plan needs no
//     more stencils than the range holds, and otherwise gets a new range at the end; the ranges
//     left behind are garbage, and once garbage is more than half of the buffer the ranges are
//     packed again (every control point is then recomputed at the next draw);
//   - what is cached (control points, the evaluated grid) is refreshed for those sub-faces and
//     the neighbours that copy their edge vertices (recordSubfaceRefresh), so the frame after
//     the edit costs what the edit touched.
// The result equals uploadPlans of the edited cage in everything a draw reads (tests compare
// the pictures and the grid bit for bit).
//
// Holes stay in the tables (PlannedCage plans them; PlanBuffers::holeDrawn hides them), so
// making or filling one rewrites that sub-face's record only. The drawn set changes when a
// sub-face gains or loses its planned surface (a hole whose plan could not be built is filled):
// then the sub-face tables are packed again (O(cage) bookkeeping, no evaluation), every kept
// sub-face keeps its control-point range, grid factors and evaluated vertices (moved to their
// new slots), and only the sub-faces whose edges or corners now have another owner are
// evaluated again.
//
// Topology edits renumber the sub-faces (and the cage's vertices, edges and faces): given the
// renumbering, the sub-face tables are packed again (as above), the positions and boundary
// points uploaded again (O(cage) copies, no evaluation), and kept sub-faces keep their
// control-point ranges and evaluated grid vertices; new sub-faces, re-planned ones and those
// whose edges now have another owner are evaluated. With uniform grid factors the grid keeps its
// layout for what was there; adaptive factors on a cage with new edges lay it out anew.
//
// Changes it does not apply in place (the caller uploads the cage again, with the reason): a
// ring that changed under a tag edit, a topology edit while a displacement is set.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "plan_pass.h"

namespace qp {

struct PlanTableUpdate {
    bool applied = false;  // false: nothing was changed; `reason` says why (upload the cage again)
    std::string reason;
    uint32_t rewrittenSubfaces = 0;    // drawn sub-faces whose record was rewritten
    uint32_t appendedPlans = 0;
    uint32_t relocatedSubfaces = 0;    // got a new control-point range
    bool compacted = false;            // the control-point ranges were packed again
    bool gridDropped = false;          // holes: the grid could not keep its factors (a segment
                                       // only new sub-faces have, an edge split otherwise): it is
                                       // laid out and evaluated whole at the next draw
    std::vector<uint32_t> refresh;     // drawn sub-faces to pass to recordSubfaceRefresh
};

// `subfaces`: PlannedCage sub-faces (any order, repeats allowed) whose plan, rotation or
// control points the edit changed (EditReport::updatedSubfaceList and the sub-faces of
// replannedFaceList). `previousSubfaceOf`: after a topology edit, EditReport::previousSubfaceOf
// (empty for tag edits); then only `subfaces` are looked at for new owners of their edges and
// corners, so they must hold every re-planned sub-face. Writes the host-visible buffers directly: the device must be done with
// them. Fails only when a buffer cannot grow (out of memory): then upload the cage again.
Result<PlanTableUpdate> updatePlanTables(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers,
                                         const PlannedCage& planned, std::span<const uint32_t> subfaces,
                                         std::span<const uint32_t> previousSubfaceOf = {});

}  // namespace qp
