#include "scheme_culling.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "displacement/displaced_mesh.h"
#include "scheme_support.h"

namespace qp {

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The bounds for this frame: kept, or built (timed into the frame) when absent or of the other kind.
void ensureBounds(PatchCulling& culling, bool perSubface, const PatchBounds& patches, const Displacement* displacement,
                  DrawStats& stats) {
    if (culling.bounds && culling.perSubface == perSubface) return;
    const auto start = std::chrono::steady_clock::now();
    culling.bounds = perSubface ? subfaceCullSet(patches, culling.cover) : patchCullSet(patches);
    culling.perSubface = perSubface;
    culling.margins = perSubface && displacement ? displacementMargins(*displacement) : std::vector<float>{};
    stats.cullMilliseconds += millisecondsSince(start);
}

}  // namespace

std::vector<uint32_t> keepBesideDrawn(std::vector<uint32_t> culled, const CullAdjacency& neighbours, const PatchCullSet& set,
                                      const DrawView& view, DrawStats& stats) {
    if (neighbours.items.empty() || stats.cull.backFacing == 0) return culled;
    const auto start = std::chrono::steady_clock::now();
    std::vector<char> isCulled(set.size(), 0);
    for (uint32_t e : culled) isCulled[e] = 1;
    const CullFrustum frustum = frustumOf(view.viewProjection);
    std::vector<uint32_t> kept;
    for (uint32_t e : culled) {
        bool cull = outsideFrustum(frustum, set.boxes[e]);
        if (!cull) {
            cull = true;
            for (uint32_t k = neighbours.first[e]; k < neighbours.first[e + 1] && cull; ++k) cull = isCulled[neighbours.items[k]];
            if (!cull) --stats.cull.backFacing;
        }
        if (cull) kept.push_back(e);
    }
    stats.cullMilliseconds += millisecondsSince(start);
    return kept;
}

CullAdjacency adjacencyOfGroups(uint32_t entries, const std::vector<std::vector<uint32_t>>& groups) {
    std::vector<std::vector<uint32_t>> around(entries);
    for (const std::vector<uint32_t>& group : groups)
        for (uint32_t a : group)
            for (uint32_t b : group)
                if (a != b) around[a].push_back(b);
    CullAdjacency adjacency;
    for (std::vector<uint32_t>& list : around) {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        adjacency.items.insert(adjacency.items.end(), list.begin(), list.end());
        adjacency.first.push_back(uint32_t(adjacency.items.size()));
    }
    return adjacency;
}

std::vector<std::vector<uint32_t>> facesAroundVertices(const PlannedCage& planned) {
    const Topology& topology = planned.topology();
    std::vector<std::vector<uint32_t>> groups(planned.cage().vertexCount());
    for (uint32_t v = 0; v < groups.size(); ++v)
        groups[v].assign(topology.vertexFaces.begin() + topology.vertexFaceOffsets[v],
                         topology.vertexFaces.begin() + topology.vertexFaceOffsets[v + 1]);
    return groups;
}

CullAdjacency subfaceAdjacency(const PlannedCage& planned) {
    std::vector<std::vector<uint32_t>> groups = facesAroundVertices(planned);
    for (std::vector<uint32_t>& group : groups) {
        std::vector<uint32_t> subfaces;
        for (uint32_t face : group)
            for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s) subfaces.push_back(s);
        group = std::move(subfaces);
    }
    return adjacencyOfGroups(planned.subfaceCount(), groups);
}

PatchCover patchCover(uint32_t subfaceCount, uint32_t patchCount, std::vector<std::pair<uint32_t, uint32_t>> pairs) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    PatchCover cover;
    cover.first.assign(subfaceCount + 1, 0);
    cover.subfacesOfPatch.assign(patchCount, 0);
    for (const auto& pair : pairs) {
        ++cover.first[pair.first + 1];
        cover.patches.push_back(pair.second);
        ++cover.subfacesOfPatch[pair.second];
    }
    for (uint32_t s = 0; s < subfaceCount; ++s) cover.first[s + 1] += cover.first[s];
    return cover;
}

