#include "plan_update.h"

#include <algorithm>
#include <cassert>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "grid_relayout.h"

namespace qp {

namespace {

template <class T>
size_t bytesOf(const std::vector<T>& values) {
    return values.size() * sizeof(T);
}

// `buffer` holding `values`: rewritten from `from` (an element index) onwards when it fits, else
// replaced by a buffer half as big again (`grown` says so: descriptors must be rebound).
template <class T>
Status storeTail(const VulkanContext& ctx, Buffer& buffer, const std::vector<T>& values, size_t from, bool& grown) {
    if (bytesOf(values) <= buffer.size) {
        if (values.size() > from) uploadBuffer(buffer, values.data() + from, (values.size() - from) * sizeof(T), from * sizeof(T));
        return success();
    }
    Result<Buffer> bigger = createBuffer(ctx, bytesOf(values) + bytesOf(values) / 2, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (!bigger) return bigger.error();
    uploadBuffer(*bigger, values.data(), bytesOf(values));
    destroyBuffer(ctx, buffer);
    buffer = *bigger;
    grown = true;
    return success();
}

// Plans new to the database into the tables (and their buffers).
Status appendNewPlans(const VulkanContext& ctx, PlanBuffers& buffers, const PlanDatabase& database, PlanTableUpdate& update,
                      bool& rebind) {
    GpuPlanData& data = buffers.data;
    const size_t oldPlans = data.plans.size(), oldNodes = data.nodes.size(), oldPoints = data.points.size(),
                 oldWeights = data.weights.size();
    appendPlanTables(data, database);
    update.appendedPlans = uint32_t(data.plans.size() - oldPlans);
    if (update.appendedPlans == 0) return success();
    Status stored = storeTail(ctx, buffers.planHeaders, data.plans, oldPlans, rebind);
    if (stored) stored = storeTail(ctx, buffers.nodes, data.nodes, oldNodes, rebind);
    if (stored) stored = storeTail(ctx, buffers.points, data.points, oldPoints, rebind);
    if (stored) stored = storeTail(ctx, buffers.weights, data.weights, oldWeights, rebind);
    if (!stored) {  // tables that grew already hold the new plans too; the rest is as before
        data.plans.resize(oldPlans);
        data.nodes.resize(oldNodes);
        data.points.resize(oldPoints);
        data.weights.resize(oldWeights);
    }
    return stored;
}

// The owner (PlannedCage sub-face, its edge or corner) of what `drawn`'s edge e or corner c
// shows: equal before and after a change means that part of its grid copies the same bits.
struct EdgeOwners {
    uint64_t segment[4], secondHalf[4], corner[4];
    uint32_t flags[4];
};
// `previousOf` (empty: the identity) names owners by their numbers before a topology edit.
EdgeOwners ownersOf(const GpuPlanData& data, uint32_t drawn, std::span<const uint32_t> previousOf = {}) {
    const GpuSubfaceBoundary& b = data.boundaries[drawn];
    auto name = [&](uint32_t owner) {
        const uint32_t subface = data.subfaces[owner].subface;
        return uint64_t(previousOf.empty() ? subface : previousOf[subface]);
    };
    auto segmentOwner = [&](uint32_t segment) {
        const GpuSegment& g = data.segments[segment];
        return name(g.owner) << 8 | uint64_t(g.ownerEdge) << 1 | g.ownerReversed;
    };
    EdgeOwners o{};
    for (uint32_t e = 0; e < 4; ++e) {
        o.flags[e] = b.edges[e].flags;
        o.segment[e] = segmentOwner(b.edges[e].segment);
        o.secondHalf[e] = (b.edges[e].flags & kEdgeRefSplit) ? segmentOwner(b.edges[e].secondHalf) : 0;
        const GpuPoint& p = data.boundaryPoints[b.corners[e]];
        o.corner[e] = name(p.owner) << 8 | p.ownerCorner;
    }
    return o;
}
bool operator==(const EdgeOwners& a, const EdgeOwners& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The grid is laid out and evaluated whole at the next draw.
Status dropGrid(PlanBuffers& buffers, PlanTableUpdate& update) {
    buffers.gridLayout = GridLayout{};
    buffers.gridEvaluator = GridEvaluator::None;
    update.gridDropped = true;
    return success();
}

// Sub-faces gained or lost their planned surface (a hole whose plan could not be built was
// filled), or a topology edit renumbered them
// (`previousOf`, PlanChange::previousSubfaceOf; empty: the numbering stayed): the sub-face
// tables are packed again; the plan tables, every kept sub-face's control-point range and the
// evaluated grid stay, so only what now has another owner (and the sub-faces that are new or
// gained a surface) is evaluated again.
Status repackDrawnSet(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, const PlannedCage& planned,
                      const std::vector<uint32_t>& changed, std::span<const uint32_t> previousOf, PlanTableUpdate& update,
                      bool& rebind) {
    GpuPlanData& data = buffers.data;
    const PlanDatabase& database = planned.database();
    // Ring users: a tag edit keeps every ring, so the old lists can be renumbered; a topology
    // edit renumbers the vertices too, and they are built again.
    bool sameRings = previousOf.empty() && data.vertexSubfaceOffsets.size() == planned.cage().vertexCount() + 1;
    for (size_t k = 0; k < changed.size() && sameRings; ++k)
        if (const uint32_t d = buffers.drawnOfSubface[changed[k]]; d != UINT32_MAX)
            sameRings = ringUsersMatch(data, d, planned.subfaceRing(changed[k]));
    GpuPlanData old;  // the sub-face part before the change: what ownersOf and the ring users read
    old.subfaces = std::move(data.subfaces);
    old.boundaries = std::move(data.boundaries);
    old.segments = std::move(data.segments);
    old.boundaryPoints = std::move(data.boundaryPoints);
    old.vertexSubfaceOffsets = std::move(data.vertexSubfaceOffsets);
    old.vertexSubfaces = std::move(data.vertexSubfaces);
    old.controlPointCount = data.controlPointCount;
    const std::vector<uint32_t> oldDrawnOf = buffers.drawnOfSubface, oldCapacity = buffers.controlPointCapacity;
    packSubfaces(data, planned);
    const uint32_t count = uint32_t(data.subfaces.size());
    std::vector<uint32_t> drawnOf(planned.subfaceCount(), UINT32_MAX), oldOf(count, UINT32_MAX);
    for (uint32_t d = 0; d < count; ++d) {
        const uint32_t subface = data.subfaces[d].subface;
        drawnOf[subface] = d;
        const uint32_t previous = previousOf.empty() ? subface : previousOf[subface];
        oldOf[d] = previous < oldDrawnOf.size() ? oldDrawnOf[previous] : UINT32_MAX;
    }
    // Macro faces follow the topology and the drawn numbering; a tag edit that kept both keeps them.
    // Built again by the first frame that can draw them (a pass over the whole cage).
    bool renumbered = !previousOf.empty() || count != old.subfaces.size();
    for (uint32_t d = 0; d < count && !renumbered; ++d) renumbered = oldOf[d] != d;
    if (renumbered) {
        markMacroGridStale(data);
        buffers.macroInputs = {};  // chosen for the old macro faces: choose again
    }
    buffers.adaptiveInputs = {};  // the segments are numbered anew

    // The ring users on another core while control points, owners and the grid are settled
    // below: they read the planned cage's rings and the records' sub-face numbers, which
    // nothing up to the wait writes.
    tbb::task_group ringUsers;
    ringUsers.run([&] {
        if (sameRings)
            renumberRingUsers(data, planned, old.vertexSubfaceOffsets, old.vertexSubfaces, oldOf, uint32_t(old.subfaces.size()));
        else
            buildRingUsers(data, planned);
    });

    // Control points: kept sub-faces keep their ranges (and cached values); new ones go at the end.
    std::vector<uint32_t>& capacity = buffers.controlPointCapacity;
    capacity.assign(count, 0);
    uint32_t end = old.controlPointCount;
    for (uint32_t d = 0; d < count; ++d) {
        // A kept sub-face with its old plan fits its range (a range holds at least its plan's
        // stencils): the plan is looked up only for the others.
        const bool samePlan = oldOf[d] != UINT32_MAX && old.subfaces[oldOf[d]].plan == data.subfaces[d].plan;
        const uint32_t stencils = samePlan ? 0 : database.plan(data.subfaces[d].plan).stencilCount();
        if (oldOf[d] != UINT32_MAX && (samePlan || oldCapacity[oldOf[d]] >= stencils)) {
            data.subfaces[d].cpOffset = old.subfaces[oldOf[d]].cpOffset;
            capacity[d] = oldCapacity[oldOf[d]];
        } else {
            data.subfaces[d].cpOffset = end;
            capacity[d] = stencils;
            end += stencils;
            ++update.relocatedSubfaces;
        }
    }
    data.controlPointCount = end;

    // What to evaluate again: changed sub-faces, new ones, and every sub-face whose edges or
    // corners now come from another owner (with that owner).
    std::vector<uint32_t>& refresh = update.refresh;
    for (uint32_t s : changed)
        if (drawnOf[s] != UINT32_MAX) refresh.push_back(drawnOf[s]);
    // Which kept sub-faces' owners changed, collected in order below. An owner is the first user
    // of a segment or point, and only faces on that edge or at that vertex use it: a topology edit
    // re-plans every face at a vertex of a face it made, changed or removed (PlannedCage), so
    // only re-planned sub-faces, all in `changed`, can see a new owner. Elsewhere (a sub-face
    // that lost its surface re-plans nothing around it) every kept sub-face is compared.
    std::vector<char> ownersChanged(count, 0);
    if (!previousOf.empty()) {
        for (uint32_t s : changed)
            if (const uint32_t d = drawnOf[s]; d != UINT32_MAX && oldOf[d] != UINT32_MAX)
                ownersChanged[d] = !(ownersOf(data, d, previousOf) == ownersOf(old, oldOf[d]));
#ifndef NDEBUG
        for (uint32_t d = 0; d < count; ++d)
            assert((oldOf[d] == UINT32_MAX || ownersChanged[d] || ownersOf(data, d, previousOf) == ownersOf(old, oldOf[d])) &&
                   "a sub-face that was not re-planned sees a new owner");
#endif
    } else {
        tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 1024), [&](const tbb::blocked_range<uint32_t>& range) {
            for (uint32_t d = range.begin(); d != range.end(); ++d)
                ownersChanged[d] = oldOf[d] != UINT32_MAX && !(ownersOf(data, d) == ownersOf(old, oldOf[d]));
        });
    }
    bool sameStructure = true;  // every kept sub-face's edges split as before
    for (uint32_t d = 0; d < count; ++d) {
        if (oldOf[d] == UINT32_MAX) {
            refresh.push_back(d);
            continue;
        }
        if (!ownersChanged[d]) continue;
        const EdgeOwners now = ownersOf(data, d, previousOf), before = ownersOf(old, oldOf[d]);
        refresh.push_back(d);
        const GpuSubfaceBoundary& b = data.boundaries[d];
        for (uint32_t e = 0; e < 4; ++e) {
            sameStructure &= now.flags[e] == before.flags[e];
            refresh.push_back(data.segments[b.edges[e].segment].owner);
            if (b.edges[e].flags & kEdgeRefSplit) refresh.push_back(data.segments[b.edges[e].secondHalf].owner);
            refresh.push_back(data.boundaryPoints[b.corners[e]].owner);
        }
    }
    std::sort(refresh.begin(), refresh.end());
    refresh.erase(std::unique(refresh.begin(), refresh.end()), refresh.end());

    // The grid: the same factors for what was there, the old vertices moved to their new slots.
    GridLayout& layout = buffers.gridLayout;
    Status grid = success();
    if (!layout.subfaceOffset.empty() && layout.uniformRequest > 0 && buffers.displacement == nullptr) {
        // Uniform factors: what the next frame asks for is known; kept sub-faces must keep their
        // factor (their slots stay valid), and the pieces of edges split as before (an edge
        // split otherwise now has another owner: the sub-face is evaluated again anyway).
        GridFactors factors = uniformGridFactors(data, layout.uniformRequest);
        bool same = true;
        for (uint32_t d = 0; d < count && same; ++d) {
            if (oldOf[d] == UINT32_MAX) continue;
            same &= factors.subfaceFactor[d] == layout.factors.subfaceFactor[oldOf[d]];
            const GpuSubfaceBoundary &b = data.boundaries[d], &ob = old.boundaries[oldOf[d]];
            for (uint32_t e = 0; e < 4; ++e) {
                if (b.edges[e].flags != ob.edges[e].flags) continue;
                same &= factors.segmentPieces[b.edges[e].segment] == layout.factors.segmentPieces[ob.edges[e].segment];
                if (b.edges[e].flags & kEdgeRefSplit)
                    same &= factors.segmentPieces[b.edges[e].secondHalf] == layout.factors.segmentPieces[ob.edges[e].secondHalf];
            }
        }
        grid = same ? carryGrid(ctx, pass, buffers, std::move(factors), oldOf, ownersChanged) : dropGrid(buffers, update);
    } else if (!layout.subfaceOffset.empty()) {
        GridFactors factors;
        factors.segmentPieces.assign(data.segments.size(), 0);
        factors.subfaceFactor.assign(count, 0);
        bool known = sameStructure && buffers.displacement == nullptr;
        for (uint32_t d = 0; d < count && known; ++d) {
            if (oldOf[d] == UINT32_MAX) continue;
            factors.subfaceFactor[d] = layout.factors.subfaceFactor[oldOf[d]];
            const GpuSubfaceBoundary &b = data.boundaries[d], &ob = old.boundaries[oldOf[d]];
            for (uint32_t e = 0; e < 4; ++e) {
                factors.segmentPieces[b.edges[e].segment] = layout.factors.segmentPieces[ob.edges[e].segment];
                if (b.edges[e].flags & kEdgeRefSplit)
                    factors.segmentPieces[b.edges[e].secondHalf] = layout.factors.segmentPieces[ob.edges[e].secondHalf];
            }
        }
        for (uint32_t piece : factors.segmentPieces) known &= piece > 0;  // a segment only new sub-faces have
        for (uint32_t d = 0; d < count && known; ++d) {
            const GpuSubfaceBoundary& b = data.boundaries[d];
            uint32_t& n = factors.subfaceFactor[d];
            for (uint32_t e = 0; e < 4; ++e) {
                const uint32_t pieces = factors.segmentPieces[b.edges[e].segment] * ((b.edges[e].flags & kEdgeRefSplit) ? 2 : 1);
                if (oldOf[d] == UINT32_MAX) n = std::max(n, pieces);  // the adaptive rule (uniform: equal)
                else known &= n % pieces == 0;
            }
        }
        grid = known ? carryGrid(ctx, pass, buffers, std::move(factors), oldOf, ownersChanged) : dropGrid(buffers, update);
    }

    ringUsers.wait();
    if (!grid) return grid;
    buffers.drawnOfSubface = std::move(drawnOf);
    const VkDeviceSize listBytes = (2 * VkDeviceSize(count) + 4) * sizeof(uint32_t);
    if (listBytes > buffers.updateList.size && !data.hostEvaluation) {
        Result<Buffer> list = createBuffer(ctx, listBytes + listBytes / 2,
                                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT);
        if (!list) return list.error();
        destroyBuffer(ctx, buffers.updateList);
        buffers.updateList = *list;
        rebind = true;
    }
    Status stored = storeTail(ctx, buffers.subfaces, data.subfaces, 0, rebind);
    if (!data.hostEvaluation) {  // what only the device's evaluation and tessellator read
        if (stored) stored = storeTail(ctx, buffers.rings, data.rings, 0, rebind);
        if (stored) stored = storeTail(ctx, buffers.boundaries, data.boundaries, 0, rebind);
        if (stored) stored = storeTail(ctx, buffers.segments, data.segments, 0, rebind);
        if (stored) stored = storeTail(ctx, buffers.boundaryPoints, data.boundaryPoints, 0, rebind);
    }
    update.rewrittenSubfaces = count;
    return stored;
}

}  // namespace

Result<PlanTableUpdate> updatePlanTables(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers,
                                         const PlannedCage& planned, std::span<const uint32_t> subfaces,
                                         std::span<const uint32_t> previousSubfaceOf) {
    PlanTableUpdate update;
    GpuPlanData& data = buffers.data;
    const PlanDatabase& database = planned.database();
    const bool renumbered = !previousSubfaceOf.empty();
    if (renumbered && previousSubfaceOf.size() != planned.subfaceCount()) {
        update.reason = "the renumbering does not match the cage's sub-faces";
        return update;
    }
    if (renumbered && buffers.displacement) {
        update.reason = "a displacement is set (its tiles follow the old sub-faces)";
        return update;
    }
    if (!renumbered && buffers.drawnOfSubface.size() != planned.subfaceCount()) {
        update.reason = "the cage's sub-faces were renumbered";
        return update;
    }
    std::vector<uint32_t> changed(subfaces.begin(), subfaces.end());
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());

