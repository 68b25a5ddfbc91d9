#include "gpu_plans.h"

#include <algorithm>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

constexpr uint32_t kFirstHalf = 1 << 2, kSecondHalf = 2 << 2;  // GpuSegment::ownerEdge

// Sub-face edge e runs from corner kEdgeStart[e] to corner kEdgeEnd[e].
constexpr uint32_t kEdgeStart[4] = {0, 1, 3, 0};
constexpr uint32_t kEdgeEnd[4] = {1, 2, 2, 3};

// Boundaries are built in two steps so that the first runs on every core: each sub-face's
// corners, flags, midpoints and segment slots (independent of the others; the slots wait in
// the segment fields), then, in drawing order, segments numbered and points and segments owned
// by their first user.
struct BoundaryBuilder {
    const PlannedCage& planned;
    const Cage& cage;
    const Topology& topology;

    uint32_t vertexPoint(uint32_t v) const { return v; }
    uint32_t midpoint(uint32_t edge) const { return cage.vertexCount() + edge; }
    uint32_t centre(uint32_t face) const { return cage.vertexCount() + topology.edgeCount() + face; }

    // A quad's edge is split when a drawn sub-face of a non-quad has half of it: then the
    // midpoint is that sub-face's corner (and owned). Holes count (they are kept and hidden);
    // next to a face without any surface nothing meets the edge's middle, so the quad keeps it
    // whole.
    bool edgeIsSplit(uint32_t edge) const {
        for (uint32_t k = topology.edgeFaceOffsets[edge]; k < topology.edgeFaceOffsets[edge + 1]; ++k) {
            const uint32_t face = topology.edgeFaces[k], n = cage.faceSize(face);
            if (n == 4) continue;
            for (uint32_t i = 0; i < n; ++i) {
                if (topology.faceEdges[cage.faceOffsets[face] + i] != edge) continue;
                // Sub-face i has the edge's first half, sub-face i + 1 its second.
                const uint32_t first = planned.firstSubface(face);
                if (planned.hasPlannedSurface(first + i) || planned.hasPlannedSurface(first + (i + 1) % n)) return true;
            }
        }
        return false;
    }

    // Segments are found by what they are, in one flat array: a whole cage edge, the half of a
    // cage edge at one of its vertices, or the spoke from a cage edge's midpoint to the centre
    // of a non-quad face (named by the first corner of the face on that edge).
    uint32_t slotCount() const { return 3 * topology.edgeCount() + uint32_t(cage.faceVertices.size()); }
    uint32_t wholeEdge(uint32_t edge) const { return 3 * edge; }
    uint32_t halfEdge(uint32_t edge, uint32_t vertex) const {
        return 3 * edge + (vertex == topology.edgeVertices[2 * edge] ? 1 : 2);
    }
    uint32_t spoke(uint32_t face, uint32_t edge) const {
        const uint32_t* edges = &topology.faceEdges[cage.faceOffsets[face]];
        return 3 * topology.edgeCount() + cage.faceOffsets[face] + uint32_t(std::find(edges, edges + cage.faceSize(face), edge) - edges);
    }

