// Topology edits on a Cage: extrude faces, delete faces, split a face, insert an edge loop,
// merge vertices, make a face from existing vertices.
//
// Every operation reads a cage (and its Topology, which must be buildTopology(cage)) and
// returns either an Error with a message a user can act on (nothing is changed: the input is
// const) or a TopologyEdit: the edited cage, which passes validateCage, plus the bookkeeping
// the plan engine needs to re-plan only what changed (PlannedCage::applyTopologyEdit) and the
// history needs to undo it (cage_delta.h).
//
// Numbering rules shared by all operations (the plan engine and the history rely on them):
//   - faces and vertices that survive keep their relative order; created faces and vertices
//     are appended at the end; removed ones leave no gap (later indices shift down);
//   - a face that survives with a different vertex list keeps its index (it is "changed");
//   - tags follow what they are keyed by: creases by vertex pair, corners by vertex, holes by
//     face; each operation documents what happens to tags on the elements it touches
//     (docs/editing.md has the full table).
// Texture coordinates (when the cage has them) follow the face corners; new corners reuse or
// interpolate the coordinates of the corners they come from.
//
// Non-manifold input (OpenSubdiv's regression cages) is accepted where the result is well
// defined; otherwise the operation refuses with a message naming the offending element.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "mesh/topology.h"

namespace qp {

// oldFaceOf / oldVertexOf entry of an element that did not exist before the edit.
inline constexpr uint32_t kNewElement = UINT32_MAX;

struct TopologyEdit {
    Cage cage;                          // the edited cage
    std::vector<uint32_t> oldFaceOf;    // per face of `cage`: its index before, or kNewElement
    std::vector<uint32_t> oldVertexOf;  // per vertex of `cage`: its index before, or kNewElement

    // Filled by finishTopologyEdit (every operation below calls it):
    std::vector<uint32_t> changedFaces;  // faces of `cage` that are new or got a new vertex list
    std::vector<uint32_t> removedFaces;  // faces of the old cage that are gone (old numbering)

    // What the editor typically selects after the operation (new numbering, sorted):
    // extrude: the moved region; split: the new edge; edge loop: the loop's edges and vertices;
    // merge: the merged vertex; make face: the new face.
    std::vector<uint32_t> resultVertices;
    std::vector<EdgeKey> resultEdges;
    std::vector<uint32_t> resultFaces;
};

// Region extrude. The selected faces move off as connected regions: every vertex of a region
// that lies on the region's boundary (an edge used by exactly one selected face, including
// cage-boundary edges) or is used by an unselected face is duplicated; the selected faces keep
// their indices and take the duplicates; a side quad (a, b, b', a') joins each boundary edge
// a->b to its copy a'->b', oriented like the region. Then every vertex of each connected region
// moves by `distance` along the region's area-weighted average normal (0: leave them in place
// for an interactive move; resultVertices are the vertices to move).
// Tags: a crease on a boundary edge stays on it and is copied to the edge's copy (the region
// keeps its sharp rim); creases inside a region move with it; a corner on a duplicated vertex
// stays and is copied to the duplicate; hole flags of the selected faces are kept, side quads
// are not holes.
// Refuses: an empty or out-of-range selection, an edge used by more than one selected face
// unless it is a manifold edge between two selected faces, a selected face that visits a
// vertex twice, a selection with nothing to extrude (a closed surface: no boundary, no
// neighbour), and a non-zero distance when a region's normals cancel out.
Result<TopologyEdit> extrudeFaces(const Cage& cage, const Topology& topology, std::span<const uint32_t> faces,
                                  float distance = 0.0f);

// Deletes the faces (the hole they leave is an open boundary; hole flags of other faces are
// kept and renumbered). Creases on edges no face uses any more are dropped. With
// `removeUnusedVertices`, vertices that only the deleted faces used are removed (corners on
// them dropped, later vertices renumbered); vertices that were already unused stay.
// Refuses an empty or out-of-range selection and deleting every face.
Result<TopologyEdit> deleteFaces(const Cage& cage, const Topology& topology, std::span<const uint32_t> faces,
                                 bool removeUnusedVertices = true);

// Splits `face` in two along a new edge between two of its non-adjacent vertices a and b. The
// half that holds the face's first corner keeps the face's index (and its first corner); the
// other half is appended. Both halves keep the hole flag; the new edge has no crease.
// Refuses: a or b not in the face, in it twice, equal or adjacent, or already joined by an
// edge of another face (the split would make that edge non-manifold).
Result<TopologyEdit> splitFace(const Cage& cage, const Topology& topology, uint32_t face, uint32_t a, uint32_t b);

// Inserts an edge loop across the ring of quads through edge (a, b): every ring edge gets a new
// vertex at fraction t from its "a" side (t measured consistently along the ring: on the
// opposite edge of each quad, from the vertex next to the "a" side of the edge it entered
// through), and every quad of the ring is split in two by the new loop edges. The ring stops at
// non-quads, at boundary or non-manifold edges, and where it meets a quad it has already cut;
// a face next to a cut edge that is not cut itself (an n-gon, say) gets the new vertex inserted
// into that edge. A ring that closes on itself is a full loop.
// Tags: a creased edge that is cut passes its sharpness to both halves; loop edges have no
// crease; halves of a hole face are holes. The half of a quad holding its first corner keeps
// its index; the other half is appended.
// Refuses: no edge a-b, t outside (0, 1), a non-manifold edge a-b, and an edge with no quad on
// either side (nothing to cut across).
Result<TopologyEdit> insertEdgeLoop(const Cage& cage, const Topology& topology, uint32_t a, uint32_t b, float t);

enum class MergeTarget : uint8_t {
    Centroid,  // the merged vertex sits at the centroid of the selected vertices
    Last,      // ... at the position of the last vertex of the list
};

// Merges the vertices into one: the last vertex of the list survives (its index, shifted down
// by the removed ones) and the others are removed. In every face the merged vertices are
// replaced by the survivor, then repeated consecutive vertices and spikes (x, y, x) are
// collapsed; faces left with fewer than 3 vertices are removed, and of faces that became the
// same cycle (either orientation) only the lowest-numbered one stays.
// Tags, resolved deterministically: creases of edges that become one edge keep the largest
// sharpness; creases between two merged vertices disappear, as do creases of edges no face
// uses any more; the survivor's corner sharpness is the largest of the merged vertices'; hole
// flags follow their faces.
// Refuses: fewer than two distinct vertices, out-of-range vertices, a result with no faces,
// and a result where a face would visit a vertex twice (pinched; ill-defined).
Result<TopologyEdit> mergeVertices(const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices,
                                   MergeTarget target = MergeTarget::Centroid);

// Adds a face through existing vertices, in the given order unless that disagrees with the
// orientation of the faces it shares edges with, in which case it is reversed. No tags on it.
// Refuses: fewer than 3 vertices, repeated or out-of-range vertices, an edge that already has
// two or more faces (the new face would make it non-manifold), shared edges whose faces
// disagree on the orientation, and a face that already exists.
Result<TopologyEdit> makeFace(const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices);

// Checks an edit's maps against the cage it was made from (sizes, ranges, kept elements in
// their old relative order), normalises and validates the new cage, and fills changedFaces
// and removedFaces. `what` names the operation in messages. Used by the operations above and
// by code that builds a TopologyEdit by hand (PlannedCage::addFace, the history).
Status finishTopologyEdit(const Cage& before, TopologyEdit& edit, const std::string& what);

}  // namespace qp
