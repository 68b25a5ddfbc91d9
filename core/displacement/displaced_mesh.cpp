#include "displacement/displaced_mesh.h"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "displacement/sculpt_samples.h"

namespace qp {

namespace {

// D at grid vertex (i, j) of n: one formula for the full build and the incremental update.
DisplacementValue displacementAt(const Displacement& displacement, uint32_t subface, uint32_t i, uint32_t j, uint32_t n) {
    if (displacement.empty()) return DisplacementValue{};
    return evaluateDisplacement(displacement, subface, float(i) / float(n), float(j) / float(n));
}

void displaceVertex(DisplacedMesh& mesh, uint32_t vertex, const DisplacementValue& d) {
    const SurfaceFrame& f = mesh.frames[vertex];
    const DisplacedPoint p = displacePoint(f.position, f.du, f.dv, f.normal, d);
    mesh.positions[vertex] = p.position;
    mesh.normals[vertex] = p.normal;
}

}  // namespace

uint32_t requiredMeshFactor(const PlannedCage& planned, const DisplacementLayout& layout) {
    uint32_t factor = 1;
    for (uint32_t face = 0; face < planned.cage().faceCount(); ++face) {
        bool quad = planned.cage().faceSize(face) == 4;
        for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s)
            factor = std::max(factor, (quad ? 1 : 2) * requiredTessellationFactor(layout, s));
    }
    return factor;
}

Result<DisplacedMesh> buildDisplacedMesh(const PlannedCage& planned, const Displacement& displacement, uint32_t factor) {
    return buildDisplacedMesh(planned, displacement, factor, [&planned](uint32_t s, float u, float v) {
        const LimitSample sample = planned.evaluate(s, u, v);
        return SurfaceFrame{sample.position, sample.du, sample.dv, limitNormal(planned, s, u, v, sample)};
    });
}

Result<DisplacedMesh> buildDisplacedMesh(const PlannedCage& planned, const Displacement& displacement, uint32_t factor,
                                         const SurfaceFunction& surface) {
    const Cage& cage = planned.cage();
    bool anyNgon = false;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) anyNgon |= cage.faceSize(f) != 4;
    if (factor < 1 || factor > 2 * kMaxDisplacementResolution)
        return Error{"mesh factor must be between 1 and " + std::to_string(2 * kMaxDisplacementResolution) + ", got " +
                     std::to_string(factor)};
    if (anyNgon && factor % 2)
        return Error{"mesh factor must be even on a cage with non-quad faces (their sub-faces get half), got " +
                     std::to_string(factor)};
    if (!displacement.empty() && displacement.layout.tiles.size() != planned.subfaceCount())
        return Error{"the displacement has " + std::to_string(displacement.layout.tiles.size()) +
                     " sub-faces but the cage has " + std::to_string(planned.subfaceCount())};

    DisplacedMesh mesh;
    mesh.factor = factor;
    uint32_t vertices = 0;
    for (uint32_t face = 0; face < cage.faceCount(); ++face)
        for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s) {
            if (!planned.hasSurface(s)) continue;
            uint32_t n = cage.faceSize(face) == 4 ? factor : factor / 2;
            mesh.gridSubface.push_back(s);
            mesh.gridFactor.push_back(n);
            mesh.gridOffset.push_back(vertices);
            vertices += (n + 1) * (n + 1);
        }
    mesh.positions.resize(vertices);
    mesh.normals.resize(vertices);
    mesh.frames.resize(vertices);

    // Without displacement the layout still names the shared boundaries and their owners.
    const SampleGridLayout fallback =
        displacement.empty() ? buildSampleGridLayout(cage, planned.topology(), 1) : SampleGridLayout{};
    const SampleGridLayout& layout = displacement.empty() ? fallback : displacement.layout.adjacency;
    const BoundaryOwners owners = computeBoundaryOwners(layout, planned);
    tbb::parallel_for(size_t(0), mesh.gridSubface.size(), [&](size_t g) {
        const uint32_t s = mesh.gridSubface[g], n = mesh.gridFactor[g];
        for (uint32_t j = 0; j <= n; ++j)
            for (uint32_t i = 0; i <= n; ++i) {
                const float u = float(i) / float(n), v = float(j) / float(n);
                const SurfaceFrame own = surface(s, u, v);
                glm::vec3 position = own.position, normal = own.normal;
                const DisplacementValue d = displacementAt(displacement, s, i, j, n);
                {
                    // The boundary's owner evaluates the limit there, from integers.
                    const DisplacementSubface& sf = layout.subfaces[s];
                    const bool onEdge = i == 0 || i == n || j == 0 || j == n;
                    if (onEdge) {
                        uint32_t owner = kNoSite;
                        glm::vec2 uv;
                        const bool corner = (i == 0 || i == n) && (j == 0 || j == n);
                        if (corner) {
                            uint32_t c = j == 0 ? (i == 0 ? 0 : 1) : (i == n ? 2 : 3);
                            const PointOwner& o = owners.points[sf.corners[c]];
                            owner = o.subface;
                            uv = {kCornerU[o.corner], kCornerV[o.corner]};
                        } else {
                            uint32_t edge = j == 0 ? 0 : i == n ? 1 : j == n ? 2 : 3;
                            uint32_t along = edge == 0 || edge == 2 ? i : j;
                            EdgeSite site = edgeSite(sf, edge, along, n);
                            if (site.k == 0 || site.k == site.intervals) {
                                // The midpoint of a split edge: a point.
                                const DisplacementSegment& seg = layout.segments[site.segment];
                                const PointOwner& o = owners.points[site.k == 0 ? seg.pointA : seg.pointB];
                                owner = o.subface;
                                uv = {kCornerU[o.corner], kCornerV[o.corner]};
                            } else {
                                const SegmentOwner& o = owners.segments[site.segment];
                                owner = o.subface;
                                uv = o.uv(layout, site.k, site.intervals);
                            }
                        }
                        if (owner != s || uv != glm::vec2(u, v)) {
                            const SurfaceFrame at = surface(owner, uv.x, uv.y);
                            position = at.position;
                            normal = at.normal;
                        }
                    }
                }
                const uint32_t vertex = mesh.gridOffset[g] + j * (n + 1) + i;
                mesh.frames[vertex] = SurfaceFrame{position, own.du, own.dv, normal};
                displaceVertex(mesh, vertex, d);
            }
    });
    for (size_t g = 0; g < mesh.gridSubface.size(); ++g) {
        const uint32_t n = mesh.gridFactor[g], base = mesh.gridOffset[g];
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
                mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
            }
    }
    return mesh;
}

void redisplaceGrids(DisplacedMesh& mesh, const Displacement& displacement, std::span<const uint32_t> grids) {
    tbb::parallel_for(size_t(0), grids.size(), [&](size_t k) {
        const uint32_t g = grids[k], s = mesh.gridSubface[g], n = mesh.gridFactor[g];
        for (uint32_t j = 0; j <= n; ++j)
            for (uint32_t i = 0; i <= n; ++i)
                displaceVertex(mesh, mesh.gridOffset[g] + j * (n + 1) + i, displacementAt(displacement, s, i, j, n));
    });
}

}  // namespace qp