    // Step one: everything but the segment numbers (their slots stand in for them).
    GpuSubfaceBoundary build(uint32_t face, uint32_t k) const {
        const uint32_t n = cage.faceSize(face);
        const uint32_t* fv = cage.faceBegin(face);
        GpuSubfaceBoundary b{};
        if (n == 4) {
            for (uint32_t i = 0; i < 4; ++i) b.corners[i] = vertexPoint(fv[i]);
            for (uint32_t e = 0; e < 4; ++e) {
                uint32_t a = fv[kEdgeStart[e]], z = fv[kEdgeEnd[e]];
                // Sub-face edges 0, 1, 2, 3 run along the face's edges 0, 1, 2, 3 (2 and 3 backwards).
                uint32_t cageEdge = topology.faceEdges[cage.faceOffsets[face] + e];
                GpuEdgeRef& ref = b.edges[e];
                if (edgeIsSplit(cageEdge)) {
                    ref.midpoint = midpoint(cageEdge);
                    ref.segment = halfEdge(cageEdge, a);
                    ref.secondHalf = halfEdge(cageEdge, z);
                    ref.flags = kEdgeRefSplit;
                } else {
                    ref.segment = wholeEdge(cageEdge);
                    ref.flags = a > z ? kEdgeRefReversed : 0;
                }
            }
        } else {
            uint32_t next = topology.faceEdges[cage.faceOffsets[face] + k];
            uint32_t prev = topology.faceEdges[cage.faceOffsets[face] + (k + n - 1) % n];
            b.corners[0] = vertexPoint(fv[k]);
            b.corners[1] = midpoint(next);
            b.corners[2] = centre(face);
            b.corners[3] = midpoint(prev);
            // Edges 0 and 3 are the halves of `next` and `prev` at the corner's vertex, 1 and 2
            // the spokes from their midpoints to the centre.
            const uint32_t slots[4] = {halfEdge(next, fv[k]), spoke(face, next), spoke(face, prev), halfEdge(prev, fv[k])};
            for (uint32_t e = 0; e < 4; ++e) {
                uint32_t a = b.corners[kEdgeStart[e]], z = b.corners[kEdgeEnd[e]];
                b.edges[e].segment = slots[e];
                b.edges[e].flags = a > z ? kEdgeRefReversed : 0;
            }
            // Edges 0 and 3 are halves of cage edges: their factor comes from the whole edge.
            b.edges[0].flags |= kEdgeRefHalf;
            b.edges[0].midpoint = b.corners[1];
            b.edges[3].flags |= kEdgeRefHalf;
            b.edges[3].midpoint = b.corners[3];
        }
        return b;
    }
};

// Step two, for one drawn sub-face in drawing order: its segments numbered (the first user of a
// slot makes the segment and owns it) and its corners' points owned by their first user.
void numberSegments(GpuPlanData& gpu, std::vector<uint32_t>& segmentIndex, uint32_t drawn) {
    auto segment = [&](uint32_t slot, uint32_t ownerEdge, uint32_t reversed) {
        uint32_t& index = segmentIndex[slot];
        if (index == UINT32_MAX) {
            index = uint32_t(gpu.segments.size());
            gpu.segments.push_back(GpuSegment{drawn, ownerEdge, reversed, 0});
        }
        return index;
    };
    GpuSubfaceBoundary& b = gpu.boundaries[drawn];
    for (uint32_t e = 0; e < 4; ++e) {
        GpuEdgeRef& ref = b.edges[e];
        if (ref.flags & kEdgeRefSplit) {
            // Each half runs from the lower point id to the higher: vertex -> midpoint forwards,
            // midpoint -> vertex backwards (midpoint ids are above every vertex id).
            ref.segment = segment(ref.segment, e | kFirstHalf, 0);
            ref.secondHalf = segment(ref.secondHalf, e | kSecondHalf, 1);
        } else {
            ref.segment = segment(ref.segment, e, ref.flags & kEdgeRefReversed);
        }
    }
    for (uint32_t c = 0; c < 4; ++c)
        if (GpuPoint& p = gpu.boundaryPoints[b.corners[c]]; p.owner == UINT32_MAX) p = GpuPoint{drawn, c};
}

}  // namespace

