// Edge loops, edge rings and face loops: the selections a modeler's Alt+click makes (Blender's
// rules), found on the cage's topology alone.
//
// - edgeLoop: from an edge, both ways through every regular vertex: an interior vertex with
//   exactly 4 edges and 4 faces continues on the edge opposite (the one sharing no face with the
//   edge arrived by). A boundary edge continues along the boundary through boundary vertices with
//   exactly 3 edges (the one interior edge is the loop's "side"). The walk stops at a pole (any
//   other vertex), a non-manifold edge, or where it closes on itself.
// - edgeRing: from an edge, both ways across quads: each quad beside the edge gives its opposite
//   edge, which continues into the quad on its other side. Stops at a non-quad, a boundary or
//   non-manifold edge, or where it closes.
// - faceLoop: the quads an edge ring crosses (the strip of faces across the edge's direction).
//
// Results are sorted (EdgeKeys, face indices) and hold the start edge (or, for face loops, the
// quads beside it) whenever the edge exists; an edge that does not exist gives an empty result.
#pragma once

#include <cstdint>
#include <vector>

#include "edit/selection.h"
#include "mesh/cage.h"
#include "mesh/topology.h"

namespace qp {

std::vector<EdgeKey> edgeLoop(const Cage& cage, const Topology& topology, EdgeKey edge);
std::vector<EdgeKey> edgeRing(const Cage& cage, const Topology& topology, EdgeKey edge);
std::vector<uint32_t> faceLoop(const Cage& cage, const Topology& topology, EdgeKey edge);

}  // namespace qp
