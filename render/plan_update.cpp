#include "plan_update.h"

#include <algorithm>

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

bool sameVertices(std::span<const uint32_t> a, std::span<const uint32_t> b) {
    if (a.size() != b.size()) return false;
    std::vector<uint32_t> x(a.begin(), a.end()), y(b.begin(), b.end());
    std::sort(x.begin(), x.end());
    std::sort(y.begin(), y.end());
    return x == y;
}

}  // namespace

Result<PlanTableUpdate> updatePlanTables(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers,
                                         const PlannedCage& planned, std::span<const uint32_t> subfaces) {
    PlanTableUpdate update;
    GpuPlanData& data = buffers.data;
    const PlanDatabase& database = planned.database();
    if (buffers.drawnOfSubface.size() != planned.subfaceCount()) {
        update.reason = "the cage's sub-faces were renumbered";
        return update;
    }
    std::vector<uint32_t> changed(subfaces.begin(), subfaces.end());
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());

    // Check everything first, so that a change this cannot apply leaves the buffers untouched.
    for (uint32_t s : changed) {
        const uint32_t drawn = buffers.drawnOfSubface[s];
        if (planned.hasSurface(s) != (drawn != UINT32_MAX)) {
            update.reason = "sub-face " + std::to_string(s) + (drawn == UINT32_MAX ? " gained" : " lost") + " its surface";
            return update;
        }
        if (drawn == UINT32_MAX) continue;
        const uint32_t end = drawn + 1 < data.subfaces.size() ? data.subfaces[drawn + 1].ringOffset : uint32_t(data.rings.size());
        const std::span<const uint32_t> old(data.rings.data() + data.subfaces[drawn].ringOffset, end - data.subfaces[drawn].ringOffset);
        if (!sameVertices(old, planned.subfaceRing(s))) {
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

    // Plans new to the database.
    const size_t oldPlans = data.plans.size(), oldNodes = data.nodes.size(), oldPoints = data.points.size(),
                 oldWeights = data.weights.size();
    appendPlanTables(data, database);
    update.appendedPlans = uint32_t(data.plans.size() - oldPlans);
    bool rebind = false;
    if (update.appendedPlans > 0) {
        Status stored = storeTail(ctx, buffers.planHeaders, data.plans, oldPlans, rebind);
        if (stored) stored = storeTail(ctx, buffers.nodes, data.nodes, oldNodes, rebind);
        if (stored) stored = storeTail(ctx, buffers.points, data.points, oldPoints, rebind);
        if (stored) stored = storeTail(ctx, buffers.weights, data.weights, oldWeights, rebind);
        if (!stored) {
            // Tables that grew already hold the new plans too; the rest is as before.
            data.plans.resize(oldPlans);
            data.nodes.resize(oldNodes);
            data.points.resize(oldPoints);
            data.weights.resize(oldWeights);
            if (rebind) bindPlanBuffers(ctx, pass, buffers);
            return stored.error();
        }
    }

    // Records, rings and control-point ranges of the changed sub-faces.
    uint64_t live = 0;
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) live += capacity[d];
    for (uint32_t s : changed) {
        const uint32_t drawn = buffers.drawnOfSubface[s];
        if (drawn == UINT32_MAX) continue;
        GpuSubface& record = data.subfaces[drawn];
        record.plan = planned.subfacePlan(s);
        record.rotation = planned.subfaceRotation(s);
        const std::span<const uint32_t> ring = planned.subfaceRing(s);
        std::copy(ring.begin(), ring.end(), data.rings.begin() + record.ringOffset);
        uploadBuffer(buffers.rings, ring.data(), ring.size_bytes(), size_t(record.ringOffset) * sizeof(uint32_t));
        const uint32_t stencils = database.plan(record.plan).stencilCount();
        if (stencils > capacity[drawn]) {
            live += stencils - capacity[drawn];
            record.cpOffset = data.controlPointCount;
            data.controlPointCount += stencils;
            capacity[drawn] = stencils;
            ++update.relocatedSubfaces;
        }
        update.refresh.push_back(drawn);
        ++update.rewrittenSubfaces;
    }
    std::sort(update.refresh.begin(), update.refresh.end());

    // Pack the ranges again once more than half of the buffer is garbage.
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
    if (controlBytes > buffers.controlPoints.size) {
        Result<Buffer> bigger = createBuffer(ctx, controlBytes + controlBytes / 2, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
        if (!bigger) return bigger.error();
        // Cached control points stay valid where they are (coherent, mapped memory).
        std::copy_n(static_cast<const char*>(buffers.controlPoints.data), buffers.controlPoints.size,
                    static_cast<char*>(bigger->data));
        destroyBuffer(ctx, buffers.controlPoints);
        buffers.controlPoints = *bigger;
        rebind = true;
    }
    if (update.compacted) uploadBuffer(buffers.subfaces, data.subfaces.data(), bytesOf(data.subfaces));
    else
        for (uint32_t drawn : update.refresh)
            uploadBuffer(buffers.subfaces, &data.subfaces[drawn], sizeof(GpuSubface), size_t(drawn) * sizeof(GpuSubface));
    if (rebind) bindPlanBuffers(ctx, pass, buffers);
    update.applied = true;
    return update;
}

}  // namespace qp