PatchCover quadPatchCover(const QuadPatchSource& source, uint32_t patchCount) {
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    constexpr int kCells = 4;
    for (uint32_t s = 0; s < source.originalSubfaces; ++s)
        for (int j = 0; j < kCells; ++j)
            for (int i = 0; i < kCells; ++i) {
                const RefinedLocation at = locateOnQuads(source, s, (i + 0.5) / kCells, (j + 0.5) / kCells);
                if (source.facePatch[at.face] != kNoPatch) pairs.push_back({s, source.facePatch[at.face]});
            }
    return patchCover(source.originalSubfaces, patchCount, std::move(pairs));
}

CullAdjacency quadPatchAdjacency(const QuadPatchSource& source, uint32_t patchCount) {
    const Topology& topology = source.topology;
    std::vector<std::vector<uint32_t>> groups(source.quads.vertexCount());
    for (uint32_t v = 0; v < groups.size(); ++v)
        for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k)
            if (source.facePatch[topology.vertexFaces[k]] != kNoPatch) groups[v].push_back(source.facePatch[topology.vertexFaces[k]]);
    return adjacencyOfGroups(patchCount, groups);
}

PatchCullSet patchCullSet(const PatchBounds& patches) {
    PatchCullSet set;
    for (uint32_t p = 0; p < patches.count; ++p) {
        const glm::vec3 origin = patches.anchor(p);
        PatchCullLeaves leaves;
        patches.addLeaves(p, origin, leaves);
        appendPatch(set, leaves, origin);
    }
    return set;
}

PatchCullSet subfaceCullSet(const PatchBounds& patches, const PatchCover& cover) {
    PatchCullSet set;
    for (uint32_t s = 0; s + 1 < cover.first.size(); ++s) {
        if (cover.first[s] == cover.first[s + 1]) {
            appendAbsentPatch(set);
            continue;
        }
        const glm::vec3 origin = patches.anchor(cover.patches[cover.first[s]]);
        PatchCullLeaves leaves;
        for (uint32_t k = cover.first[s]; k < cover.first[s + 1]; ++k) patches.addLeaves(cover.patches[k], origin, leaves);
        appendPatch(set, leaves, origin);
    }
    return set;
}

std::vector<uint32_t> whollyCulledSubfaces(const PatchCover& cover, std::span<const uint32_t> culledPatches) {
    std::vector<uint32_t> out;
    if (culledPatches.empty()) return out;
    for (uint32_t s = 0; s + 1 < cover.first.size(); ++s) {
        bool all = cover.first[s] < cover.first[s + 1];
        for (uint32_t k = cover.first[s]; k < cover.first[s + 1] && all; ++k)
            all = std::binary_search(culledPatches.begin(), culledPatches.end(), cover.patches[k]);
        if (all) out.push_back(s);
    }
    return out;
}

uint64_t patchesWhollyCulled(const PatchCover& cover, std::span<const uint32_t> culledSubfaces) {
    std::vector<uint32_t> culledOf(cover.subfacesOfPatch.size(), 0);  // per patch: its culled sub-faces
    uint64_t whole = 0;
    for (uint32_t s : culledSubfaces)
        for (uint32_t k = cover.first[s]; k < cover.first[s + 1]; ++k) {
            const uint32_t p = cover.patches[k];
            whole += ++culledOf[p] == cover.subfacesOfPatch[p];
        }
    return whole;
}

std::vector<float> displacementMargins(const Displacement& displacement) {
    const DisplacementLayout& layout = displacement.layout;
    std::vector<float> margins(layout.tiles.size(), 0.0f);
    for (uint32_t s = 0; s < layout.tiles.size(); ++s) {
        const DisplacementTile& tile = layout.tiles[s];
        for (uint32_t k = 0; k < (tile.cells + 2) * (tile.cells + 2); ++k)
            margins[s] = std::max(margins[s], std::abs(displacement.samples[layout.padded[tile.offset + k]]));
    }
    return margins;
}

std::vector<uint32_t> cullPatchesForView(PatchCulling& culling, const PatchBounds& patches, const DrawView& view,
                                         DrawStats& stats) {
    if (view.culledSubfacesOut) view.culledSubfacesOut->clear();
    if (view.culledPatchesOut) view.culledPatchesOut->clear();
    if (view.cull == CullMethod::None) return {};
    ensureBounds(culling, false, patches, nullptr, stats);
    const std::vector<uint32_t> culled =
        keepBesideDrawn(cullForView(*culling.bounds, culling.closed, {}, view, stats), culling.patchNeighbours, *culling.bounds, view, stats);
    if (view.culledSubfacesOut) *view.culledSubfacesOut = whollyCulledSubfaces(culling.cover, culled);
    if (view.culledPatchesOut) *view.culledPatchesOut = culled;
    return culled;
}

