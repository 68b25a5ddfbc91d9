// GridLayout: where the grid paths (plan_pass.h) keep their evaluated vertices, and how shared
// edges stay watertight there.
//
// Factors. Every boundary segment (gpu_plans.h) is cut into `segmentPieces` pieces, the same
// number from both sides; a drawn sub-face's grid factor n is at least the pieces of each of
// its edges, and a multiple of them (a split cage edge counts twice its half's pieces). Uniform
// factors give every quad n = f and every n-gon sub-face n = f / 2 (f even when the cage has
// non-quads): the 2k / k rule. Adaptive factors cut each segment by its screen size, like the
// tessellated path's control stage but rounded up to powers of two, and give a sub-face the
// largest of its edges' pieces.
//
// Slots. Each drawn sub-face owns (n + 1)^2 consecutive vertex slots from `subfaceOffset`,
// row-major from its corner 0 (x along u, y along v), evaluated at (x / n, y / n). Along an
// edge cut into P < n pieces, slot i shows edge vertex round(i P / n): it snaps, leaving
// degenerate triangles rather than cracks.
//
// Watertightness by ownership. A vertex on a sub-face boundary belongs to the owner of its
// boundary point or segment (gpu_plans.h). `source[slot]` is the slot itself when the slot is
// evaluated (interior slots, the owner's boundary slots) and otherwise the owner's slot it is
// a copy of: evaluating is phase 1, copying phase 2, so every face around an edge draws the
// same bits, and the value of an evaluated slot depends on its own sub-face's control points
// only. That is what makes incremental updates exact (plan_pass.h, recordMovedVertices).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "gpu_plans.h"

namespace qp {

// One grid vertex (the grid buffer's element): limit position and unit normal (zero where the
// derivatives are degenerate).
struct GridVertex {
    float position[3];
    float normal[3];
};
static_assert(sizeof(GridVertex) == 24);

struct GridFactors {
    std::vector<uint32_t> segmentPieces;  // per GpuPlanData::segments
    std::vector<uint32_t> subfaceFactor;  // per drawn sub-face: n
    // Macro faces (GpuPlanData::macros, macro_grid.h chooseMacroPieces): pieces per span id, and
    // per macro face its grid's columns and rows (0, 0: drawn as single faces); empty when none is
    // drawn as one.
    std::vector<uint32_t> macroSpanPieces, macroResolution;

