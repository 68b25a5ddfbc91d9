#include "grid_drawing.h"

#include <algorithm>
#include <vector>

#include "scheme_culling.h"

namespace qp {

void prepareGridDrawing(GridDrawing& drawing, const PlannedCage& planned, uint32_t factor) {
    drawing.grid = buildSubfaceGrid(planned, factor);
    drawing.gridFirstIndex.assign(1, 0);
    for (uint32_t subface : drawing.grid.subfaces) {  // 6 n^2 indices each
        const uint32_t n = subfaceGridFactor(planned, subface, factor);
        drawing.gridFirstIndex.push_back(drawing.gridFirstIndex.back() + 6 * n * n);
    }
    drawing.planned = &planned;
    drawing.factor = factor;
}

Status createGridDrawing(GridDrawing& drawing, const GpuContext& gpu) {
    if (Status pass = createSchemeMeshPass(drawing.pass, gpu); !pass) return pass;
    drawing.context = gpu.vulkan;
    return success();
}

Status setGridDisplacement(GridDrawing& drawing, const Displacement* displacement) {
    drawing.displacement = displacementToDraw(displacement);
    return success();
}

Status updateGridDrawing(GridDrawing& drawing, const Scheme& scheme) {
    if (!drawing.context || drawing.grid.samples.empty()) return success();
    if (drawing.displacement) {
        if (Status cleared = replaceMesh(*drawing.context, drawing.mesh, {}, {}); !cleared) return cleared;  // drawn instead
        return buildDisplacedDrawing(drawing.displaced, *drawing.context, scheme, *drawing.planned, *drawing.displacement,
                                     displacedGridFactor(*drawing.planned, *drawing.displacement, drawing.factor));
    }
    destroyDisplacedDrawing(drawing.displaced);
    std::vector<SurfacePoint> points(drawing.grid.samples.size());
    evaluateParallel(scheme, drawing.grid.samples, points);
    return replaceMesh(*drawing.context, drawing.mesh, meshVertices(points), drawing.grid.indices);
}

Status gridDisplacementChanged(GridDrawing& drawing, std::span<const uint32_t> samples) {
    return updateDisplacedDrawing(drawing.displaced, samples);
}

DrawStats recordGridDrawing(VkCommandBuffer cmd, const GridDrawing& drawing, const RenderTarget& target,
                            const DrawView& view, DrawStats stats, std::span<const uint32_t> culledSubfaces) {
    if (drawing.displacement) {
        recordDisplacedParts(cmd, drawing.pass, target, view, drawing.displaced, culledSubfaces, stats);
        return stats;
    }
    std::vector<IndexRange> parts;
    if (!culledSubfaces.empty()) {
        std::vector<uint32_t> culledGrids;  // positions in grid.subfaces (both ascending)
        const std::vector<uint32_t>& gridded = drawing.grid.subfaces;
        for (uint32_t s : culledSubfaces) {
            const auto at = std::lower_bound(gridded.begin(), gridded.end(), s);
            if (at != gridded.end() && *at == s) culledGrids.push_back(uint32_t(at - gridded.begin()));
        }
        parts = keptIndexRanges(drawing.gridFirstIndex, culledGrids);
    }
    recordMeshParts(cmd, drawing.pass, target, view, drawing.mesh, culledSubfaces.empty() ? nullptr : &parts, stats);
    return stats;
}

uint64_t gridDrawingBytes(const GridDrawing& drawing) {
    return drawing.mesh.vertices.size + drawing.mesh.indices.size + drawing.displaced.gpu.vertices.size +
           drawing.displaced.gpu.indices.size;
}

void destroyGridDrawing(GridDrawing& drawing) {
    if (!drawing.context) return;
    if (drawing.mesh.indexCount) destroyMesh(*drawing.context, drawing.mesh);
    destroyDisplacedDrawing(drawing.displaced);
    destroyMeshPass(*drawing.context, drawing.pass);
    drawing.context = nullptr;
}

}  // namespace qp