void appendPlanTables(GpuPlanData& gpu, const PlanDatabase& database) {
    for (uint32_t id = uint32_t(gpu.plans.size()); id < database.size(); ++id) {
        const Plan& plan = database.plan(id);
        GpuPlanHeader header{};
        header.rootNode = uint32_t(gpu.nodes.size());
        header.weightOffset = uint32_t(gpu.weights.size());
        header.ringSize = plan.ringSize;
        header.maxDepth = plan.maxDepth;
        std::copy(plan.stencilCountByLevel.begin(), plan.stencilCountByLevel.end(), header.stencilCountByLevel);
        header.stencilCountByLevel[kMaxPlanDepth + 1] = plan.cornerTangents;
        const uint32_t pointBase = uint32_t(gpu.points.size());
        for (const PlanNode& node : plan.nodes) {
            GpuNode g{};
            g.kind_mask_edge_levels = uint32_t(node.kind) | uint32_t(node.boundaryMask) << 8 |
                                      uint32_t(node.edge) << 16 | uint32_t(node.levels) << 24;
            g.first = node.first + (node.kind == NodeKind::Internal ? header.rootNode : pointBase);
            g.sharpness = node.sharpness;
            gpu.nodes.push_back(g);
        }
        if (!gpu.hostEvaluation) {
            gpu.points.insert(gpu.points.end(), plan.points.begin(), plan.points.end());
            gpu.weights.insert(gpu.weights.end(), plan.stencilWeights.begin(), plan.stencilWeights.end());
        }
        gpu.plans.push_back(header);
    }
}

GpuPlanData packPlans(const PlannedCage& planned, bool hostEvaluation) {
    GpuPlanData gpu;
    gpu.hostEvaluation = hostEvaluation;
    appendPlanTables(gpu, planned.database());
    packSubfaces(gpu, planned);
    buildRingUsers(gpu, planned);
    return gpu;
}

void packSubfaces(GpuPlanData& gpu, const PlannedCage& planned) {
    const PlanDatabase& database = planned.database();
    gpu.subfaces.clear();
    gpu.controlPointCount = 0;
    gpu.segments.clear();
    const Cage& cage = planned.cage();
    const Topology& topology = planned.topology();
    std::vector<std::pair<uint32_t, uint32_t>> faceAndCorner;  // per drawn sub-face
    // Sized once (a repack runs on every hole and topology edit; rings keep their capacity).
    faceAndCorner.reserve(planned.subfaceCount());
    gpu.subfaces.reserve(planned.subfaceCount());
    uint32_t ringSize = 0;
    for (uint32_t face = 0; face < cage.faceCount(); ++face) {
        for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s) {
            // planned.hasPlannedSurface(s), with the plan looked up once for its stencils too.
            if (planned.subfacePlan(s) == kNoPlan) continue;
            const Plan& plan = database.plan(planned.subfacePlan(s));
            if (!plan.hasSurface()) continue;
            GpuSubface g{};
            g.plan = planned.subfacePlan(s);
            g.rotation = planned.subfaceRotation(s);
            g.ringOffset = ringSize;
            g.cpOffset = gpu.controlPointCount;
            g.subface = s;
            ringSize += uint32_t(planned.subfaceRing(s).size());
            gpu.controlPointCount += plan.stencilCount();
            gpu.subfaces.push_back(g);
            faceAndCorner.push_back({face, s - planned.firstSubface(face)});
        }
    }
    gpu.ringEntries = ringSize;
    gpu.rings.resize(gpu.hostEvaluation ? 0 : ringSize);
    auto packRings = [&](const tbb::blocked_range<size_t>& range) {
        for (size_t d = range.begin(); d != range.end(); ++d) {
            const std::span<const uint32_t> ring = planned.subfaceRing(gpu.subfaces[d].subface);
            std::copy(ring.begin(), ring.end(), gpu.rings.begin() + gpu.subfaces[d].ringOffset);
        }
    };
    if (!gpu.hostEvaluation) tbb::parallel_for(tbb::blocked_range<size_t>(0, gpu.subfaces.size(), 1024), packRings);

    // Non-quads first, so half segments are owned by the n-gon sub-face that has exactly that
    // edge; a quad owns half of its edge only when no such sub-face is in the tables (boundary
    // rule "none").
    gpu.boundaryPoints.assign(cage.vertexCount() + topology.edgeCount() + cage.faceCount(), GpuPoint{UINT32_MAX, 0});
    const uint32_t count = uint32_t(gpu.subfaces.size());
    gpu.boundaries.resize(count);
    const BoundaryBuilder builder{planned, cage, topology};
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 1024), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t d = range.begin(); d != range.end(); ++d)
            gpu.boundaries[d] = builder.build(faceAndCorner[d].first, faceAndCorner[d].second);
    });
    std::vector<uint32_t> segmentIndex(builder.slotCount(), UINT32_MAX);  // slot -> segment, or UINT32_MAX
    gpu.segments.reserve(topology.edgeCount());  // one per edge on an all-quad cage; n-gons add spokes and halves
    for (bool quads : {false, true})
        for (uint32_t d = 0; d < count; ++d)
            if ((cage.faceSize(faceAndCorner[d].first) == 4) == quads) numberSegments(gpu, segmentIndex, d);
}