std::vector<uint32_t> cullSubfacesForView(PatchCulling& culling, const PatchBounds& patches,
                                          const Displacement* displacement, const DrawView& view, DrawStats& stats) {
    if (view.culledSubfacesOut) view.culledSubfacesOut->clear();
    if (view.culledPatchesOut) view.culledPatchesOut->clear();
    stats.patches = patches.count;
    if (view.cull == CullMethod::None) return {};
    ensureBounds(culling, true, patches, displacement, stats);
    // Displaced, only the frustum culls (no back-facing entries for the seams to keep).
    const std::vector<uint32_t> culled = keepBesideDrawn(cullForView(*culling.bounds, culling.closed, culling.margins, view, stats),
                                                        culling.subfaceNeighbours, *culling.bounds, view, stats);
    if (view.culledSubfacesOut) *view.culledSubfacesOut = culled;
    stats.patches -= patchesWhollyCulled(culling.cover, culled);
    return culled;
}

std::vector<IndexRange> keptIndexRanges(std::span<const uint32_t> firstIndex, std::span<const uint32_t> culled) {
    std::vector<IndexRange> ranges;
    const uint32_t parts = uint32_t(firstIndex.size()) - 1;
    uint32_t begin = 0;  // the first part of the run being kept
    auto keep = [&](uint32_t end) {
        if (end > begin && firstIndex[end] > firstIndex[begin])
            ranges.push_back({firstIndex[begin], firstIndex[end] - firstIndex[begin]});
    };
    for (uint32_t part : culled) {
        if (part >= parts) break;
        keep(part);
        begin = std::max(begin, part + 1);
    }
    keep(parts);
    return ranges;
}

std::vector<IndexRange> displacedKeptRanges(const DisplacedDrawing& drawing, std::span<const uint32_t> culledSubfaces) {
    const DisplacedMesh& mesh = drawing.mesh;
    std::vector<uint32_t> firstIndex(mesh.gridFactor.size() + 1, 0);  // 6 n^2 indices a grid
    for (size_t g = 0; g < mesh.gridFactor.size(); ++g)
        firstIndex[g + 1] = firstIndex[g] + 6 * mesh.gridFactor[g] * mesh.gridFactor[g];
    std::vector<uint32_t> culledGrids;  // ascending: grids follow their sub-faces' order
    for (uint32_t s : culledSubfaces)
        if (s < drawing.gridOfSubface.size() && drawing.gridOfSubface[s] != UINT32_MAX)
            culledGrids.push_back(drawing.gridOfSubface[s]);
    return keptIndexRanges(firstIndex, culledGrids);
}

void recordMeshParts(VkCommandBuffer cmd, const MeshPass& pass, const RenderTarget& target, const DrawView& view,
                     const GpuMesh& mesh, const std::vector<IndexRange>* parts, DrawStats& stats) {
    MeshDraw draw{&mesh, glm::vec3(0.8f), true, view.wireframe};
    stats.triangles = mesh.indexCount / 3;
    if (parts) {
        draw.ranges = *parts;
        stats.triangles = 0;
        for (const IndexRange& range : *parts) stats.triangles += range.count / 3;
    }
    recordMeshPass(cmd, pass, target, MeshView{view.viewProjection, view.eye, view.background, view.shading, view.clear},
                   stats.triangles ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
    stats.drawnBy = DrawnBy::CpuMesh;
}

void recordDisplacedParts(VkCommandBuffer cmd, const MeshPass& pass, const RenderTarget& target, const DrawView& view,
                          const DisplacedDrawing& drawing, std::span<const uint32_t> culledSubfaces, DrawStats& stats) {
    if (culledSubfaces.empty()) return recordMeshParts(cmd, pass, target, view, drawing.gpu, nullptr, stats);
    const std::vector<IndexRange> parts = displacedKeptRanges(drawing, culledSubfaces);
    recordMeshParts(cmd, pass, target, view, drawing.gpu, &parts, stats);
}

}  // namespace qp