    // Check everything first, so that a change this cannot apply leaves the buffers untouched.
    bool drawnSetChanged = renumbered;
    for (uint32_t s : changed) {
        if (renumbered) break;  // every table is packed again
        const uint32_t drawn = buffers.drawnOfSubface[s];
        if (planned.hasPlannedSurface(s) != (drawn != UINT32_MAX)) {
            drawnSetChanged = true;
            continue;
        }
        if (drawn != UINT32_MAX && !ringUsersMatch(data, drawn, planned.subfaceRing(s))) {
            update.reason = "the 1-ring of sub-face " + std::to_string(s) + " changed";
            return update;
        }
    }

    // Control-point capacities as packPlans laid them out, the first time.
    std::vector<uint32_t>& capacity = buffers.controlPointCapacity;
    if (capacity.size() != data.subfaces.size()) {
        capacity.resize(data.subfaces.size());
        for (uint32_t d = 0; d < data.subfaces.size(); ++d) capacity[d] = database.plan(data.subfaces[d].plan).stencilCount();
    }

    bool rebind = false;
    if (Status s = appendNewPlans(ctx, buffers, database, update, rebind); !s) {
        if (rebind)
            if (Status bound = bindPlanBuffers(ctx, pass, buffers); !bound) return bound.error();
        return s.error();
    }
    if (renumbered) {  // the cage's vertices, edges and faces have new numbers too
        buffers.pointPositionsHost = boundaryPointPositions(planned);
        buffers.adaptiveInputs = {};
        if (!buffers.data.hostEvaluation) {
            Status stored = storeTail(ctx, buffers.positions, cagePositions(planned), 0, rebind);
            if (stored) stored = storeTail(ctx, buffers.pointPositions, buffers.pointPositionsHost, 0, rebind);
            if (!stored) return stored.error();
        }
    }
    if (drawnSetChanged) {
        if (Status s = repackDrawnSet(ctx, pass, buffers, planned, changed, previousSubfaceOf, update, rebind); !s)
            return s.error();
    } else {
        // Records, rings and control-point ranges of the changed sub-faces, where they are.
        for (uint32_t s : changed) {
            const uint32_t drawn = buffers.drawnOfSubface[s];
            if (drawn == UINT32_MAX) continue;
            GpuSubface& record = data.subfaces[drawn];
            record.plan = planned.subfacePlan(s);
            record.rotation = planned.subfaceRotation(s);
            if (!data.hostEvaluation) {  // the same vertices, perhaps in another order
                const std::span<const uint32_t> ring = planned.subfaceRing(s);
                std::copy(ring.begin(), ring.end(), data.rings.begin() + record.ringOffset);
                uploadBuffer(buffers.rings, ring.data(), ring.size_bytes(), size_t(record.ringOffset) * sizeof(uint32_t));
            }
            const uint32_t stencils = database.plan(record.plan).stencilCount();
            if (stencils > capacity[drawn]) {
                record.cpOffset = data.controlPointCount;
                data.controlPointCount += stencils;
                capacity[drawn] = stencils;
                ++update.relocatedSubfaces;
            }
            update.refresh.push_back(drawn);
            ++update.rewrittenSubfaces;
        }
        std::sort(update.refresh.begin(), update.refresh.end());
    }