void buildRingUsers(GpuPlanData& gpu, const PlannedCage& planned) {
    const uint32_t vertexCount = planned.cage().vertexCount(), count = uint32_t(gpu.subfaces.size());
    gpu.vertexSubfaceOffsets.assign(vertexCount + 1, 0);
    for (uint32_t d = 0; d < count; ++d)
        for (uint32_t v : planned.subfaceRing(gpu.subfaces[d].subface)) ++gpu.vertexSubfaceOffsets[v + 1];
    for (uint32_t v = 0; v < vertexCount; ++v) gpu.vertexSubfaceOffsets[v + 1] += gpu.vertexSubfaceOffsets[v];
    gpu.vertexSubfaces.resize(gpu.vertexSubfaceOffsets.back());
    std::vector<uint32_t> fill(gpu.vertexSubfaceOffsets.begin(), gpu.vertexSubfaceOffsets.end() - 1);
    for (uint32_t d = 0; d < count; ++d)
        for (uint32_t v : planned.subfaceRing(gpu.subfaces[d].subface)) gpu.vertexSubfaces[fill[v]++] = d;
}

bool ringUsersMatch(const GpuPlanData& gpu, uint32_t drawn, std::span<const uint32_t> ring) {
    const uint32_t end = drawn + 1 < gpu.subfaces.size() ? gpu.subfaces[drawn + 1].ringOffset : gpu.ringEntries;
    if (ring.size() != end - gpu.subfaces[drawn].ringOffset) return false;
    // Equal lengths, and every vertex of `ring` lists the sub-face as often as `ring` holds it:
    // then the packed ring has no other vertex.
    for (uint32_t v : ring) {
        if (v + 1 >= gpu.vertexSubfaceOffsets.size()) return false;
        const auto users = std::equal_range(gpu.vertexSubfaces.begin() + gpu.vertexSubfaceOffsets[v],
                                            gpu.vertexSubfaces.begin() + gpu.vertexSubfaceOffsets[v + 1], drawn);
        if (users.second - users.first != std::count(ring.begin(), ring.end(), v)) return false;
    }
    return true;
}

