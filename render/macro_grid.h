// MacroGrid: the grid paths' macro faces (core/plans/macro_faces.h) in drawn sub-faces, and how a
// far-away block of faces is drawn with fewer than two triangles a face (Brainerd et al. 2016
// §7.3, §9.4: per-face tessellation factors below 1).
//
// Only the drawing changes. Every member keeps its own grid slots (grid_layout.h: evaluated and
// owned as before); a coarse macro face draws one Nu x Nv grid over its W x H faces whose
// vertices are its members' slots (the slots that evaluate them, so neighbours share vertices),
// and its members draw nothing. Far away that is fewer triangles than faces.
//
// Watertightness. A macro face is eligible when every member has one grid factor n with each of
// its edges in n pieces, and none is hidden or a hole; lengths are then counted in pieces of 1/n
// of a cage edge. Each side is cut into spans (MacroSpan: the stretches with one neighbour
// across). A span shared by two eligible macro faces takes P pieces, a divisor of its length,
// from its screen size (or the uniform request), the same number from both (one span id); any
// other span keeps every piece, as the single faces across it draw. A side's vertices are its
// spans' (start + k length / P). The macro face's grid has a column at every vertex of its bottom
// and top sides and a row at every vertex of its left and right ones; a boundary row snaps the
// columns that are not its own side's vertices to the nearest one (degenerate triangles, no
// T-junction). Both faces of a span therefore draw the same vertices along it, bit for bit, and a
// stretch of single faces on one side costs columns there only.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "plans/macro_faces.h"
#include "plans/planned_cage.h"

namespace qp {

struct GpuPlanData;
struct GridFactors;
struct AdaptiveView;

// Which partition a cage's macro faces come from (core/plans/macro_faces.h): Auto keeps rectangles or
// aligned blocks, whichever saves more quads when every macro face is drawn as one (faces in
// macro faces minus macro faces; quartets, the paper's blocks of two, only when asked for); Off
// has none.
enum class MacroChoice : uint8_t { Auto, Rectangles, Quartets, Blocks, Off };

struct MacroGridFace {
    uint32_t width, height, firstCell;
    uint32_t head;          // the member with the lowest drawn index: its index range holds the macro face's
    uint32_t spanBegin[5];  // MacroFace::spanBegin
};

// Where a span id is first met, and the macro face that shares it (UINT32_MAX: none).
struct MacroSpanUse {
    uint32_t macro, side, span, other;
};

struct MacroGrid {
    MacroChoice choice = MacroChoice::Auto;  // kept when the grid is built again
    // The sub-faces were renumbered (a topology edit) since it was built: it is empty until the
    // first frame that can draw macro faces builds it again (preparePlanFrame), so an edit does
    // not pay a pass over the whole cage for frames that never draw a macro face.
    bool stale = false;
    std::vector<MacroGridFace> faces;
    std::vector<uint32_t> cellDrawn;     // per cell: the drawn sub-face
    std::vector<uint8_t> cellRotation;   // per cell: MacroCell::rotation
    std::vector<MacroSpan> spans;
    std::vector<uint8_t> spanShared;     // per span id
    std::vector<MacroSpanUse> spanUses;  // per span id
    std::vector<uint32_t> macroOfDrawn;  // per drawn sub-face: its macro face, or UINT32_MAX

    uint32_t spanCount() const { return uint32_t(spanShared.size()); }
};

// data.macros built again for its choice, in the drawn numbering of `data` (its sub-face tables;
// non-quads have no macro faces: their sub-faces are drawn alone): uploadPlans, and the first
// frame after a repack that renumbered sub-faces.
void rebuildMacroGrid(const PlannedCage& planned, GpuPlanData& data);
// After a repack that renumbered sub-faces: data.macros emptied and marked stale (choice kept).
void markMacroGridStale(GpuPlanData& data);
const char* macroChoiceName(MacroChoice choice);  // "auto", "rectangles", "quartets", "blocks", "off"

// Chooses factors.macroSpanPieces and factors.macroResolution (left empty when no macro face is
// coarse) for factors already complete otherwise. Adaptive with `view` (a span cut for its
// polyline's screen length, as segments are; with `previous`, a span keeps its pieces while they
// are enough and not 2.5 times too many), else uniform per-face factor n / `minify`. `blocked`:
// drawn sub-faces (sorted) that are hidden or holes. Only eligible macro faces with a span below
// its length are drawn as macro faces, or every eligible one with `whole`.
void chooseMacroPieces(const GpuPlanData& data, GridFactors& factors, std::span<const glm::vec4> pointPositions,
                       const AdaptiveView* view, uint32_t minify, std::span<const uint32_t> blocked,
                       const GridFactors* previous = nullptr, bool whole = false);

// Nu, Nv of macro face m (0: drawn as single faces).
uint32_t macroColumns(const GridFactors& factors, uint32_t m);
uint32_t macroRows(const GridFactors& factors, uint32_t m);

// Writes the 6 Nu Nv indices of coarse macro face m: triangles over its members' grid slots,
// through `source` (grid_layout.h) to the slots that evaluate them.
void writeMacroIndices(const MacroGrid& grid, uint32_t m, const GridFactors& factors,
                       std::span<const uint32_t> subfaceOffset, std::span<const uint32_t> source, uint32_t* out);

// Culled drawn sub-faces (sorted) as a draw may skip them: a coarse macro face's head only when
// every member is culled (its triangles cover them all).
std::vector<uint32_t> culledForDrawing(const MacroGrid& grid, const GridFactors& factors, std::span<const uint32_t> culled);

}  // namespace qp
