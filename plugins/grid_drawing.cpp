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
    Result<MeshPass> pass = createMeshPass(*gpu.vulkan, gpu.cache, gpu.colorFormat, gpu.depthFormat);
    if (!pass) return pass.error();
    drawing.pass = *pass;
    drawing.context = gpu.vulkan;
    return success();
}

Status setGridDisplacement(GridDrawing& drawing, const Displacement* displacement) {
    drawing.displacement = displacement && !displacement->empty() ? displacement : nullptr;
    return success();
}

Status updateGridDrawing(GridDrawing& drawing, const Scheme& scheme) {
    if (!drawing.context || drawing.grid.samples.empty()) return success();
    if (drawing.mesh.indexCount) destroyMesh(*drawing.context, drawing.mesh);
    drawing.mesh = GpuMesh{};
    if (drawing.displacement)
        return buildDisplacedDrawing(drawing.displaced, *drawing.context, scheme, *drawing.planned, *drawing.displacement,
                                     displacedGridFactor(*drawing.planned, *drawing.displacement, drawing.factor));
    destroyDisplacedDrawing(drawing.displaced);
    std::vector<SurfacePoint> points(drawing.grid.samples.size());
    evaluateParallel(scheme, drawing.grid.samples, points);
    Result<GpuMesh> mesh = uploadMesh(*drawing.context, meshVertices(points), drawing.grid.indices);
    if (!mesh) return mesh.error();
    drawing.mesh = *mesh;
    return success();
}

Status gridDisplacementChanged(GridDrawing& drawing, std::span<const uint32_t> samples) {
    return updateDisplacedDrawing(drawing.displaced, samples);
}

DrawStats recordGridDrawing(VkCommandBuffer cmd, const GridDrawing& drawing, const RenderTarget& target,
                            const DrawView& view, DrawStats stats, std::span<const uint32_t> culledSubfaces) {
    const GpuMesh& mesh = drawing.displacement ? drawing.displaced.gpu : drawing.mesh;
    std::vector<IndexRange> parts;
    if (!culledSubfaces.empty() && drawing.displacement) {
        parts = displacedKeptRanges(drawing.displaced, culledSubfaces);
    } else if (!culledSubfaces.empty()) {
        std::vector<uint32_t> culledGrids;  // positions in grid.subfaces (both ascending)
        const std::vector<uint32_t>& gridded = drawing.grid.subfaces;
        for (uint32_t s : culledSubfaces) {
            const auto at = std::lower_bound(gridded.begin(), gridded.end(), s);
            if (at != gridded.end() && *at == s) culledGrids.push_back(uint32_t(at - gridded.begin()));
        }
        parts = keptIndexRanges(drawing.gridFirstIndex, culledGrids);
    }
    recordMeshParts(cmd, drawing.pass, target, view, mesh, culledSubfaces.empty() ? nullptr : &parts, stats);
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