    // Pack the ranges again once more than half of the buffer is garbage.
    uint64_t live = 0;
    for (uint32_t c : capacity) live += c;
    if (data.controlPointCount > 4096 && uint64_t(data.controlPointCount) > 2 * live) {
        uint32_t next = 0;
        for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
            data.subfaces[d].cpOffset = next;
            capacity[d] = database.plan(data.subfaces[d].plan).stencilCount();
            next += capacity[d];
        }
        data.controlPointCount = next;
        buffers.controlPointLevel = kNoControlPoints;  // every range moved: recomputed at the next draw
        update.compacted = true;
    }
    const VkDeviceSize controlBytes = VkDeviceSize(std::max(data.controlPointCount, 1u)) * sizeof(glm::vec4);
    if (controlBytes > buffers.controlPoints.size && !data.hostEvaluation) {
        Result<Buffer> bigger = createBuffer(ctx, controlBytes + controlBytes / 2, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
        if (!bigger) return bigger.error();
        // Cached control points stay valid where they are (coherent, mapped memory).
        std::memcpy(bigger->data, buffers.controlPoints.data, buffers.controlPoints.size);
        destroyBuffer(ctx, buffers.controlPoints);
        buffers.controlPoints = *bigger;
        rebind = true;
    }
    if (update.compacted || drawnSetChanged) uploadBuffer(buffers.subfaces, data.subfaces.data(), bytesOf(data.subfaces));
    else
        for (uint32_t drawn : update.refresh)
            uploadBuffer(buffers.subfaces, &data.subfaces[drawn], sizeof(GpuSubface), size_t(drawn) * sizeof(GpuSubface));
    updateHoleDrawn(buffers, planned);
    if (rebind)
        if (Status s = bindPlanBuffers(ctx, pass, buffers); !s) return s.error();
    update.applied = true;
    return update;
}

}  // namespace qp
