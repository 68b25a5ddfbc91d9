// Culling (DrawView::cull, docs/culling.md) for the schemes that draw patches of their own (acc1,
// acc2, pn, osd-fas) and for uniform: the shared bookkeeping around core/culling/patch_cull_set.h.
//
// A scheme describes its patches by their culling leaves (PatchBounds) and which sub-faces each
// covers (PatchCover). Drawn one primitive per patch (the tessellator), a patch is culled by its
// own entry; drawn as triangles over sub-face grids (the CPU grid, a displaced mesh), a sub-face
// is culled by one entry made of the leaves of every patch that covers part of it (its grid's
// triangles join points of those patches, so they lie in the union of their boxes).
//
// Outlines: the tests judge the limit surface (or, for uniform, each flat triangle), the
// rasteriser draws triangles. Where a culled back-facing patch meets a drawn one, the unculled
// frame could still show one of its pixels at the outline: through the sliver a non-watertight
// seam leaves (each patch or sub-face evaluated on its own, the two sides of an edge differ in
// the last bits and snap to different sub-pixel points: osd-fas on catmark_cubes_infsharp, 1 to
// 3 pixels in 16 views), where a patch that ncone or pplane judged away by a hair had a triangle
// in front (osd-fas on the same cubes), and where a back-facing triangle won the depth test along
// the edge it shares with a front-facing one at a fold (uniform, watertight, on
// catmark_toroidal_tet; acc2 on catmark_righthanded showed a back patch through a crack of the
// front one beside it). So a back-facing entry is culled only when none of its neighbours (the
// entries sharing a point with it, PatchCulling's) is drawn: the culled back lies a patch away
// from every outline. On coarse cages this keeps most of the back drawn.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "culling/patch_cull_set.h"
#include "displaced_drawing.h"
#include "mesh_pass.h"
#include "plans/quad_patch_source.h"
#include "scheme_api.h"

