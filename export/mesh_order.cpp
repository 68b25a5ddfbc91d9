#include "mesh_order.h"

#include <meshoptimizer.h>

namespace qp {

namespace {

template <class T>
void remapVertices(std::vector<T>& values, const std::vector<unsigned>& remap, size_t vertexCount) {
    std::vector<T> out(vertexCount);
    meshopt_remapVertexBuffer(out.data(), values.data(), values.size(), sizeof(T), remap.data());
    values = std::move(out);
}

}  // namespace

float averageCacheMissRatio(std::span<const uint32_t> indices, uint32_t vertexCount) {
    if (indices.empty()) return 0.0f;
    return meshopt_analyzeVertexCache(indices.data(), indices.size(), vertexCount, kCacheSize, 0, 0).acmr;
}

OrderReport optimizeMeshOrder(LimitMesh& mesh) {
    OrderReport report;
    report.acmrBefore = averageCacheMissRatio(mesh.indices, mesh.vertexCount());
    if (mesh.indices.empty()) return report;
    std::vector<uint32_t> ordered(mesh.indices.size());
    meshopt_optimizeVertexCache(ordered.data(), mesh.indices.data(), mesh.indices.size(), mesh.vertexCount());
    std::vector<unsigned> remap(mesh.vertexCount());
    const size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), ordered.data(), ordered.size(), mesh.vertexCount());
    meshopt_remapIndexBuffer(mesh.indices.data(), ordered.data(), ordered.size(), remap.data());
    remapVertices(mesh.positions, remap, used);
    remapVertices(mesh.normals, remap, used);
    remapVertices(mesh.subfaces, remap, used);
    remapVertices(mesh.parameters, remap, used);
    if (!mesh.uvs.empty()) remapVertices(mesh.uvs, remap, used);
    report.acmrAfter = averageCacheMissRatio(mesh.indices, mesh.vertexCount());
    return report;
}

}  // namespace qp
