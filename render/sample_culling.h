// Sample culling: the CPU grid's triangles (DrawPath::CpuGrid) that cover no pixel centre of the
// viewport are left out of the draw.
//
// Why. A triangle that covers no sample makes no fragment, so leaving it out changes no pixel,
// but lavapipe pays for it all the same: its vertex shading, clipping and triangle setup run on
// one thread before the rasteriser finds it empty. Seen whole, a million-face cage at 4 px a
// segment draws 1.67 M triangles into 800 x 600 pixels and about 89% of them cover no pixel
// centre (docs/renderer.md has the measurements). Hardware does the same (small-primitive
// culling); here the host has the vertices already, so it tests them itself.
//
// Conservative. A triangle is kept when a pixel centre lies inside it or within kSampleMargin px
// of it (the device snaps vertices to 1/256 px and computes the projection in its own float
// order: both move a vertex by far less), when its winding cannot be told (area under
// kTinyArea square pixels), when a vertex is behind the eye, outside the depth range or not
// finite (the clipper's business), or when it spans more than a few pixel centres. Left out are
// triangles none of whose pixel centres in the viewport is near, and triangles with two corners
// at bit-identical positions (zero area in any projection: the device's coordinates are equal
// too). Single-sampled targets only (the renderer's).
//
// Incremental. The triangles are tested in chunks of kChunkTriangles consecutive triangles of
// the layout's index buffer (about 100 chunks at a million faces, drawn as that many ranges);
// each chunk's kept triangles are written at the chunk's own place in the culled index buffer,
// so a chunk is tested again alone. A test result is kept per triangle, drawn or not, so a chunk
// can also be written again without testing it. Everything is tested again when the view or
// the viewport changes, or the triangles change in a way not carried (below); after a vertex
// move or a displacement dab only the chunks that read a changed slot are tested, and after
// faces are hidden or shown (a hole made or filled) the chunks whose drawn triangles changed
// are written again from their results.
//
// Carried through a relayout (carrySampleCulling): a topology or hole edit renumbers the drawn
// sub-faces and shifts their slots and triangles (grid_relayout.h carryGrid). A kept sub-face's
// triangles are its old ones over its moved slots, whose values moved with them: their results
// follow them, and only the triangles of sub-faces laid out anew are tested (their slots count
// as changed). Every chunk is then written again (its triangles moved), which reads the results
// and the indices but projects nothing.
//
// Facing away (SampleView::backFacesHidden). On a closed surface whose normals point outward,
// seen from outside with the near plane clear of it (the scheme's back-patch culling decides:
// docs/culling.md), a triangle facing away from the eye is behind a facing one: the grid's
// triangles make a closed mesh (shared edges bit for bit, grid_layout.h), so the ray from the eye
// to a point of it entered the solid before, through a facing triangle nearer the eye. Such a
// triangle is left out unless one of its corners is a corner of a triangle that does not face
// away (by the evaluated slot it shows, across sub-faces): along the outline the two sheets meet
// at depths the depth test may not tell apart, so the ring of facing-away triangles there stays.
// Facing is decided in double precision with a margin (kFacingMargin); edge-on triangles count
// as facing. A triangle's result then depends on its neighbours', so any change tests everything
// (the drawn triangles only; facing first, so those left out look for no pixel centre).
//
// When. The renderer (plan_pass.h, recordGrid) uses it for CPU grids denser than
// kMinTrianglesPerPixel and without a displacement, where it pays (docs/renderer.md), and for
// every CPU grid whose back faces are hidden (coarser ones then test facing only).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "grid_layout.h"

