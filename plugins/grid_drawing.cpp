#include "grid_drawing.h"

#include <vector>

namespace qp {

void prepareGridDrawing(GridDrawing& drawing, const PlannedCage& planned, uint32_t factor) {
    drawing.grid = buildSubfaceGrid(planned, factor);
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
                            const DrawView& view, uint64_t patches) {
    const GpuMesh& mesh = drawing.displacement ? drawing.displaced.gpu : drawing.mesh;
    MeshDraw draw{&mesh, glm::vec3(0.8f), true, view.wireframe};
    recordMeshPass(cmd, drawing.pass, target, MeshView{view.viewProjection, view.eye, view.background, view.shading, view.clear},
                   mesh.indexCount ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
    return DrawStats{patches, mesh.indexCount / 3, DrawnBy::CpuMesh};
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
