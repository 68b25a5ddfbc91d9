#include "pick_cache.h"

#include <chrono>
#include <numeric>

namespace qp::editor {

namespace {

void resetIfStale(PickCache& c, const Document& doc, uint64_t generation) {
    if (c.generation == generation && c.planRevision == doc.planRevision) return;
    c = PickCache{};
    c.generation = generation;
    c.planRevision = doc.planRevision;
    std::vector<uint32_t> all(doc.planned->subfaceCount());
    std::iota(all.begin(), all.end(), 0u);
    c.index = VertexSubfaceIndex(*doc.planned, all);
}

}  // namespace

const CageRaycaster& cageRaycaster(PickCache& c, const Document& doc, uint64_t generation) {
    resetIfStale(c, doc, generation);
    if (!c.cage || c.cageRevision != doc.positionRevision) {
        c.cage.emplace(doc.planned->cage());
        c.cageRevision = doc.positionRevision;
    }
    return *c.cage;
}

const LimitPicker& limitPicker(PickCache& c, const Document& doc, uint64_t generation) {
    resetIfStale(c, doc, generation);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<glm::vec3>& positions = doc.planned->cage().positions;
    if (!c.limit) {
        c.limit.emplace(*doc.planned);
    } else if (c.limitRevision != doc.positionRevision) {
        EditReport moved;  // the sub-faces whose control points changed
        moved.updatedSubfaceList = c.index.touched(movedVertices(c.limitPositions, positions));
        c.limit->update(*doc.planned, moved);
    } else {
        return *c.limit;
    }
    c.limitPositions = positions;
    c.limitRevision = doc.positionRevision;
    c.lastLimitMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return *c.limit;
}

float pickTolerance(const Document& doc) { return std::max(computeBounds(doc.planned->cage()).diagonal(), 1e-6f); }

}  // namespace qp::editor