    bool operator==(const GridFactors&) const = default;
};

// The factor the grid actually uses for a uniform request: odd factors become even on cages
// with non-quads (their sub-faces take half of it).
uint32_t uniformGridFactor(const GpuPlanData& data, uint32_t factor);
GridFactors uniformGridFactors(const GpuPlanData& data, uint32_t factor);

// What adaptive factors depend on (the same quantities as shaders/plan_draw.glsl).
struct AdaptiveView {
    glm::mat4 viewProjection{1.0f};
    float pixelsPerUnit = 1.0f;      // plan_pass.h pixelsPerUnit()
    float pixelsPerSegment = 8.0f;   // target screen length of one segment
};

// Screen-adaptive factors from the boundary points' positions (boundaryPointPositions). With
// `previous` (the factors in use), a segment keeps its pieces (a power of two) while they are
// enough and not more than 2.5 times too many, so that small camera moves leave the grid as it is.
// Segments wholly behind the eye take one piece. A layout of more than kMaxAdaptiveGridSlots
// slots is chosen again with pixelsPerSegment raised by a power of two until it fits: a camera
// close to a dense cage asked for more than any screen shows (the faces beside it at factor 64:
// 100 M slots at a million faces, 2.3 GiB of grid, refused by the device), and such a layout is
// not worth its memory.
GridFactors adaptiveGridFactors(const GpuPlanData& data, std::span<const glm::vec4> pointPositions,
                                const AdaptiveView& view, const GridFactors* previous = nullptr);
inline constexpr uint64_t kMaxAdaptiveGridSlots = uint64_t(16) << 20;  // 384 MiB of GridVertex
// Slots of a layout of these factors (GridLayout::slotCount before laying it out).
uint64_t gridSlots(const GridFactors& factors);

// adaptiveGridFactors again for the drawn sub-faces `touched` only (sorted: every sub-face on an
// edge whose points moved, as the ring users of the moved vertices are), the rest as `factors`
// has them: the same as a full pass with `factors` as the previous ones, when only those points
// moved since `factors` were chosen for this view.
void updateAdaptiveGridFactors(const GpuPlanData& data, std::span<const glm::vec4> pointPositions, const AdaptiveView& view,
                               GridFactors& factors, std::span<const uint32_t> touched);

struct GridLayout {
    GridFactors factors;
    std::vector<uint32_t> subfaceOffset;  // first slot of each drawn sub-face, plus the total
    std::vector<uint32_t> source;         // per slot: itself (evaluated) or the slot it copies
    std::vector<uint32_t> slotSubface;    // per slot: its drawn sub-face
    // Triangles: 6 n^2 per sub-face over slots of its own block; a coarse macro face's (macro_grid.h)
    // in its head's range, over its members' corner slots, and its other members none.
    std::vector<uint32_t> indices;
    std::vector<uint32_t> indexOffset;    // first index of each drawn sub-face, plus the total
    // CSR: drawn sub-face -> the other drawn sub-faces that copy one of its slots.
    std::vector<uint32_t> dependentOffsets, dependents;
    uint32_t maxFactor = 0;
    // The uniform factor requested when these are uniformGridFactors (0: adaptive or displaced
    // factors): an update in place that adds sub-faces then knows what the next frame asks for.
    uint32_t uniformRequest = 0;

    uint32_t slotCount() const { return subfaceOffset.empty() ? 0 : subfaceOffset.back(); }
};

// `recycled`: a layout no longer needed whose arrays are reused (every entry is written again),
// so a relayout after each edit neither allocates nor clears the grid's tables.
GridLayout buildGridLayout(const GpuPlanData& data, GridFactors factors, GridLayout recycled = {});

// buildGridLayout's result, taking what it can from `before`, a layout of the tables before a
// change (a topology or hole edit that renumbered the drawn sub-faces, or factors changed for
// some): `oldOf` maps each drawn sub-face to its number in `before`, or UINT32_MAX where it is new
// or laid out otherwise; a mapped one must keep its factor and every edge's pieces. A mapped
// sub-face whose edges' and corners' owners are the same sub-faces as before (`ownersChanged[d]`
// false; empty: true of every one) and whose owners are all mapped copies from the same places
// as before, renumbered: a pass over its boundary slots instead of looking up each owner's place.
GridLayout carryGridLayout(const GpuPlanData& data, GridFactors factors, const GridLayout& before,
                           std::span<const uint32_t> oldOf, std::span<const char> ownersChanged = {},
                           GridLayout recycled = {});

// The triangles (indexOffset, indices) for layout.factors, the slots as they are: what a change
// of the macro faces alone (GridFactors::macroSpanPieces, macroResolution) lays out again.
void writeGridIndices(const GpuPlanData& data, GridLayout& layout);

// Drawn sub-faces whose slots mean something else under `after` than under `before`: their
// factor or the pieces of one of their edges changed (sorted).
std::vector<uint32_t> subfacesWithNewFactors(const GpuPlanData& data, const GridFactors& before, const GridFactors& after);

// (u, v) of a slot of drawn sub-face `drawn`, as both evaluators compute it.
inline void slotParameter(uint32_t local, uint32_t n, float& u, float& v) {
    u = float(local % (n + 1)) / float(n);
    v = float(local / (n + 1)) / float(n);
}

// Sorted, duplicate-free union of `drawn` and the sub-faces that copy slots from them.
std::vector<uint32_t> withDependents(const GridLayout& layout, std::span<const uint32_t> drawn);

}  // namespace qp
