// GridDrawing: the CPU grid path of a scheme, packaged. In update() the scheme's own evaluate()
// runs on a uniform grid over every sub-face (all cores, scheme_support.h), the triangles are
// uploaded, and record() draws them with MeshPass. What the picture shows is exactly what the
// comparison measures. On lavapipe this is often the fastest way to draw (docs/schemes.md).
#pragma once

#include <cstdint>

#include "mesh_pass.h"
#include "scheme_api.h"
#include "scheme_support.h"

namespace qp {

struct GridDrawing {
    SubfaceGrid grid;
    const VulkanContext* context = nullptr;
    MeshPass pass;
    GpuMesh mesh;
};

// The grid for `factor` segments per quad sub-face edge (build time; no device needed).
void prepareGridDrawing(GridDrawing& drawing, const PlannedCage& planned, uint32_t factor);
Status createGridDrawing(GridDrawing& drawing, const GpuContext& gpu);
// Evaluates `scheme` on the grid and uploads the triangles (no-op before createGridDrawing).
Status updateGridDrawing(GridDrawing& drawing, const Scheme& scheme);
// Clears target.area and draws; `patches` is what the scheme reports as drawn.
DrawStats recordGridDrawing(VkCommandBuffer cmd, const GridDrawing& drawing, const RenderTarget& target,
                            const DrawView& view, uint64_t patches);
uint64_t gridDrawingBytes(const GridDrawing& drawing);
void destroyGridDrawing(GridDrawing& drawing);

}  // namespace qp