namespace qp {

// The viewport in framebuffer pixels (VkViewport x, y, width, height; depth 0..1) and the
// transform to clip space.
struct SampleView {
    glm::mat4 viewProjection{1.0f};
    int32_t x = 0, y = 0;
    uint32_t width = 0, height = 0;
    // False: pixel centres are not looked for (a grid too coarse for that to pay, culled for
    // facing away only); triangles with two corners at one position still go.
    bool testPixelCentres = true;
    // Triangles facing away from `eye` (object space, homogeneous: w = 0 for an orthographic
    // view's direction toward the viewer; core/culling/patch_cull_set.h homogeneousEye) may be
    // left out (above). Only when the surface is closed, outward, seen from outside and the near
    // plane clear of it.
    bool backFacesHidden = false;
    glm::vec4 eye{0.0f};
    bool operator==(const SampleView&) const = default;
};

inline constexpr float kSampleMargin = 1.0f / 32.0f;  // pixels
inline constexpr float kTinyArea = 1e-3f;             // square pixels (twice the triangle's area)
inline constexpr uint32_t kChunkTriangles = 16384;    // SampleCulling::chunkTriangles unless set
// Below one triangle a pixel most triangles cover a centre and testing them costs what it saves
// or more (docs/renderer.md: the editor's frames on a 20k cage were 10-20% slower with it), so
// the renderer tests only grids with more triangles than the viewport has pixels.
inline constexpr float kMinTrianglesPerPixel = 1.0f;
inline constexpr size_t kMostChangedRanges = 65536;  // changed slot ranges kept before testing everything again
// A triangle faces away when the cosine between its normal and the direction to the eye is below
// minus this (computed in double: exact enough that the margin only keeps edge-on triangles).
inline constexpr double kFacingMargin = 1e-4;

// Whether the triangle a, b, c (object space, counter-clockwise seen from outside) faces away from
// `eye` (SampleView::eye) by more than kFacingMargin.
bool facesAwayFrom(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec4& eye);

// Whether the triangle a, b, c (object space) may cover a pixel centre of `view` (see above).
bool mayCoverPixelCentre(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const SampleView& view);

struct SampleCulling {
    uint32_t chunkTriangles = kChunkTriangles;  // set before the first update (tests use small chunks)
    // Used only while the grid has more triangles than this times the viewport's pixels (see
    // kMinTrianglesPerPixel).
    float minTrianglesPerPixel = kMinTrianglesPerPixel;
    // What the kept triangles were chosen for (valid: every chunk is up to date for them).
    bool valid = false;
    SampleView view;
    std::vector<std::pair<uint32_t, uint32_t>> drawnRanges;  // (first index, count); empty: every index
    // Per chunk: triangles kept (written from index 3 * chunkTriangles * chunk on), and the
    // lowest and highest slot its triangles read (a changed slot outside cannot concern it).
    std::vector<uint32_t> chunkKept, chunkSlotMin, chunkSlotMax;
    std::vector<uint32_t> chunkFacingAway;  // per chunk: drawn triangles left out as facing away
    // Per triangle of the layout, drawn or not: kCovers when it is drawn for `view`, else why not.
    std::vector<uint8_t> triangleResult;
    static constexpr uint8_t kCoversNothing = 0, kCovers = 1, kHiddenFacingAway = 2;
    // Slot ranges [first, end) written since the chunks were tested.
    std::vector<std::pair<uint32_t, uint32_t>> changedSlots;
    bool rewriteAll = false;  // the triangles moved (carried): every chunk is written again
    uint64_t keptTriangles = 0;    // of the drawn triangles
    uint64_t facingAwayTriangles = 0;  // of the drawn triangles: left out as facing away (the others covered nothing)
    uint64_t testedTriangles = 0;  // in this update, drawn or not
    bool inUse = false;                               // the last frame drew the culled triangles
};

// The layout's triangles or the whole grid changed: everything is tested again.
inline void invalidateSampleCulling(SampleCulling& culling) {
    culling.valid = false;
    culling.changedSlots.clear();
}

// The slots of the drawn sub-faces `drawn` were written (their vertices moved or were displaced).
void markSlotsChanged(SampleCulling& culling, const GridLayout& layout, std::span<const uint32_t> drawn);

// The grid was laid out anew from `before` to `after`, the slots of every kept sub-face moved
// with their values (`oldOf`: drawn index in `after` -> in `before`, UINT32_MAX for one laid out
// anew; grid_relayout.h carryGrid): the results follow the kept sub-faces' triangles, and the
// others' slots count as changed, as do those of sub-faces whose slots were written since the
// last update (`changedSlots`, in the old numbering). Reads `before`'s factors and offsets only
// (carryGrid has recycled its other tables). Tests everything again at the next update instead
// when the culling was not up to date, coarse macro faces are drawn on either side, or too many
// sub-faces are new.
void carrySampleCulling(SampleCulling& culling, const GridLayout& before, const GridLayout& after,
                        std::span<const uint32_t> oldOf);

// Brings the culled triangles up to date for `view`, drawing the index ranges `drawnRanges`
// (first index, count; empty: all) of `layout.indices` over `vertices` (the grid, one per slot).
// Writes the kept triangles into `culledIndices` (room for layout.indices.size()) chunk by chunk
// and returns the index ranges to draw from it.
std::vector<std::pair<uint32_t, uint32_t>> updateSampleCulling(SampleCulling& culling, const GridLayout& layout,
                                                               const GridVertex* vertices, const SampleView& view,
                                                               std::span<const std::pair<uint32_t, uint32_t>> drawnRanges,
                                                               uint32_t* culledIndices);

}  // namespace qp
