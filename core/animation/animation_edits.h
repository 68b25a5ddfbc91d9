// Edits of an animated cage as undo history entries (edit_history.h CustomEdit), shared by the
// editor's and the Python module's documents, so that an animation follows every edit and every
// undo the same way in both:
//  - a vertex move at a frame sets keys on that frame for the moved vertices (animate.md: the
//    editor and Python say which frame), undone by giving the vertices their tracks back;
//  - a topology edit carries the keys to the new vertices (applyTopologyEditToAnimation), undone
//    by restoring the tracks and rest positions as they were;
//  - inserting or deleting keys at a frame without moving anything (the editor's I key).
// Each entry stores only what it changes (the moved vertices' tracks before and after; the whole
// animation for a topology edit) and, after each redo or undo, shows the document's current frame
// of the cage: positions always follow the keys, whatever frame the entry was made at.
//
// The documents own their animations; an entry finds its object's through an AnimationAccess
// called when it runs (objects may have been renumbered since the entry was made).
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "animation/cage_animation.h"
#include "edit/edit_history.h"
#include "mesh/topology_edits.h"
#include "plans/planned_cage.h"

namespace qp {

// An animated cage as a document holds it: the keys, the rest positions (a vertex without keys
// stays there; what the scene file saves as the cage's positions) and the frame shown.
struct AnimatedCageState {
    ObjectAnimation* animation = nullptr;
    std::vector<glm::vec3>* rest = nullptr;
    double frame = 0.0;
};
using AnimationAccess = std::function<AnimatedCageState()>;

// Moves `vertices` to `positions` at `frame` (an integer: keys sit on frames) and sets keys there;
// with the positions the cage shows, it inserts keys without moving anything (the I key).
std::unique_ptr<CustomEdit> makeKeyedMove(const AnimatedCageState& state, AnimationAccess access, int32_t frame,
                                          std::span<const uint32_t> vertices, std::span<const glm::vec3> positions);

// Removes every vertex's key at `frame`.
std::unique_ptr<CustomEdit> makeKeyRemoval(const AnimatedCageState& state, AnimationAccess access, int32_t frame);

// `edit` made from the cage as shown at state.frame (planned.cage()).
std::unique_ptr<CustomEdit> makeAnimatedTopologyEdit(const PlannedCage& planned, const AnimatedCageState& state,
                                                     AnimationAccess access, const TopologyEdit& edit);

}  // namespace qp
