// One uniform Catmull-Clark step that keeps track of where every sub-face went, for schemes
// that need an all-quad cage (ACC-1, ACC-2) or isolated extraordinary vertices (Stam).
//
// The step is OpenSubdiv's (Far::TopologyRefiner level 1 and PrimvarRefiner), so boundary
// interpolation, creases, corners and holes follow the cage's options exactly; the refined
// cage carries OpenSubdiv's level-1 tags (sharpness decayed by one level).
//
// Children are laid out so that (sub-face, u, v) of the parent means the same surface point as
// (child face, s, t) of the refined cage (whose faces are all quads, so face = sub-face):
//   - parent face f with n corners gets children firstChild[f] + k, k = 0 .. n-1 (quads: 4);
//   - child k has the vertices (vertex point of corner k, edge point of edge k (corner k to
//     k+1), face point, edge point of edge k-1), in that order, so its frame has its origin at
//     corner k, s towards corner k+1 and t towards corner k-1;
//   - an n-gon (n != 4) sub-face k IS child k: same frame, (s, t) = (u, v);
//   - a quad (one sub-face) covers its four children (parent frame: corner 0 at (0,0), 1 at
//     (1,0), 2 at (1,1), 3 at (0,1)):
//       child 0: u <= 1/2, v <= 1/2   s = 2u,        t = 2v
//       child 1: u >= 1/2, v <= 1/2   s = 2v,        t = 2(1 - u)
//       child 2: u >= 1/2, v >= 1/2   s = 2(1 - u),  t = 2(1 - v)
//       child 3: u <= 1/2, v >= 1/2   s = 2(1 - v),  t = 2u
//     On a split line (u or v exactly 1/2) the lower-numbered child wins; the surface is
//     continuous there, so any choice gives the same point.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

struct RefinedCage {
    Cage cage;                            // all quads; level-1 tags; holes' children are holes
    std::vector<uint32_t> firstChild;     // per parent face: its first child face (faces + 1 entries)
    std::vector<uint32_t> parentFirstSubface;  // per parent face: first sub-face (faces + 1 entries)
};

// Fails when OpenSubdiv rejects the cage (the message names `source`).
Result<RefinedCage> refineOnce(const Cage& cage, const std::string& source = "cage");

// A point of a parent sub-face expressed on the refined cage. Derivatives map as
//   d/du = dsdu * d/ds + dtdu * d/dt,   d/dv = dsdv * d/ds + dtdv * d/dt.
struct RefinedLocation {
    uint32_t face = 0;  // face (= sub-face) of the refined cage
    double s = 0.0, t = 0.0;
    double dsdu = 1.0, dsdv = 0.0, dtdu = 0.0, dtdv = 1.0;
};

// `subface` numbers the parent cage's sub-faces (as PlannedCage does).
RefinedLocation locateInRefined(const RefinedCage& refined, uint32_t subface, double u, double v);

// Chains a location through a further refinement of an all-quad cage (whose faces are its
// sub-faces): the result is relative to the original (u, v).
RefinedLocation locateInRefined(const RefinedCage& refined, const RefinedLocation& outer);

}  // namespace qp
