#include "displaced_drawing.h"

#include "scheme_support.h"

namespace qp {

Status buildDisplacedDrawing(DisplacedDrawing& drawing, const VulkanContext& context, const Scheme& scheme,
                             const PlannedCage& planned, const Displacement& displacement, uint32_t factor) {
    Result<DisplacedMesh> mesh = displacedSchemeMesh(scheme, planned, displacement, factor);
    if (!mesh) return mesh.error();
    destroyDisplacedDrawing(drawing);
    drawing.mesh = std::move(mesh).value();
    drawing.users = buildDisplacementUsers(displacement.layout);
    drawing.gridOfSubface.assign(planned.subfaceCount(), UINT32_MAX);
    for (uint32_t g = 0; g < drawing.mesh.gridSubface.size(); ++g) drawing.gridOfSubface[drawing.mesh.gridSubface[g]] = g;
    const std::vector<MeshVertex> vertices = meshVertices(drawing.mesh.positions, drawing.mesh.normals);
    if (vertices.empty()) return success();
    Result<GpuMesh> gpu = uploadMesh(context, vertices, drawing.mesh.indices);
    if (!gpu) return gpu.error();
    drawing.gpu = *gpu;
    drawing.context = &context;
    drawing.displacement = &displacement;
    return success();
}

Status updateDisplacedDrawing(DisplacedDrawing& drawing, std::span<const uint32_t> samples) {
    if (!drawing.context) return success();
    const Displacement& displacement = *drawing.displacement;
    std::vector<uint32_t> grids;
    for (uint32_t s : subfacesReadingSamples(displacement.layout, drawing.users, samples))
        if (drawing.gridOfSubface[s] != UINT32_MAX) grids.push_back(drawing.gridOfSubface[s]);
    redisplaceGrids(drawing.mesh, displacement, grids);
    const DisplacedMesh& m = drawing.mesh;
    std::vector<MeshVertex> vertices;
    for (uint32_t g : grids) {
        const uint32_t first = m.gridOffset[g], count = (m.gridFactor[g] + 1) * (m.gridFactor[g] + 1);
        vertices.resize(count);
        for (uint32_t k = 0; k < count; ++k) vertices[k] = {m.positions[first + k], m.normals[first + k]};
        uploadBuffer(drawing.gpu.vertices, vertices.data(), count * sizeof(MeshVertex), size_t(first) * sizeof(MeshVertex));
    }
    return success();
}

void destroyDisplacedDrawing(DisplacedDrawing& drawing) {
    if (drawing.context && drawing.gpu.indexCount) destroyMesh(*drawing.context, drawing.gpu);
    drawing.gpu = GpuMesh{};
    drawing.context = nullptr;
    drawing.displacement = nullptr;
}

}  // namespace qp
