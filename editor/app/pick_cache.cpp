#include "pick_cache.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include <tbb/parallel_for.h>
// Header-only: the hash compiled in, no library to link.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace qp::editor {

namespace {

// What a sub-face's limit surface depends on besides its plan and rotation: its ring's positions.
uint64_t ringHash(const PlannedCage& planned, uint32_t subface) {
    const std::span<const uint32_t> ring = planned.subfaceRing(subface);
    glm::vec3 positions[64];
    if (ring.size() <= 64) {
        for (size_t i = 0; i < ring.size(); ++i) positions[i] = planned.cage().positions[ring[i]];
        return XXH3_64bits(positions, ring.size() * sizeof(glm::vec3));
    }
    uint64_t hash = 0;
    for (uint32_t v : ring) hash = XXH3_64bits_withSeed(&planned.cage().positions[v], sizeof(glm::vec3), hash);
    return hash;
}

std::vector<uint64_t> ringHashes(const PlannedCage& planned) {
    std::vector<uint64_t> out(planned.subfaceCount());
    tbb::parallel_for(uint32_t(0), planned.subfaceCount(), [&](uint32_t s) { out[s] = ringHash(planned, s); });
    return out;
}

std::vector<uint32_t> plansAndRotations(const PlannedCage& planned) {
    std::vector<uint32_t> out(2 * size_t(planned.subfaceCount()));
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
        // A hole keeps its plan (holes are planned as if they were not): it counts as no plan.
        out[2 * s] = planned.hasSurface(s) ? planned.subfacePlan(s) : kNoPlan;
        out[2 * s + 1] = planned.subfaceRotation(s);
    }
    return out;
}

void resetIfStale(PickCache& c, const Document& doc, uint64_t generation) {
    if (c.generation == generation && c.planRevision == doc.planRevision) return;
    if (c.generation == generation && c.topologyRevision == doc.topologyRevision && c.limit &&
        c.limitPlans.size() == 2 * size_t(doc.planned->subfaceCount())) {
        // Tags changed, the numbering did not: the limit picker re-samples just the sub-faces
        // whose plan (a hole has none) or rotation changed; the cage raycaster does not care.
        const std::vector<uint32_t> now = plansAndRotations(*doc.planned);
        for (uint32_t s = 0; s < doc.planned->subfaceCount(); ++s)
            if (now[2 * s] != c.limitPlans[2 * s] || now[2 * s + 1] != c.limitPlans[2 * s + 1]) {
                c.replanned.push_back(s);
                c.displacedReplanned.push_back(s);
            }
        c.limitPlans = now;
        c.planRevision = doc.planRevision;
        return;
    }
    std::optional<LimitPicker> carried;
    std::vector<uint32_t> carriedPlans;
    std::vector<uint64_t> carriedRings;
    if (c.generation == generation && c.limit && c.topologySinceRevision == doc.topologyRevision &&
        c.topologySince.topologyChanged && c.topologySince.previousSubfaceOf.size() == doc.planned->subfaceCount()) {
        // Topology edits the cache was told of: kept sub-faces keep their samples unless their plan,
        // rotation or ring positions differ from when they were sampled (in the old numbering).
        const PlannedCage& planned = *doc.planned;
        carriedPlans = plansAndRotations(planned);
        carriedRings = ringHashes(planned);
        EditReport report;
        report.topologyChanged = true;
        report.previousSubfaceOf = c.topologySince.previousSubfaceOf;
        const size_t before = c.limitRings.size();
        std::vector<char> replannedBefore(before, 0);  // re-planned, not re-sampled yet
        for (uint32_t s : c.replanned) replannedBefore[s] = 1;
        for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
            const uint32_t previous = report.previousSubfaceOf[s];
            if (previous >= before) continue;  // new: sampled anyway
            if (replannedBefore[previous] || carriedPlans[2 * s] != c.limitPlans[2 * previous] ||
                carriedPlans[2 * s + 1] != c.limitPlans[2 * previous + 1] || carriedRings[s] != c.limitRings[previous])
                report.updatedSubfaceList.push_back(s);
        }
        c.limit->update(planned, report);
        carried = std::move(c.limit);
    }
    const uint32_t builds = c.limitBuilds, displacedBuilds = c.displacedBuilds;
    c = PickCache{};
    c.limitBuilds = builds;
    c.displacedBuilds = displacedBuilds;
    if (carried) {
        c.limit = std::move(carried);
        c.limitPlans = std::move(carriedPlans);
        c.limitRings = std::move(carriedRings);
        c.limitPositions = doc.planned->cage().positions;
        c.limitRevision = doc.positionRevision;
    }
    c.generation = generation;
    c.planRevision = doc.planRevision;
    c.topologyRevision = doc.topologyRevision;
    std::vector<uint32_t> all(doc.planned->subfaceCount());
    std::iota(all.begin(), all.end(), 0u);
    c.index = VertexSubfaceIndex(*doc.planned, all);
}

}  // namespace

namespace {

// The vertices that moved since revision `seen`, whose positions `copy` holds, with `copy`
// brought up to date: the document's position step when it leads from there (the moved
// vertices alone), else every position compared.
std::vector<uint32_t> catchUpPositions(const Document& doc, uint64_t seen, std::vector<glm::vec3>& copy) {
    const std::vector<glm::vec3>& positions = doc.planned->cage().positions;
    if (seen == doc.positionRevision && copy.size() == positions.size()) return {};
    if (doc.lastMove.leads(seen, doc.positionRevision) && copy.size() == positions.size()) {
        for (uint32_t v : doc.lastMove.vertices) copy[v] = positions[v];
        return doc.lastMove.vertices;
    }
    std::vector<uint32_t> moved = movedVertices(copy, positions);
    copy = positions;
    return moved;
}

}  // namespace

