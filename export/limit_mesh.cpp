#include "limit_mesh.h"

#include <algorithm>
#include <optional>
#include <string>

#include "cpu_grid.h"
#include "grid_layout.h"

namespace qp {

namespace {

struct SlotGrid {
    GpuPlanData data;
    GridLayout layout;
};

Result<SlotGrid> slotGrid(const PlannedCage& planned, const MeshDensity& density) {
    if (!density.adaptive && (density.factor < 1 || density.factor > 64))
        return Error{"the tessellation factor must be 1 to 64, got " + std::to_string(density.factor)};
    if (density.adaptive && !(density.adaptive->pixelsPerSegment > 0.0f))
        return Error{"the adaptive target must be a positive number of pixels"};
    SlotGrid grid;
    grid.data = packPlans(planned);
    if (grid.data.subfaces.empty()) return Error{"the cage has no surface to export (every face is a hole or unplanned)"};
    grid.layout = buildGridLayout(grid.data, density.adaptive ? adaptiveGridFactors(grid.data, boundaryPointPositions(planned),
                                                                                    *density.adaptive)
                                                              : uniformGridFactors(grid.data, density.factor));
    return grid;
}

// The owner's slot a slot shows (itself when it is evaluated).
uint32_t ownerSlot(const GridLayout& layout, uint32_t slot) {
    for (uint32_t steps = 0; layout.source[slot] != slot && steps < 4; ++steps) slot = layout.source[slot];
    return slot;
}

// Welds by ownership and leaves out holes and degenerate triangles; `positions` and `normals`
// are per slot (only evaluated slots are read). With UVs, a shared vertex is split where the
// sub-faces around it give it different UVs (a seam).
LimitMesh weld(const SlotGrid& grid, std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
               const PlannedCage& planned, const CageUvs* uvs) {
    const GridLayout& layout = grid.layout;
    std::vector<uint32_t> vertexOfSlot(layout.slotCount(), UINT32_MAX);  // the first vertex made for an owned slot
    std::vector<uint32_t> nextAtSlot;                                      // per vertex: another one at the same slot
    std::vector<uint32_t> surfaceIndices;                                  // triangles by owned slot (the closure)
    LimitMesh mesh;
    auto localParameter = [&](uint32_t slot) {
        const uint32_t drawn = layout.slotSubface[slot];
        glm::vec2 p(0.0f);
        slotParameter(slot - layout.subfaceOffset[drawn], layout.factors.subfaceFactor[drawn], p.x, p.y);
        return p;
    };
    auto vertexOf = [&](uint32_t cornerSlot) {
        const uint32_t slot = ownerSlot(layout, cornerSlot);
        glm::vec2 uv(0.0f);
        if (uvs) {  // the UV the triangle's own sub-face gives this corner
            const glm::vec2 p = localParameter(cornerSlot);
            uv = uvs->at(grid.data.subfaces[layout.slotSubface[cornerSlot]].subface, p.x, p.y);
        }
        for (uint32_t v = vertexOfSlot[slot]; v != UINT32_MAX; v = nextAtSlot[v])
            if (!uvs || uvs->sameUv(mesh.uvs[v], uv)) return v;
        const uint32_t v = mesh.vertexCount();
        const glm::vec2 p = localParameter(slot);
        mesh.positions.push_back(positions[slot]);
        mesh.normals.push_back(normals[slot]);
        mesh.subfaces.push_back(grid.data.subfaces[layout.slotSubface[slot]].subface);
        mesh.parameters.push_back(p);
        if (uvs) mesh.uvs.push_back(uv);
        nextAtSlot.push_back(vertexOfSlot[slot]);
        vertexOfSlot[slot] = v;
        return v;
    };
    for (uint32_t drawn = 0; drawn < grid.data.subfaces.size(); ++drawn) {
        if (!planned.hasSurface(grid.data.subfaces[drawn].subface)) continue;  // a hole
        for (uint32_t i = layout.indexOffset[drawn]; i + 2 < layout.indexOffset[drawn + 1]; i += 3) {
            const uint32_t sa = ownerSlot(layout, layout.indices[i]), sb = ownerSlot(layout, layout.indices[i + 1]),
                           sc = ownerSlot(layout, layout.indices[i + 2]);
            if (sa == sb || sb == sc || sa == sc) continue;  // snapped flat along an edge
            surfaceIndices.insert(surfaceIndices.end(), {sa, sb, sc});
            mesh.indices.insert(mesh.indices.end(),
                                {vertexOf(layout.indices[i]), vertexOf(layout.indices[i + 1]), vertexOf(layout.indices[i + 2])});
        }
    }
    mesh.closure = meshClosure(surfaceIndices);
    return mesh;
}

Result<std::optional<CageUvs>> cageUvs(const PlannedCage& planned, UvMode uv) {
    if (uv == UvMode::None) return std::optional<CageUvs>();
    Result<CageUvs> uvs = CageUvs::create(planned, uv);
    if (!uvs) return uvs.error();
    return std::optional<CageUvs>(std::move(uvs).value());
}

}  // namespace

Result<LimitMesh> exactLimitMesh(const PlannedCage& planned, const MeshDensity& density, const Displacement* displacement,
                                 UvMode uv) {
    Result<std::optional<CageUvs>> uvs = cageUvs(planned, uv);
    if (!uvs) return uvs.error();
    Result<SlotGrid> grid = slotGrid(planned, density);
    if (!grid) return grid.error();
    std::vector<GridVertex> vertices(grid->layout.slotCount());
    GridFrames frames;
    if (displacement) frames.resize(grid->layout);
    evaluateWholeGridOnCpu(planned, grid->data, grid->layout, vertices.data(), displacement, displacement ? &frames : nullptr);
    std::vector<glm::vec3> positions(vertices.size()), normals(vertices.size());
    for (size_t s = 0; s < vertices.size(); ++s) {
        positions[s] = {vertices[s].position[0], vertices[s].position[1], vertices[s].position[2]};
        normals[s] = {vertices[s].normal[0], vertices[s].normal[1], vertices[s].normal[2]};
    }
    return weld(*grid, positions, normals, planned, *uvs ? &**uvs : nullptr);
}

Result<LimitMesh> evaluatedLimitMesh(const PlannedCage& planned, const MeshDensity& density, const SlotEvaluator& evaluate,
                                     UvMode uv) {
    Result<std::optional<CageUvs>> uvs = cageUvs(planned, uv);
    if (!uvs) return uvs.error();
    Result<SlotGrid> grid = slotGrid(planned, density);
    if (!grid) return grid.error();
    const GridLayout& layout = grid->layout;
    std::vector<uint32_t> owned;
    std::vector<SampleRequest> requests;
    for (uint32_t slot = 0; slot < layout.slotCount(); ++slot) {
        if (layout.source[slot] != slot) continue;
        const uint32_t drawn = layout.slotSubface[slot];
        SampleRequest r{grid->data.subfaces[drawn].subface, 0.0f, 0.0f};
        slotParameter(slot - layout.subfaceOffset[drawn], layout.factors.subfaceFactor[drawn], r.u, r.v);
        owned.push_back(slot);
        requests.push_back(r);
    }
    std::vector<glm::vec3> evaluatedPositions(requests.size()), evaluatedNormals(requests.size());
    evaluate(requests, evaluatedPositions, evaluatedNormals);
    std::vector<glm::vec3> positions(layout.slotCount()), normals(layout.slotCount());
    for (size_t k = 0; k < owned.size(); ++k) {
        positions[owned[k]] = evaluatedPositions[k];
        normals[owned[k]] = evaluatedNormals[k];
    }
    return weld(*grid, positions, normals, planned, *uvs ? &**uvs : nullptr);
}

MeshClosure meshClosure(std::span<const uint32_t> indices) {
    // Every directed edge as (undirected key, direction), sorted: runs are the uses of one edge.
    std::vector<std::pair<uint64_t, bool>> edges;
    edges.reserve(indices.size());
    for (size_t t = 0; t + 2 < indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = indices[t + k], b = indices[t + (k + 1) % 3];
            edges.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), a < b});
        }
    std::sort(edges.begin(), edges.end());
    MeshClosure closure;
    for (size_t i = 0; i < edges.size();) {
        size_t j = i, forward = 0;
        for (; j < edges.size() && edges[j].first == edges[i].first; ++j) forward += edges[j].second;
        const size_t total = j - i;
        if (total == 1) ++closure.borderEdges;
        else if (total > 2 || forward != 1) ++closure.nonManifoldEdges;
        i = j;
    }
    return closure;
}

}  // namespace qp
