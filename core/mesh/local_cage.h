// A local cage: some faces of a cage with their tags, renumbered densely, for OpenSubdiv to
// refine or check just the part of a cage an edit touched (the uniform scheme's in-place tag
// updates, PlannedCage's topology edits).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "mesh/cage.h"

namespace qp {

struct LocalCage {
    Cage cage;                          // passes validateCage when the whole cage does
    std::vector<uint32_t> globalVertex; // local vertex -> its number in the whole cage
};

// `faces` (distinct) in the given order, their vertices numbered in order of first use. Creases
// on their edges, corners on their vertices and the holes among them come along; so do the
// texture coordinates when `withUVs` (and the cage has them). Faces outside the set are missing:
// their edges are boundaries of the local cage.
LocalCage localCage(const Cage& cage, std::span<const uint32_t> faces, bool withUVs = false);

}  // namespace qp
