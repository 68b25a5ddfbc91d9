// Selection: the vertices, edges or faces of a cage the user has picked, as sorted unique
// lists of indices (edges by their end vertices, like creases), plus the operations an editor
// offers on them. A selection holds elements of its mode only; converting changes the mode.
//
// Rules (Blender's, which most users know):
//   convert  vertex -> edge: edges with both ends selected; vertex -> face: faces with every
//            corner selected; edge -> vertex: their ends; edge -> face: faces with every edge
//            selected; face -> vertex: their corners; face -> edge: their edges.
//   grow     vertex: + vertices joined to a selected one by an edge; edge: + edges sharing a
//            vertex with a selected edge; face: + faces sharing a vertex with a selected face.
//   shrink   the inverse: vertex: drop vertices with an unselected neighbour; edge: drop edges
//            at a vertex that has an unselected edge; face: drop faces sharing a vertex with an
//            unselected face.
// Every function taking a Topology needs buildTopology(cage) of the same cage.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "mesh/cage.h"
#include "mesh/topology.h"
#include "mesh/topology_edits.h"

namespace qp {

enum class SelectionMode : uint8_t { Vertex, Edge, Face };

struct Selection {
    SelectionMode mode = SelectionMode::Vertex;
    std::vector<uint32_t> vertices;  // Vertex mode
    std::vector<EdgeKey> edges;      // Edge mode
    std::vector<uint32_t> faces;     // Face mode

    size_t size() const;
    bool empty() const { return size() == 0; }
    bool operator==(const Selection&) const = default;
};

// How a click or a box combines with what is selected (plain, shift, ctrl+shift, ctrl).
enum class SelectOp : uint8_t { Replace, Add, Toggle, Remove };

// Combines picked elements into the selection: indices in vertex or face mode, EdgeKeys (either
// order) in edge mode.
// Elements are taken as given (the picker returns valid ones); the lists stay sorted/unique.
void applyPick(Selection& selection, SelectOp op, std::span<const uint32_t> elements);
void applyPick(Selection& selection, SelectOp op, std::span<const EdgeKey> edges);

Selection selectAll(const Cage& cage, const Topology& topology, SelectionMode mode);
Selection invertSelection(const Selection& selection, const Cage& cage, const Topology& topology);
Selection growSelection(const Selection& selection, const Cage& cage, const Topology& topology);
Selection shrinkSelection(const Selection& selection, const Cage& cage, const Topology& topology);
Selection convertSelection(const Selection& selection, SelectionMode mode, const Cage& cage, const Topology& topology);

// The vertices a transform of the selection moves (sorted): the selected vertices, the ends of
// the selected edges, the corners of the selected faces.
std::vector<uint32_t> selectedVertices(const Selection& selection, const Cage& cage);

// The selection carried across a topology edit: elements that still exist (faces and vertices
// through the edit's maps, edges whose both ends survive and which are still edges) keep being
// selected. (edit.resultVertices/resultEdges/resultFaces say what an operation suggests
// selecting instead.) `topology` is buildTopology(edit.cage).
Selection remapSelection(const Selection& selection, const TopologyEdit& edit, const Topology& topology);

}  // namespace qp
