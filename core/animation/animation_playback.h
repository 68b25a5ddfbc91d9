// Playing a cage animation (cage_animation.h) on a planned cage: a frame is a vertex move of the
// vertices whose position at that frame differs from the one shown, so it re-plans nothing and
// refreshes only the sub-faces around them (every sub-face, through PlannedCage's whole-cage
// path, when every vertex moves).
#pragma once

#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "animation/cage_animation.h"
#include "plans/planned_cage.h"

namespace qp {

// The positions of `rest.size()` vertices at `frame`.
std::vector<glm::vec3> positionsAtFrame(const ObjectAnimation& animation, std::span<const glm::vec3> rest, double frame);

// Moves `planned` to `frame`; `rest` are the cage's rest positions (a vertex without keys stays
// there). The report's replannedFaces is 0 by construction; updatedSubfaces counts the refresh.
Result<EditReport> showFrame(PlannedCage& planned, const ObjectAnimation& animation, std::span<const glm::vec3> rest,
                             double frame);

}  // namespace qp
