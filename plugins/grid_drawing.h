// GridDrawing: the CPU grid path of a scheme, packaged. In update() the scheme's own evaluate()
// runs on a uniform grid over every sub-face (all cores, scheme_support.h), the triangles are
// uploaded, and record() draws them with MeshPass. What the picture shows is exactly what the
// comparison measures. On lavapipe this is often the fastest way to draw (docs/schemes.md).
//
// Displacement (Scheme::setDisplacement): with one set, update() draws the scheme's own surface
// displaced along its own normal, watertight, on a grid of at least displacedGridFactor
// (displaced_drawing.h), and gridDisplacementChanged re-displaces only what a dab reached.
// Schemes with a tessellated path draw through this grid while displaced.
//
// Culling: record() leaves out the sub-faces the scheme culled (scheme_culling.h,
// cullSubfacesForView), drawing the index ranges of the others.
#pragma once

#include <cstdint>

#include "displaced_drawing.h"
#include "mesh_pass.h"
#include "scheme_api.h"
#include "scheme_support.h"

namespace qp {

struct GridDrawing {
    SubfaceGrid grid;
    std::vector<uint32_t> gridFirstIndex;  // per sub-face of `grid`, its first index; the total last
    const PlannedCage* planned = nullptr;
    uint32_t factor = 1;                          // requested segments per quad sub-face edge
    const Displacement* displacement = nullptr;  // non-empty, or none
    const VulkanContext* context = nullptr;
    MeshPass pass;
    GpuMesh mesh;                 // without displacement
    DisplacedDrawing displaced;   // with it
};

// The grid for `factor` segments per quad sub-face edge (build time; no device needed).
void prepareGridDrawing(GridDrawing& drawing, const PlannedCage& planned, uint32_t factor);
Status createGridDrawing(GridDrawing& drawing, const GpuContext& gpu);
// Scheme::setDisplacement's argument: drawn from the next updateGridDrawing on; nullptr or an
// empty one removes it.
Status setGridDisplacement(GridDrawing& drawing, const Displacement* displacement);
// Evaluates `scheme` on the grid (displaced, if set) and uploads the triangles (no-op before
// createGridDrawing).
Status updateGridDrawing(GridDrawing& drawing, const Scheme& scheme);
// Scheme::displacementChanged: brings the displaced mesh up to date around these samples.
Status gridDisplacementChanged(GridDrawing& drawing, std::span<const uint32_t> samples);
// Clears target.area and draws every sub-face but `culledSubfaces` (sorted). `stats` is what the
// scheme filled in (the patches it drew, its culling); the triangles are those drawn.
DrawStats recordGridDrawing(VkCommandBuffer cmd, const GridDrawing& drawing, const RenderTarget& target,
                            const DrawView& view, DrawStats stats, std::span<const uint32_t> culledSubfaces = {});
uint64_t gridDrawingBytes(const GridDrawing& drawing);
void destroyGridDrawing(GridDrawing& drawing);

}  // namespace qp