void renumberRingUsers(GpuPlanData& gpu, const PlannedCage& planned, const std::vector<uint32_t>& oldOffsets,
                       const std::vector<uint32_t>& oldUsers, const std::vector<uint32_t>& oldOf, uint32_t oldCount) {
    const uint32_t vertexCount = uint32_t(oldOffsets.size()) - 1, count = uint32_t(gpu.subfaces.size());
    std::vector<uint32_t> newOfOld(oldCount, UINT32_MAX);
    std::vector<std::pair<uint32_t, uint32_t>> joining;  // (vertex, drawn) of the sub-faces drawn only now
    for (uint32_t d = 0; d < count; ++d) {
        if (oldOf[d] != UINT32_MAX) {
            newOfOld[oldOf[d]] = d;
            continue;
        }
        for (uint32_t v : planned.subfaceRing(gpu.subfaces[d].subface)) joining.push_back({v, d});
    }
    std::sort(joining.begin(), joining.end());
    gpu.vertexSubfaceOffsets.assign(vertexCount + 1, 0);
    gpu.vertexSubfaces.clear();
    gpu.vertexSubfaces.reserve(gpu.ringEntries);
    auto join = joining.begin();
    for (uint32_t v = 0; v < vertexCount; ++v) {
        // Both lists ascend (oldOf keeps the order of kept sub-faces): merge them.
        for (uint32_t k = oldOffsets[v]; k < oldOffsets[v + 1]; ++k) {
            const uint32_t d = newOfOld[oldUsers[k]];
            if (d == UINT32_MAX) continue;
            for (; join != joining.end() && join->first == v && join->second < d; ++join) gpu.vertexSubfaces.push_back(join->second);
            gpu.vertexSubfaces.push_back(d);
        }
        for (; join != joining.end() && join->first == v; ++join) gpu.vertexSubfaces.push_back(join->second);
        gpu.vertexSubfaceOffsets[v + 1] = uint32_t(gpu.vertexSubfaces.size());
    }
}

std::vector<uint32_t> subfacesAround(const GpuPlanData& data, std::span<const uint32_t> vertices) {
    std::vector<uint32_t> out;
    for (uint32_t v : vertices)
        out.insert(out.end(), data.vertexSubfaces.begin() + data.vertexSubfaceOffsets[v],
                   data.vertexSubfaces.begin() + data.vertexSubfaceOffsets[v + 1]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::vector<uint32_t> boundaryPointsAround(const PlannedCage& planned, std::span<const uint32_t> vertices) {
    const Topology& topology = planned.topology();
    const uint32_t vertexCount = planned.cage().vertexCount(), edgeCount = topology.edgeCount();
    std::vector<uint32_t> out;
    for (uint32_t v : vertices) {
        out.push_back(v);
        for (uint32_t k = topology.vertexEdgeOffsets[v]; k < topology.vertexEdgeOffsets[v + 1]; ++k)
            out.push_back(vertexCount + topology.vertexEdges[k]);
        for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k)
            out.push_back(vertexCount + edgeCount + topology.vertexFaces[k]);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

glm::vec4 boundaryPointPosition(const PlannedCage& planned, uint32_t id) {
    const Cage& cage = planned.cage();
    const Topology& topology = planned.topology();
    if (id < cage.vertexCount()) return glm::vec4(cage.positions[id], 1.0f);
    id -= cage.vertexCount();
    if (id < topology.edgeCount()) {
        // A midpoint carries the radius of its whole edge's bounding sphere, so both sides of a
        // split edge size it from the same numbers.
        const glm::vec3& a = cage.positions[topology.edgeVertices[2 * id]];
        const glm::vec3& b = cage.positions[topology.edgeVertices[2 * id + 1]];
        return glm::vec4(0.5f * (a + b), 0.5f * glm::length(b - a));
    }
    id -= topology.edgeCount();
    glm::vec3 sum(0.0f);
    for (uint32_t i = 0; i < cage.faceSize(id); ++i) sum += cage.positions[cage.faceBegin(id)[i]];
    return glm::vec4(sum / float(cage.faceSize(id)), 1.0f);
}

std::vector<glm::vec4> boundaryPointPositions(const PlannedCage& planned) {
    const uint32_t count = planned.cage().vertexCount() + planned.topology().edgeCount() + planned.cage().faceCount();
    std::vector<glm::vec4> points(count);
    // Every point on its own (a topology edit renumbers them all, in the frame that shows it).
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 4096), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t id = range.begin(); id != range.end(); ++id) points[id] = boundaryPointPosition(planned, id);
    });
    return points;
}

std::vector<float> cagePositions(const PlannedCage& planned) {
    std::vector<float> out;
    out.reserve(planned.cage().vertexCount() * 3);
    for (const glm::vec3& p : planned.cage().positions) out.insert(out.end(), {p.x, p.y, p.z});
    return out;
}

}  // namespace qp
