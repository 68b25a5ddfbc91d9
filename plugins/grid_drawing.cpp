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

void setGridDisplacement(GridDrawing& drawing, const Displacement* displacement) {
    drawing.displacement = displacement && !displacement->empty() ? displacement : nullptr;
}

Status updateGridDrawing(GridDrawing& drawing, const Scheme& scheme) {
    if (!drawing.context || drawing.grid.samples.empty()) return success();
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> displacedIndices;
    if (drawing.displacement) {
        Result<SchemeMesh> displaced = displacedSchemeMesh(
            scheme, *drawing.planned, *drawing.displacement, displacedGridFactor(*drawing.planned, *drawing.displacement, drawing.factor));
        if (!displaced) return displaced.error();
        vertices = std::move(displaced->vertices);
        displacedIndices = std::move(displaced->indices);
    } else {
        std::vector<SurfacePoint> points(drawing.grid.samples.size());
        evaluateParallel(scheme, drawing.grid.samples, points);
        vertices = meshVertices(points);
    }
    if (drawing.mesh.indexCount) destroyMesh(*drawing.context, drawing.mesh);
    drawing.mesh = GpuMesh{};
    Result<GpuMesh> mesh = uploadMesh(*drawing.context, vertices, drawing.displacement ? displacedIndices : drawing.grid.indices);
    if (!mesh) return mesh.error();
    drawing.mesh = *mesh;
    return success();
}

DrawStats recordGridDrawing(VkCommandBuffer cmd, const GridDrawing& drawing, const RenderTarget& target,
                            const DrawView& view, uint64_t patches) {
    MeshDraw draw{&drawing.mesh, glm::vec3(0.8f), true, view.wireframe};
    recordMeshPass(cmd, drawing.pass, target, MeshView{view.viewProjection, view.eye, view.background},
                   drawing.mesh.indexCount ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
    return DrawStats{patches, drawing.mesh.indexCount / 3};
}

uint64_t gridDrawingBytes(const GridDrawing& drawing) { return drawing.mesh.vertices.size + drawing.mesh.indices.size; }

void destroyGridDrawing(GridDrawing& drawing) {
    if (!drawing.context) return;
    if (drawing.mesh.indexCount) destroyMesh(*drawing.context, drawing.mesh);
    destroyMeshPass(*drawing.context, drawing.pass);
    drawing.context = nullptr;
}

}  // namespace qp
