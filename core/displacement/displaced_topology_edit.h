// A topology edit on an object with sculpted displacement, as ONE history entry: the topology
// step (a plain TopologyDelta, or makeAnimatedTopologyEdit's entry on an animated object), then
// the displacement carried to the new cage (transferDisplacement), then optionally a move of
// vertices (an extrude by a distance is an extrude in place, whose surface the sculpt is
// projected from, then that move: the extruded region takes its sculpt along, as a move does).
//
// The transfer runs once, the first time the entry is performed; undo and redo swap the
// displacements before and after, so undo brings the sculpt back bit for bit. The target
// Displacement and the listener must outlive the entry (they live in the document that owns the
// history); the listener hears of every swap as a new layout.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "displacement/displacement_edit.h"
#include "displacement/displacement_transfer.h"
#include "edit/edit_history.h"
#include "mesh/topology_edits.h"

namespace qp {

// The plain topology step as a CustomEdit (what EditHistory::applyTopologyEdit records). `edit`
// must have been made from planned.cage() by an operation of topology_edits.h.
std::unique_ptr<CustomEdit> makeTopologyStep(const PlannedCage& planned, const TopologyEdit& edit);

// Vertices moved to new places right after the topology step (numbering after it).
struct FollowingMove {
    std::vector<uint32_t> vertices;
    std::vector<glm::vec3> positions;
};

std::unique_ptr<CustomEdit> makeDisplacedTopologyEdit(std::unique_ptr<CustomEdit> topologyStep, Displacement& target,
                                                      DisplacementListener listener, FollowingMove move = {});

// An extrude by `distance` split as the entry above wants it: the extrude in place, and the
// move of its result vertices to where extrudeFaces(..., distance) puts them.
struct SplitExtrude {
    TopologyEdit inPlace;
    FollowingMove move;
};
Result<SplitExtrude> splitExtrude(const Cage& cage, const Topology& topology, std::span<const uint32_t> faces,
                                  float distance);

}  // namespace qp
