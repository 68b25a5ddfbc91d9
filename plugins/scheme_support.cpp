#include "scheme_support.h"

#include <algorithm>
#include <chrono>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "displacement/displaced_mesh.h"

namespace qp {

uint32_t faceOfSubface(const PlannedCage& planned, uint32_t subface) {
    uint32_t lo = 0, hi = planned.cage().faceCount();  // the last face whose first sub-face <= subface
    while (hi - lo > 1) {
        const uint32_t mid = (lo + hi) / 2;
        (planned.firstSubface(mid) <= subface ? lo : hi) = mid;
    }
    return lo;
}

uint32_t subfaceGridFactor(const PlannedCage& planned, uint32_t subface, uint32_t factor) {
    const bool quad = planned.cage().faceSize(faceOfSubface(planned, subface)) == 4;
    return quad ? factor : std::max(1u, factor / 2);
}

SubfaceGrid buildSubfaceGrid(const PlannedCage& planned, uint32_t factor) {
    SubfaceGrid grid;
    grid.factor = factor;
    const Cage& cage = planned.cage();
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t count = subfaceCount(cage.faceSize(f));
        const uint32_t n = cage.faceSize(f) == 4 ? factor : std::max(1u, factor / 2);
        for (uint32_t k = 0; k < count; ++k) {
            const uint32_t subface = planned.firstSubface(f) + k;
            if (!planned.hasSurface(subface)) continue;
            const uint32_t base = uint32_t(grid.samples.size()), side = n + 1;
            grid.subfaces.push_back(subface);
            grid.firstSample.push_back(base);
            for (uint32_t y = 0; y <= n; ++y)
                for (uint32_t x = 0; x <= n; ++x)
                    grid.samples.push_back({subface, float(x) / float(n), float(y) / float(n)});
            for (uint32_t y = 0; y < n; ++y)
                for (uint32_t x = 0; x < n; ++x) {
                    const uint32_t a = base + y * side + x, b = a + 1, c = a + side + 1, d = a + side;
                    grid.indices.insert(grid.indices.end(), {a, b, c, a, c, d});
                }
        }
    }
    grid.firstSample.push_back(uint32_t(grid.samples.size()));
    return grid;
}

glm::vec3 normalOf(const glm::vec3& du, const glm::vec3& dv) {
    const glm::vec3 n = glm::cross(du, dv);
    const float length = glm::length(n);
    return length > 0.0f ? n / length : glm::vec3(0.0f);
}

SurfacePoint surfacePoint(const glm::vec3& position, const glm::vec3& du, const glm::vec3& dv) {
    return SurfacePoint{position, normalOf(du, dv), du, dv, true};
}

void evaluateParallel(const Scheme& scheme, std::span<const SampleRequest> requests, std::span<SurfacePoint> out) {
    constexpr size_t kChunk = 1024;
    const size_t chunks = (requests.size() + kChunk - 1) / kChunk;
    tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
        const size_t begin = c * kChunk, count = std::min(kChunk, requests.size() - begin);
        scheme.evaluate(requests.subspan(begin, count), out.subspan(begin, count));
    });
}

std::vector<uint32_t> cullForView(const PatchCullSet& set, bool closed, std::span<const float> margins,
                                  const DrawView& view, DrawStats& stats) {
    if (view.cull == CullMethod::None) return {};
    const auto start = std::chrono::steady_clock::now();
    // Hidden faces open the surface: what lies behind them shows its back side.
    const bool backPatch = closed && view.hiddenSubfaces.empty();
    std::vector<uint32_t> culled = cullPatches(set, view.cull, view.viewProjection,
                                               homogeneousEye(view.viewProjection, view.eye), backPatch, margins, &stats.cull);
    stats.cullMilliseconds += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return culled;
}

std::vector<MeshVertex> meshVertices(std::span<const SurfacePoint> points) {
    std::vector<MeshVertex> vertices(points.size());
    for (size_t i = 0; i < points.size(); ++i) vertices[i] = {points[i].position, points[i].normal};
    return vertices;
}

std::vector<MeshVertex> meshVertices(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) {
    std::vector<MeshVertex> vertices(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) vertices[i] = {positions[i], normals[i]};
    return vertices;
}

Status createSchemeMeshPass(MeshPass& pass, const GpuContext& gpu) {
    Result<MeshPass> created = createMeshPass(*gpu.vulkan, gpu.cache, gpu.colorFormat, gpu.depthFormat);
    if (!created) return created.error();
    pass = *created;
    return success();
}

Status replaceMesh(const VulkanContext& context, GpuMesh& mesh, std::span<const MeshVertex> vertices,
                   std::span<const uint32_t> indices) {
    if (mesh.indexCount) destroyMesh(context, mesh);
    mesh = GpuMesh{};
    if (vertices.empty()) return success();
    Result<GpuMesh> uploaded = uploadMesh(context, vertices, indices);
    if (!uploaded) return uploaded.error();
    mesh = *uploaded;
    return success();
}

uint32_t displacedGridFactor(const PlannedCage& planned, const Displacement& displacement, uint32_t requested) {
    uint32_t factor = std::max(requested, 1u);
    if (!displacement.empty()) factor = std::max(factor, requiredMeshFactor(planned, displacement.layout));
    bool anyNgon = false;
    for (uint32_t f = 0; f < planned.cage().faceCount(); ++f) anyNgon |= planned.cage().faceSize(f) != 4;
    if (anyNgon) factor += factor % 2;
    return std::min(factor, 2 * kMaxDisplacementResolution);
}

Result<DisplacedMesh> displacedSchemeMesh(const Scheme& scheme, const PlannedCage& planned,
                                          const Displacement& displacement, uint32_t factor) {
    return buildDisplacedMesh(planned, displacement, factor, [&scheme](uint32_t s, float u, float v) {
        const SampleRequest request{s, u, v};
        SurfacePoint point;
        scheme.evaluate(std::span<const SampleRequest>(&request, 1), std::span<SurfacePoint>(&point, 1));
        if (!point.hasDerivatives) point.du = point.dv = glm::vec3(0.0f);  // displacePoint falls back to the normal
        return SurfaceFrame{point.position, point.du, point.dv, point.normal};
    });
}

}  // namespace qp
