// Table-driven uniform Catmull-Clark refinement (Loop 2010 §3), the math behind `uniform`.
//
// Topology is refined once (OpenSubdiv's Far::TopologyRefiner gives each level's adjacency
// and the crease sharpness Sdc assigns to it); from it we build, per level, the subdivision
// tables of Loop 2010: a face table (offset, valence, old vertices), an edge table (two old
// vertices and two new face points each; a boundary edge lists its ends twice) and a vertex
// table. Applying them is three data-parallel kernels per level over one vertex buffer that
// holds every level, one output vertex per work item; only positions are touched when the
// cage's vertices move.
//
// Beyond Loop 2010's smooth, boundary and corner rules the tables carry OpenSubdiv's
// sharpness rules (Sdc, DeRose et al. 1998): an edge point blends smooth and sharp by the
// edge's sharpness when it is below 1; a vertex point uses the crease or corner mask while its
// edges are sharp and blends parent and child masks by Sdc's fractional weight where
// sharpness runs out. The vertex table therefore stores weights (a dense mask per vertex)
// instead of Loop's valence-driven kernel. Not reproduced: the "smooth triangle" option.
//
// The surface of the scheme at (sub-face, u, v) is the finest level's mesh, drawn as two
// triangles per quad (diagonal from the quad's vertex 0 to 2), linearly interpolated there.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <opensubdiv/far/topologyRefiner.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "mesh/result.h"
#include "plans/planned_cage.h"

namespace qp {

// Tables that produce level l + 1 from level l; indices address the shared vertex buffer.
struct RefinementLevelTables {
    std::vector<uint32_t> faceChild, faceOffsets, faceVertices;  // face points: averages
    std::vector<uint32_t> edgeChild;
    std::vector<uint32_t> edgePoints;   // 4 per edge: v0, v1, f0, f1 (boundary: v0, v1, v0, v1)
    std::vector<float> edgeSharpWeight; // 0 smooth, 1 sharp (midpoint), between: blend
    // Vertex points: masks. Each vertex has room for 1 + edges + faces terms (the most any rule
    // needs; unused terms weigh 0), so a tag edit rewrites a mask where it is.
    std::vector<uint32_t> vertexChild, vertexOffsets, vertexIndices;
    std::vector<float> vertexWeights;
};

// One quad of the finest level: its vertices (indices into the finest level) and where its
// corners sit in its sub-face's (u, v) domain.
struct RefinedQuad {
    uint32_t vertices[4];
    glm::vec2 domain[4];
    uint32_t subface;
};

struct UniformRefinement {
    uint32_t levels = 0;
    std::vector<uint32_t> levelOffset;  // first vertex of each level in the buffer; levels + 2 entries
    std::vector<RefinementLevelTables> tables;  // levels entries
    std::vector<RefinedQuad> quads;     // finest level, every sub-face's (holes' too)
    std::vector<uint32_t> drawnQuads;   // the quads of sub-faces with a surface (ascending)
    // The refined topology (its tags are those of build time; updateUniformTags keeps the
    // tables current): what a tag edit's local refinement is matched against.
    std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> refiner;
    // Per sub-face, the quads covering it as a (2^m)^2 grid, row-major over (u, v) cells:
    // subfaceCellBase[s] indexes cellQuad; subfaceSide[s] = 2^m (0 when the sub-face has none).
    std::vector<uint32_t> subfaceCellBase, subfaceSide, cellQuad;

    uint32_t finestVertexCount() const { return levelOffset[levels + 1] - levelOffset[levels]; }
};

// Refines `planned`'s cage `levels` times (1..8) and builds the tables.
Result<UniformRefinement> buildUniformRefinement(const PlannedCage& planned, uint32_t levels);

// After a tag edit (edge or vertex sharpness, holes, the crease method) re-planned `subfaces` of
// the same topology: the tables are rewritten where the edit reaches, from a uniform refinement
// of just the faces around the re-planned ones (their masks need nothing beyond those faces),
// matched to the refinement component by component; the drawn quads follow the holes. The
// result equals buildUniformRefinement of the edited cage up to the order of each mask's terms.
// Fails, changing nothing drawn, when the local refinement cannot be matched (non-manifold
// edges between the same two vertices): then build again.
Status updateUniformTags(UniformRefinement& refinement, const PlannedCage& planned, std::span<const uint32_t> subfaces);

// Runs the kernels: `buffer` gets every level's positions (resized to levelOffset.back()),
// starting from the cage's. Parallel over each table.
void applyUniformRefinement(const UniformRefinement& refinement, std::span<const glm::vec3> cagePositions,
                            std::vector<glm::vec3>& buffer);

// Area-weighted vertex normals of the finest level's drawable quads.
std::vector<glm::vec3> refinedNormals(const UniformRefinement& refinement, std::span<const glm::vec3> finest);

// The drawn (triangulated) mesh at (sub-face, u, v): position, interpolated normal, and the
// triangle's derivatives in the sub-face's frame. The sub-face must have quads.
struct RefinedSample {
    glm::vec3 position, normal, du, dv;
};
RefinedSample sampleRefined(const UniformRefinement& refinement, std::span<const glm::vec3> finest,
                            std::span<const glm::vec3> normals, uint32_t subface, float u, float v);

}  // namespace qp