const CageRaycaster& cageRaycaster(PickCache& c, const Document& doc, uint64_t generation) {
    resetIfStale(c, doc, generation);
    const bool noneMoved = doc.lastMove.leads(c.cageRevision, doc.positionRevision) && doc.lastMove.vertices.empty();
    if (!c.cage || (c.cageRevision != doc.positionRevision && !noneMoved)) c.cage.emplace(doc.planned->cage());
    c.cageRevision = doc.positionRevision;
    return *c.cage;
}

void noteTopologyChange(PickCache& c, const Document& doc, const EditReport& change) {
    if (!change.topologyChanged || !c.limit) return;
    if (c.topologySinceRevision == ~0ull) c.topologySince = change;
    else accumulateReport(c.topologySince, change);
    c.topologySinceRevision = doc.topologyRevision;
}

const LimitPicker& limitPicker(PickCache& c, const Document& doc, uint64_t generation) {
    resetIfStale(c, doc, generation);
    const auto start = std::chrono::steady_clock::now();
    if (!c.limit) {
        c.limit.emplace(*doc.planned, LimitPicker::resolutionFor(doc.planned->subfaceCount()));
        ++c.limitBuilds;
        c.limitPlans = plansAndRotations(*doc.planned);
        c.limitRings = ringHashes(*doc.planned);
        c.replanned.clear();
        c.limitPositions = doc.planned->cage().positions;
    } else if (c.limitRevision != doc.positionRevision || !c.replanned.empty()) {
        EditReport changed;  // the sub-faces whose control points or plans changed
        changed.updatedSubfaceList = c.index.touched(catchUpPositions(doc, c.limitRevision, c.limitPositions));
        changed.updatedSubfaceList.insert(changed.updatedSubfaceList.end(), c.replanned.begin(), c.replanned.end());
        std::sort(changed.updatedSubfaceList.begin(), changed.updatedSubfaceList.end());
        changed.updatedSubfaceList.erase(std::unique(changed.updatedSubfaceList.begin(), changed.updatedSubfaceList.end()),
                                         changed.updatedSubfaceList.end());
        c.replanned.clear();
        c.limit->update(*doc.planned, changed);
        for (uint32_t s : changed.updatedSubfaceList) c.limitRings[s] = ringHash(*doc.planned, s);
    } else {
        return *c.limit;
    }
    c.limitRevision = doc.positionRevision;
    c.lastLimitMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return *c.limit;
}

namespace {

// The end of the document's stream of changed samples (Document::takenSamples).
uint64_t sampleStreamEnd(const Document& doc) {
    return doc.takenBefore + doc.takenSamples.size() + doc.unsyncedSamples.size();
}

// The samples listed in the stream from `from` on (repeats allowed); `from` must not lie
// before what the document still keeps.
std::vector<uint32_t> sampleStreamFrom(const Document& doc, uint64_t from) {
    const size_t taken = size_t(from - doc.takenBefore);
    std::vector<uint32_t> out;
    if (taken < doc.takenSamples.size()) out.assign(doc.takenSamples.begin() + std::ptrdiff_t(taken), doc.takenSamples.end());
    const size_t unsynced = taken > doc.takenSamples.size() ? taken - doc.takenSamples.size() : 0;
    if (unsynced < doc.unsyncedSamples.size())
        out.insert(out.end(), doc.unsyncedSamples.begin() + std::ptrdiff_t(unsynced), doc.unsyncedSamples.end());
    return out;
}

void sortUnique(std::vector<uint32_t>& list) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
}

}  // namespace

const DisplacedPicker& displacedPicker(PickCache& c, const Document& doc, uint64_t generation) {
    resetIfStale(c, doc, generation);
    const Displacement& displacement = displacementOf(doc);
    const auto start = std::chrono::steady_clock::now();
    // A new layout (new, resampled, cleared displacement), a lost picker, or changes the
    // document no longer lists (the picker fell far behind): sample everything.
    const bool rebuild = !c.displaced || c.displacedLayout != doc.displacementRevision ||
                         c.displacedSampleStream < doc.takenBefore || c.displacedSampleStream > sampleStreamEnd(doc);
    if (rebuild) {
        c.displaced.emplace(*doc.planned, displacement);
        ++c.displacedBuilds;
        c.displacedReplanned.clear();
        c.displacedPositions = doc.planned->cage().positions;
    } else {
        const bool moved = c.displacedRevision != doc.positionRevision || !c.displacedReplanned.empty();
        const bool painted = c.displacedSampleRevision != doc.sampleRevision;
        if (!moved && !painted) return *c.displaced;
        if (moved) {  // the limit surface changed under these sub-faces
            std::vector<uint32_t> stale = c.index.touched(catchUpPositions(doc, c.displacedRevision, c.displacedPositions));
            stale.insert(stale.end(), c.displacedReplanned.begin(), c.displacedReplanned.end());
            sortUnique(stale);
            c.displacedReplanned.clear();
            if (!stale.empty()) c.displaced->updateSubfaces(*doc.planned, displacement, stale);
        }
        if (painted) {
            const std::vector<uint32_t> samples = sampleStreamFrom(doc, c.displacedSampleStream);
            if (!samples.empty()) c.displaced->updateSamples(*doc.planned, displacement, samples);
        }
    }
    c.displacedSampleStream = sampleStreamEnd(doc);
    c.displacedRevision = doc.positionRevision;
    c.displacedLayout = doc.displacementRevision;
    c.displacedSampleRevision = doc.sampleRevision;
    c.lastDisplacedMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return *c.displaced;
}

float pickTolerance(const Document& doc) { return std::max(cageExtent(doc).bounds.diagonal(), 1e-6f); }

}  // namespace qp::editor