namespace qp {

// Which entries touch which (share a point), both ways: entry e's are items[first[e] .. first[e + 1]).
struct CullAdjacency {
    std::vector<uint32_t> first{0};
    std::vector<uint32_t> items;
};
// Entries that share a point are neighbours (`groups[k]`: the entries at point k).
CullAdjacency adjacencyOfGroups(uint32_t entries, const std::vector<std::vector<uint32_t>>& groups);
// Per cage vertex the faces around it (groups for adjacencyOfGroups when entries are faces).
std::vector<std::vector<uint32_t>> facesAroundVertices(const PlannedCage& planned);
// Sub-faces of faces that share a vertex.
CullAdjacency subfaceAdjacency(const PlannedCage& planned);
// Outlines (above): of `culled` (sorted, what cullPatches gave for `view`), the entries outside
// the frustum and the back-facing ones none of whose `neighbours` is drawn; the others are drawn
// after all (and leave stats.cull.backFacing). No-op without neighbours.
std::vector<uint32_t> keepBesideDrawn(std::vector<uint32_t> culled, const CullAdjacency& neighbours, const PatchCullSet& set,
                                      const DrawView& view, DrawStats& stats);

// Which sub-faces each patch covers part of, both ways.
struct PatchCover {
    std::vector<uint32_t> first{0};  // per sub-face: its patches are patches[first[s] .. first[s + 1])
    std::vector<uint32_t> patches;
    std::vector<uint32_t> subfacesOfPatch;  // per patch: how many sub-faces it covers
};
// From (sub-face, patch) pairs, in any order, repeats allowed.
PatchCover patchCover(uint32_t subfaceCount, uint32_t patchCount, std::vector<std::pair<uint32_t, uint32_t>> pairs);
// acc1, acc2: one patch per quad of source.quads that has one (facePatch); a sub-face of the
// original cage covers the quads its 4 x 4 cell centres land on (locateOnQuads: 1 quad, or 4
// once a quad was refined; never more than 16 after two steps).
PatchCover quadPatchCover(const QuadPatchSource& source, uint32_t patchCount);
// Their patches' neighbours: the patches of quads that share a vertex.
CullAdjacency quadPatchAdjacency(const QuadPatchSource& source, uint32_t patchCount);

// A scheme's patches as culling leaves: `anchor(p)`, a point near patch p, becomes the origin of
// the entries it starts; `addLeaves(p, origin, leaves)` adds its leaves relative to `origin`.
struct PatchBounds {
    uint32_t count = 0;
    std::function<glm::vec3(uint32_t)> anchor;
    std::function<void(uint32_t, const glm::vec3&, PatchCullLeaves&)> addLeaves;
};
PatchCullSet patchCullSet(const PatchBounds& patches);  // one entry per patch
// One entry per sub-face: the leaves of the patches covering it (absent: none covers it).
PatchCullSet subfaceCullSet(const PatchBounds& patches, const PatchCover& cover);

// The sub-faces whose every patch is in `culledPatches` (sorted), sorted.
std::vector<uint32_t> whollyCulledSubfaces(const PatchCover& cover, std::span<const uint32_t> culledPatches);
// How many patches have every sub-face they cover in `culledSubfaces` (sorted).
uint64_t patchesWhollyCulled(const PatchCover& cover, std::span<const uint32_t> culledSubfaces);

// Per sub-face the largest |D| of its tile: a displaced point s + D N (|N| = 1, D a convex
// combination of the tile's padded coefficients) lies within it of the undisplaced surface.
std::vector<float> displacementMargins(const Displacement& displacement);

// What a scheme keeps for culling: its cover, whether back-patch tests apply, and the bounds,
// built when a frame first needs them and kept until positions or the displacement change
// (the scheme resets `bounds` then).
struct PatchCulling {
    PatchCover cover;
    bool closed = false;  // closedOutwardSurface of the cage
    // Outlines (above): per patch, per sub-face, its neighbours.
    CullAdjacency patchNeighbours, subfaceNeighbours;
    std::optional<PatchCullSet> bounds;
    bool perSubface = false;     // what `bounds` holds entries of
    std::vector<float> margins;  // per sub-face entry, when displaced
};
// The patches `view` culls (sorted; none without DrawView::cull), from one entry per patch; the
// counts into stats.cull and the time (building the bounds included) into
// stats.cullMilliseconds; *view.culledSubfacesOut (when set) gets the sub-faces wholly culled,
// *view.culledPatchesOut the culled patches.
std::vector<uint32_t> cullPatchesForView(PatchCulling& culling, const PatchBounds& patches, const DrawView& view,
                                         DrawStats& stats);
// The same per sub-face (the grid paths), boxes grown by `displacement`'s margins when it is set
// (then only the frustum culls); stats.patches becomes the patches minus those wholly culled.
std::vector<uint32_t> cullSubfacesForView(PatchCulling& culling, const PatchBounds& patches,
                                          const Displacement* displacement, const DrawView& view, DrawStats& stats);

// The index ranges that draw every part but the culled ones: part k owns the indices
// [firstIndex[k], firstIndex[k + 1]); `culled` (sorted) names parts. Neighbouring kept parts
// make one range.
std::vector<IndexRange> keptIndexRanges(std::span<const uint32_t> firstIndex, std::span<const uint32_t> culled);
// The same for a displaced mesh's grids, leaving out the sub-faces `culledSubfaces` (sorted).
std::vector<IndexRange> displacedKeptRanges(const DisplacedDrawing& drawing, std::span<const uint32_t> culledSubfaces);
// Clears target.area and draws `mesh` with MeshPass: all of it when `parts` is null, else those
// ranges; stats.triangles and stats.drawnBy say what was drawn.
void recordMeshParts(VkCommandBuffer cmd, const MeshPass& pass, const RenderTarget& target, const DrawView& view,
                     const GpuMesh& mesh, const std::vector<IndexRange>* parts, DrawStats& stats);
// recordMeshParts of a displaced mesh, all but the sub-faces `culledSubfaces` (sorted).
void recordDisplacedParts(VkCommandBuffer cmd, const MeshPass& pass, const RenderTarget& target, const DrawView& view,
                          const DisplacedDrawing& drawing, std::span<const uint32_t> culledSubfaces, DrawStats& stats);

}  // namespace qp
