#include "plans/planned_cage.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cmath>
#include <future>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mesh/local_cage.h"
#include "plans/corner_frame.h"
#include "plans/memory_estimate.h"
#include "plans/osd_refiner.h"

namespace qp {

namespace {

// Runs body(begin, end) over ranges of [0, count), each on one thread, which fetches its
// per-thread state once for the range (a thread-local of this shared library is a call each
// time it is reached: twice a sub-face was 1.7% of a million-face `plan-stats`' samples). On all
// cores for large counts; inline for the handful of sub-faces a local edit touches, where waking
// worker threads costs more than the work (and on a busy machine a descheduled worker can hold
// the edit up for milliseconds).
template <class Body>
void forEachRange(size_t count, const Body& body) {
    if (count < 64) {
        body(size_t(0), count);
    } else {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count),
                          [&](const tbb::blocked_range<size_t>& range) { body(range.begin(), range.end()); });
    }
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Planning at least this many sub-faces hands the heap's free pages back afterwards (0.3-9 ms at
// a million faces; nothing worth it on small cages).
constexpr uint32_t kReleaseAfterSubfaces = 1u << 16;
// Planning at least this many sub-faces first makes a GatherIndex of the cage.
constexpr size_t kGatherIndexAfterSubfaces = 4096;

// A fresh PlannedCage::controlPointsGeneration_: unique across every planned cage of the process.
uint64_t nextControlPointsGeneration() {
    static std::atomic<uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

Result<PlannedCage> PlannedCage::create(Cage cage, PlanDatabase& database, const PlanOptions& options,
                                        const std::string& source) {
    if (Status valid = validateCage(cage, source); !valid) return valid.error();
    if (options.maxDepth < 1 || options.maxDepth > kMaxPlanDepth)
        return Error{"plan depth must be between 1 and " + std::to_string(kMaxPlanDepth)};
    // Refused before the plans take the memory (a million faces need about 2 GiB).
    if (Status memory = checkMemory(planningBytesEstimate(cage), availableMemoryBytes(),
                                    "planning " + source + " (" + std::to_string(cage.faceCount()) + " faces)");
        !memory)
        return memory.error();

    PlannedCage planned;
    planned.cage_ = std::move(cage);
    // Whether OpenSubdiv accepts the whole topology is asked beside the planning, on a thread of
    // its own (a third of a second on one core at a million faces; about 0.1 s of it is hidden in
    // the planning's serial steps, the rest shares the cores); its verdict comes first.
    std::future<Status> accepted = std::async(std::launch::async, [&planned, &source]() -> Status {
        if (auto refiner = createRefiner(planned.cage_, source); !refiner) return refiner.error();
        return success();
    });
    planned.topology_ = buildTopology(planned.cage_);
    planned.options_ = options;
    planned.database_ = &database;
    planned.source_ = source;
    std::vector<uint32_t> noOldFaces(planned.cage_.faceCount(), UINT32_MAX);
    planned.remapSubfaces(noOldFaces);

    std::vector<uint32_t> all(planned.cage_.faceCount());
    for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
    EditReport report;
    const Status planning = planned.replanFaces(all, report);
    if (Status status = accepted.get(); !status) return status.error();
    if (!planning) return planning.error();
    if (planned.subfaceCount() >= kReleaseAfterSubfaces) releaseFreedMemory();
    return planned;
}

std::span<const uint32_t> PlannedCage::subfaceRing(uint32_t subface) const { return subfaceRing_[subface]; }

std::span<const glm::vec3> PlannedCage::storedControlPoints(uint32_t subface) const {
    return subfaceControlPoints_[subface];
}

std::span<const glm::vec3> PlannedCage::controlPointsFor(uint32_t subface, uint32_t level,
                                                         std::vector<glm::vec3>& scratch) const {
    const std::vector<glm::vec3>& stored = subfaceControlPoints_[subface];
    if (level <= kStoredControlPointLevel || subfacePlan_[subface] == kNoPlan) return stored;
    const Plan& plan = database_->plan(subfacePlan_[subface]);
    if (stored.size() == plan.stencilCount()) return stored;
    const std::span<const uint32_t> ring = subfaceRing_[subface];
    scratch.resize(ring.size() + plan.stencilCount());
    glm::vec3* positions = scratch.data() + plan.stencilCount();
    const glm::vec3 origin = subfaceOrigin(subface);
    for (size_t j = 0; j < ring.size(); ++j) positions[j] = cage_.positions[ring[j]] - origin;
    applyStencils(plan, positions, plan.stencilCount(), scratch.data());
    return {scratch.data(), plan.stencilCount()};
}

std::vector<uint32_t> PlannedCage::remapSubfaces(const std::vector<uint32_t>& oldFaceOf) {
    const std::vector<uint32_t> oldFirst = std::move(faceFirstSubface_);
    faceFirstSubface_.assign(cage_.faceCount() + 1, 0);
    for (uint32_t f = 0; f < cage_.faceCount(); ++f)
        faceFirstSubface_[f + 1] = faceFirstSubface_[f] + qp::subfaceCount(cage_.faceSize(f));
    const uint32_t count = faceFirstSubface_.back();
    std::vector<uint32_t> previousSubfaceOf(count, kNewElement);
    for (uint32_t f = 0; f < cage_.faceCount(); ++f) {
        const uint32_t old = oldFaceOf[f];
        if (old == UINT32_MAX) continue;
        const uint32_t subfaces = faceFirstSubface_[f + 1] - faceFirstSubface_[f];
        if (subfaces != oldFirst[old + 1] - oldFirst[old]) continue;  // a changed face: re-planned anyway
        for (uint32_t k = 0; k < subfaces; ++k) previousSubfaceOf[faceFirstSubface_[f] + k] = oldFirst[old] + k;
    }

    // Kept sub-faces move in place (a one-face edit moves few or none, where moving every ring
    // into new arrays cost as much as the rest of the edit): kept faces keep their order, so
    // those moving down go first in ascending order, then those moving up in descending order,
    // and no entry is overwritten before it has moved.
    const uint32_t oldCount = uint32_t(subfacePlan_.size()), room = std::max(count, oldCount);
    subfacePlan_.resize(room, kNoPlan);
    subfaceRotation_.resize(room, 0);
    subfaceRing_.resize(room);
    subfaceControlPoints_.resize(room);
    std::vector<char> filled(room, 0);
    auto move = [&](uint32_t to) {
        const uint32_t from = previousSubfaceOf[to];
        filled[to] = 1;
        if (from == to) return;
        subfacePlan_[to] = subfacePlan_[from];
        subfaceRotation_[to] = subfaceRotation_[from];
        subfaceRing_[to] = std::move(subfaceRing_[from]);
        subfaceControlPoints_[to] = std::move(subfaceControlPoints_[from]);
    };
    for (uint32_t to = 0; to < count; ++to)
        if (previousSubfaceOf[to] != kNewElement && previousSubfaceOf[to] >= to) move(to);
    for (uint32_t to = count; to-- > 0;)
        if (previousSubfaceOf[to] != kNewElement && previousSubfaceOf[to] < to) move(to);
    for (uint32_t to = 0; to < count; ++to) {  // nothing kept here: as a sub-face never planned
        if (filled[to]) continue;
        subfacePlan_[to] = kNoPlan;
        subfaceRotation_[to] = 0;
        subfaceRing_[to].clear();
        subfaceControlPoints_[to].clear();
    }
    subfacePlan_.resize(count);
    subfaceRotation_.resize(count);
    subfaceRing_.resize(count);
    subfaceControlPoints_.resize(count);
    subfaceHole_.assign(count, 0);
    controlPointsGeneration_ = nextControlPointsGeneration();  // the numbers now name other sub-faces
    for (uint32_t hole : cage_.holes)
        std::fill(subfaceHole_.begin() + faceFirstSubface_[hole], subfaceHole_.begin() + faceFirstSubface_[hole + 1], 1);
    return previousSubfaceOf;
}

Result<std::vector<PlannedCage::SubfacePlan>> PlannedCage::planFaces(const Cage& cage, const Topology& topology,
                                                                    const std::vector<uint32_t>& faces,
                                                                    EditReport& report) const {
    std::vector<std::pair<uint32_t, uint32_t>> work;  // (face, sub-face within it)
    for (uint32_t f : faces)
        for (uint32_t k = 0; k < qp::subfaceCount(cage.faceSize(f)); ++k) work.push_back({f, k});

    const uint64_t missesBefore = database_->misses();
    std::vector<SubfacePlan> plans(work.size());
    // The error of the first failing sub-face in `work`'s order, whichever thread finds it.
    std::mutex errorMutex;
    size_t firstFailed = SIZE_MAX;
    std::string firstError;
    // Worth its passes over the cage only when planning many faces (a million: the crease marks
    // 20-70 ms less, the rotated orbits about 140 ms); the orbits, arrays over the whole cage, only
    // when those faces are a quarter of it or more (not for an edit of thousands of faces of a
    // million).
    const bool indexed = work.size() >= kGatherIndexAfterSubfaces;
    const bool withOrbits = faces.size() * 4 >= cage.faceCount();
    const GatherIndex index = indexed ? buildGatherIndex(cage, topology, withOrbits) : GatherIndex{};
    forEachRange(work.size(), [&](size_t begin, size_t end) {
        GatherThread& thread = gatherThread();
        for (size_t i = begin; i < end; ++i) {
            const auto [face, k] = work[i];
            // The thread's own arrays: nothing below gathers again on this thread before they are read.
            const FaceConfig& config =
                gatherFaceConfig(thread, cage, topology, face, k, options_, indexed ? &index : nullptr);
            Result<uint32_t> id = database_->findOrBuild(config);
            if (id) {
                plans[i] = {*id, config.rotation, config.ring};
                continue;
            }
            // A hole has no surface to lose: it stays unplanned (and is planned when filled).
            if (cage.isHole(face)) continue;
            std::lock_guard<std::mutex> lock(errorMutex);
            if (i < firstFailed) {
                firstFailed = i;
                firstError = source_ + ": face " + std::to_string(face + 1) + ": " + id.error().message;
            }
        }
    });
    if (firstFailed != SIZE_MAX) return Error{firstError};
    report.newPlans += uint32_t(database_->misses() - missesBefore);
    return plans;
}

void PlannedCage::installPlans(const std::vector<uint32_t>& faces, std::vector<SubfacePlan>& plans, EditReport& report) {
    std::vector<uint32_t> subfaces;
    for (uint32_t f : faces)
        for (uint32_t s = faceFirstSubface_[f]; s < faceFirstSubface_[f + 1]; ++s) {
            SubfacePlan& p = plans[subfaces.size()];
            subfacePlan_[s] = p.plan;
            subfaceRotation_[s] = p.rotation;
            subfaceHole_[s] = cage_.isHole(f);
            subfaceRing_[s] = std::move(p.ring);
            subfaces.push_back(s);
        }
    updateControlPoints(subfaces);
    report.replannedFaceList.insert(report.replannedFaceList.end(), faces.begin(), faces.end());
    report.updatedSubfaceList.insert(report.updatedSubfaceList.end(), subfaces.begin(), subfaces.end());
}

Status PlannedCage::replanFaces(const std::vector<uint32_t>& faces, EditReport& report) {
    auto plans = planFaces(cage_, topology_, faces, report);
    if (!plans) return plans.error();
    installPlans(faces, *plans, report);
    return success();
}

void PlannedCage::updateControlPoints(const std::vector<uint32_t>& subfaces) {
    forEachRange(subfaces.size(), [&](size_t begin, size_t end) {
        thread_local std::vector<glm::vec3> spareRing;  // reused: an allocation per sub-face showed in profiles
        std::vector<glm::vec3>& ring = spareRing;
        for (size_t i = begin; i < end; ++i) {
            const uint32_t s = subfaces[i];
            if (subfacePlan_[s] == kNoPlan) {
                subfaceControlPoints_[s].clear();
                continue;
            }
            const Plan& plan = database_->plan(subfacePlan_[s]);
            ring.resize(subfaceRing_[s].size());
            const glm::vec3 origin = subfaceOrigin(s);
            for (size_t j = 0; j < ring.size(); ++j) ring[j] = cage_.positions[subfaceRing_[s][j]] - origin;
            const uint32_t stored = plan.stencilCountByLevel[kStoredControlPointLevel];
            subfaceControlPoints_[s].resize(stored);
            applyStencils(plan, ring.data(), stored, subfaceControlPoints_[s].data());
        }
    });
    controlPointsGeneration_ = nextControlPointsGeneration();
}

LimitSample PlannedCage::evaluate(uint32_t subface, float u, float v) const {
    const std::vector<glm::vec3>& stored = subfaceControlPoints_[subface];
    const uint32_t count = database_->plan(subfacePlan_[subface]).stencilCount();
    if (stored.size() == count) return evaluate(subface, stored, u, v);
    struct Computed {
        uint64_t generation = 0;
        uint32_t subface = 0;
        std::vector<glm::vec3> points;  // controlPointsFor's scratch: the control points first
    };
    thread_local Computed computed;
    if (computed.generation != controlPointsGeneration_ || computed.subface != subface) {
        controlPointsFor(subface, kMaxPlanDepth, computed.points);
        computed.generation = controlPointsGeneration_;
        computed.subface = subface;
    }
    return evaluate(subface, std::span<const glm::vec3>(computed.points.data(), count), u, v);
}

LimitSample PlannedCage::evaluate(uint32_t subface, std::span<const glm::vec3> controlPoints, float u, float v) const {
    uint32_t rotation = subfaceRotation_[subface];
    float pu, pv;
    toCornerFrame(rotation, u, v, pu, pv);
    LimitSample sample = evaluatePlan(database_->plan(subfacePlan_[subface]), controlPoints.data(), pu, pv);
    sample.position += subfaceOrigin(subface);
    derivativesToFaceFrame(rotation, sample.du, sample.dv);
    return sample;
}

std::vector<uint32_t> PlannedCage::facesSharingVertexWith(std::span<const uint32_t> vertices) const {
    std::vector<uint32_t> faces;
    for (uint32_t v : vertices)
        for (uint32_t k = topology_.vertexFaceOffsets[v]; k < topology_.vertexFaceOffsets[v + 1]; ++k)
            faces.push_back(topology_.vertexFaces[k]);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    return faces;
}

std::vector<uint32_t> PlannedCage::subfacesSeeing(std::span<const uint32_t> vertices) const {
    // Faces whose 1-ring holds v: the faces at any vertex of a face at v.
    std::vector<uint32_t> touching = facesSharingVertexWith(vertices);
    std::vector<uint32_t> ringVertices;
    for (uint32_t f : touching) ringVertices.insert(ringVertices.end(), cage_.faceBegin(f), cage_.faceBegin(f) + cage_.faceSize(f));
    std::sort(ringVertices.begin(), ringVertices.end());
    ringVertices.erase(std::unique(ringVertices.begin(), ringVertices.end()), ringVertices.end());
    std::vector<uint32_t> subfaces;
    for (uint32_t f : facesSharingVertexWith(ringVertices))
        for (uint32_t s = faceFirstSubface_[f]; s < faceFirstSubface_[f + 1]; ++s) subfaces.push_back(s);
    return subfaces;
}

namespace {

void sortUnique(std::vector<uint32_t>& list) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
}

EditReport finished(EditReport report, std::chrono::steady_clock::time_point start) {
    sortUnique(report.replannedFaceList);
    sortUnique(report.updatedSubfaceList);
    report.replannedFaces = uint32_t(report.replannedFaceList.size());
    report.updatedSubfaces = uint32_t(report.updatedSubfaceList.size());
    report.milliseconds = millisecondsSince(start);
    return report;
}

Status checkSharpness(float sharpness, const char* what) {
    if (!std::isfinite(sharpness) || sharpness < 0.0f)
        return Error{std::string(what) + " sharpness must be a number >= 0 (got " + std::to_string(sharpness) + ")"};
    return success();
}

}  // namespace

namespace {

// `list` (sorted, in the numbering before an edit) in the numbering after it, by `previousOf`.
std::vector<uint32_t> carriedThrough(const std::vector<uint32_t>& list, const std::vector<uint32_t>& previousOf) {
    std::vector<uint32_t> out;
    for (uint32_t now = 0; now < previousOf.size(); ++now)
        if (previousOf[now] != kNewElement && std::binary_search(list.begin(), list.end(), previousOf[now])) out.push_back(now);
    return out;
}

// previousOf of two edits in a row: after the second -> before the first.
std::vector<uint32_t> composed(const std::vector<uint32_t>& first, const std::vector<uint32_t>& second) {
    std::vector<uint32_t> out(second.size(), kNewElement);
    for (size_t i = 0; i < second.size(); ++i)
        if (second[i] != kNewElement && second[i] < first.size()) out[i] = first[second[i]];
    return out;
}

}  // namespace

void accumulateReport(EditReport& into, const EditReport& next) {
    into.newPlans += next.newPlans;
    into.milliseconds += next.milliseconds;
    if (next.topologyChanged) {
        into.replannedFaceList = carriedThrough(into.replannedFaceList, next.previousFaceOf);
        into.updatedSubfaceList = carriedThrough(into.updatedSubfaceList, next.previousSubfaceOf);
        into.previousFaceOf = into.topologyChanged ? composed(into.previousFaceOf, next.previousFaceOf) : next.previousFaceOf;
        into.previousSubfaceOf =
            into.topologyChanged ? composed(into.previousSubfaceOf, next.previousSubfaceOf) : next.previousSubfaceOf;
        into.topologyChanged = true;
    }
    into.replannedFaceList.insert(into.replannedFaceList.end(), next.replannedFaceList.begin(), next.replannedFaceList.end());
    into.updatedSubfaceList.insert(into.updatedSubfaceList.end(), next.updatedSubfaceList.begin(), next.updatedSubfaceList.end());
    sortUnique(into.replannedFaceList);
    sortUnique(into.updatedSubfaceList);
    into.replannedFaces = uint32_t(into.replannedFaceList.size());
    into.updatedSubfaces = uint32_t(into.updatedSubfaceList.size());
}

Result<EditReport> PlannedCage::moveVertices(std::span<const uint32_t> vertices, std::span<const glm::vec3> positions) {
    auto start = std::chrono::steady_clock::now();
    if (vertices.size() != positions.size()) return Error{"moveVertices: one position per vertex is needed"};
    for (size_t i = 0; i < vertices.size(); ++i) {
        if (vertices[i] >= cage_.vertexCount())
            return Error{"vertex " + std::to_string(vertices[i] + 1) + " does not exist"};
        const glm::vec3& p = positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return Error{"cannot move vertex " + std::to_string(vertices[i] + 1) + " to a NaN or infinite position"};
    }
    for (size_t i = 0; i < vertices.size(); ++i) cage_.positions[vertices[i]] = positions[i];

    EditReport report;
    report.updatedSubfaceList = movesEveryVertex(vertices) ? allSubfaces() : subfacesSeeing(vertices);
    updateControlPoints(report.updatedSubfaceList);
    return finished(std::move(report), start);
}

// A whole-body deformation (an animation frame) moves every vertex: then every sub-face sees one,
// and finding them through the faces around each vertex (three sorts of the whole cage) is skipped.
bool PlannedCage::movesEveryVertex(std::span<const uint32_t> vertices) const {
    if (vertices.size() < cage_.vertexCount()) return false;
    std::vector<uint8_t> moved(cage_.vertexCount(), 0);
    uint32_t distinct = 0;
    for (uint32_t v : vertices) distinct += moved[v] == 0 ? (moved[v] = 1) : 0;
    return distinct == cage_.vertexCount();
}

std::vector<uint32_t> PlannedCage::allSubfaces() const {
    std::vector<uint32_t> all(subfaceCount());
    for (uint32_t s = 0; s < all.size(); ++s) all[s] = s;
    return all;
}

Result<EditReport> PlannedCage::setEdgeSharpness(uint32_t a, uint32_t b, float sharpness) {
    EdgeCrease edge{a, b, sharpness};
    return setEdgeSharpness({&edge, 1});
}

Result<EditReport> PlannedCage::setEdgeSharpness(std::span<const EdgeCrease> edges) {
    auto start = std::chrono::steady_clock::now();
    for (const EdgeCrease& e : edges) {
        if (topology_.findEdge(e.v0, e.v1) == UINT32_MAX)
            return Error{"there is no edge between vertices " + std::to_string(e.v0 + 1) + " and " + std::to_string(e.v1 + 1)};
        if (Status s = checkSharpness(e.sharpness, "edge"); !s) return s.error();
    }
    const std::vector<EdgeCrease> before = cage_.creases;
    std::vector<uint32_t> ends;
    for (const EdgeCrease& e : edges) {
        cage_.setEdgeSharpness(e.v0, e.v1, std::min(e.sharpness, kInfiniteSharpness));
        ends.push_back(e.v0);
        ends.push_back(e.v1);
    }
    EditReport report;
    if (Status s = replanFaces(facesSharingVertexWith(ends), report); !s) {
        cage_.creases = before;  // nothing was installed: plans still match the old tags
        return s.error();
    }
    return finished(std::move(report), start);
}

Result<EditReport> PlannedCage::setVertexSharpness(uint32_t vertex, float sharpness) {
    VertexCorner corner{vertex, sharpness};
    return setVertexSharpness({&corner, 1});
}

Result<EditReport> PlannedCage::setVertexSharpness(std::span<const VertexCorner> vertices) {
    auto start = std::chrono::steady_clock::now();
    for (const VertexCorner& c : vertices) {
        if (c.vertex >= cage_.vertexCount()) return Error{"vertex " + std::to_string(c.vertex + 1) + " does not exist"};
        if (Status s = checkSharpness(c.sharpness, "vertex"); !s) return s.error();
    }
    const std::vector<VertexCorner> before = cage_.corners;
    std::vector<uint32_t> touched;
    for (const VertexCorner& c : vertices) {
        cage_.setVertexSharpness(c.vertex, std::min(c.sharpness, kInfiniteSharpness));
        touched.push_back(c.vertex);
    }
    EditReport report;
    if (Status s = replanFaces(facesSharingVertexWith(touched), report); !s) {
        cage_.corners = before;
        return s.error();
    }
    return finished(std::move(report), start);
}

Result<EditReport> PlannedCage::setHole(uint32_t face, bool hole) {
    auto start = std::chrono::steady_clock::now();
    if (face >= cage_.faceCount()) return Error{"face " + std::to_string(face + 1) + " does not exist"};
    const bool before = cage_.isHole(face);
    cage_.setHole(face, hole);
    EditReport report;
    if (Status s = replanFaces({face}, report); !s) {
        cage_.setHole(face, before);
        return s.error();
    }
    return finished(std::move(report), start);
}

Result<EditReport> PlannedCage::setCreaseMethod(CreaseMethod method) {
    auto start = std::chrono::steady_clock::now();
    if (method != CreaseMethod::Normal && method != CreaseMethod::Chaikin) return Error{"unknown crease method"};
    const CreaseMethod before = cage_.options.creaseMethod;
    cage_.options.creaseMethod = method;
    std::vector<uint32_t> all(cage_.faceCount());
    for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
    EditReport report;
    if (Status s = replanFaces(all, report); !s) {
        cage_.options.creaseMethod = before;
        return s.error();
    }
    return finished(std::move(report), start);
}

Result<EditReport> PlannedCage::applyTopologyEdit(TopologyEdit edit) {
    if (Status s = finishTopologyEdit(cage_, edit, source_); !s) return s.error();
    return applyFinishedTopologyEdit(std::move(edit));
}

Result<EditReport> PlannedCage::applyFinishedTopologyEdit(TopologyEdit edit) {
    auto start = std::chrono::steady_clock::now();
    assert(edit.oldFaceOf.size() == edit.cage.faceCount() && edit.oldVertexOf.size() == edit.cage.vertexCount() &&
           "applyFinishedTopologyEdit takes an edit that passed finishTopologyEdit");
    const Cage& before = cage_;
    const Cage& next = edit.cage;

    std::vector<uint32_t> newVertexOf(before.vertexCount(), kNewElement);
    bool renumbered = false;
    for (uint32_t v = 0; v < next.vertexCount(); ++v) {
        const uint32_t old = edit.oldVertexOf[v];
        if (old != kNewElement) newVertexOf[old] = v;
        renumbered |= old != v && old != kNewElement;
    }
    // Vertices removed from the end only (the undo of an extrude) renumber nothing: the rings of
    // faces that are not re-planned hold no removed vertex (its faces' vertices are dirty).

    // Dirty vertices (new numbering): every face at them may have a new configuration.
    std::vector<bool> dirty(next.vertexCount(), false);
    auto markOld = [&](uint32_t old) {
        if (newVertexOf[old] != kNewElement) dirty[newVertexOf[old]] = true;
    };
    for (uint32_t f : edit.changedFaces) {
        for (uint32_t i = 0; i < next.faceSize(f); ++i) dirty[next.faceBegin(f)[i]] = true;
        if (const uint32_t old = edit.oldFaceOf[f]; old != kNewElement)
            for (uint32_t i = 0; i < before.faceSize(old); ++i) markOld(before.faceBegin(old)[i]);
    }
    for (uint32_t g : edit.removedFaces)
        for (uint32_t i = 0; i < before.faceSize(g); ++i) markOld(before.faceBegin(g)[i]);
    for (const VertexCorner& c : before.corners) {
        const uint32_t v = newVertexOf[c.vertex];
        if (v != kNewElement && next.vertexSharpness(v) != c.sharpness) dirty[v] = true;
    }
    for (const VertexCorner& c : next.corners) {
        const uint32_t old = edit.oldVertexOf[c.vertex];
        if (old == kNewElement || before.vertexSharpness(old) != c.sharpness) dirty[c.vertex] = true;
    }
    for (const EdgeCrease& c : before.creases) {
        const uint32_t a = newVertexOf[c.v0], b = newVertexOf[c.v1];
        if (a != kNewElement && b != kNewElement && next.edgeSharpness(a, b) == c.sharpness) continue;
        markOld(c.v0);
        markOld(c.v1);
    }
    for (const EdgeCrease& c : next.creases) {
        const uint32_t a = edit.oldVertexOf[c.v0], b = edit.oldVertexOf[c.v1];
        if (a != kNewElement && b != kNewElement && before.edgeSharpness(a, b) == c.sharpness) continue;
        dirty[c.v0] = dirty[c.v1] = true;
    }

    Topology nextTopology = buildTopology(next);
    std::vector<uint32_t> affected;
    const bool everyFace = next.options != before.options;
    for (uint32_t f = 0; f < next.faceCount(); ++f) {
        const uint32_t old = edit.oldFaceOf[f];
        bool replan = everyFace || (old != kNewElement && before.isHole(old) != next.isHole(f));
        for (uint32_t i = 0; i < next.faceSize(f) && !replan; ++i) replan = dirty[next.faceBegin(f)[i]];
        if (replan) affected.push_back(f);
    }
    // OpenSubdiv's topology checks are local (a vertex, its faces and edges): the faces at the
    // edit's vertices are enough when the cage before it passed. The whole cage is checked when
    // every face changed, and when the local cage fails, for a message in the cage's numbering.
    const bool acceptedLocally = !everyFace && createRefiner(localCage(next, affected, true).cage, source_);
    if (!acceptedLocally)
        if (auto refiner = createRefiner(next, source_); !refiner) return refiner.error();
    std::vector<uint32_t> moved;
    for (uint32_t v = 0; v < next.vertexCount(); ++v) {
        const uint32_t old = edit.oldVertexOf[v];
        if (old != kNewElement && before.positions[old] != next.positions[v]) moved.push_back(v);
    }

    // Plan first, so that a failure leaves everything as it was.
    EditReport report;
    report.topologyChanged = true;
    auto plans = planFaces(next, nextTopology, affected, report);
    if (!plans) return plans.error();

    cage_ = std::move(edit.cage);
    topology_ = std::move(nextTopology);
    for (uint32_t f : edit.changedFaces) edit.oldFaceOf[f] = kNewElement;  // nothing of theirs is kept
    report.previousSubfaceOf = remapSubfaces(edit.oldFaceOf);
    report.previousFaceOf = edit.oldFaceOf;
    if (renumbered) {
        std::vector<bool> isAffected(cage_.faceCount(), false);
        for (uint32_t f : affected) isAffected[f] = true;
        for (uint32_t f = 0; f < cage_.faceCount(); ++f) {
            if (isAffected[f]) continue;
            for (uint32_t s = faceFirstSubface_[f]; s < faceFirstSubface_[f + 1]; ++s)
                for (uint32_t& v : subfaceRing_[s]) v = newVertexOf[v];
        }
    }

    installPlans(affected, *plans, report);
    if (!moved.empty()) {
        sortUnique(report.updatedSubfaceList);
        std::vector<uint32_t> stale = subfacesSeeing(moved);
        std::erase_if(stale, [&](uint32_t s) {
            return std::binary_search(report.updatedSubfaceList.begin(), report.updatedSubfaceList.end(), s);
        });
        updateControlPoints(stale);
        report.updatedSubfaceList.insert(report.updatedSubfaceList.end(), stale.begin(), stale.end());
    }
    return finished(std::move(report), start);
}

Result<EditReport> PlannedCage::addFace(std::span<const uint32_t> vertices) {
    TopologyEdit edit;
    edit.cage = cage_;
    edit.cage.addFace(vertices.data(), uint32_t(vertices.size()));
    if (!edit.cage.faceUVIndices.empty()) return Error{"addFace: this cage has texture coordinates; use makeFace"};
    edit.oldFaceOf.resize(edit.cage.faceCount());
    for (uint32_t f = 0; f + 1 < edit.cage.faceCount(); ++f) edit.oldFaceOf[f] = f;
    edit.oldFaceOf.back() = kNewElement;
    edit.oldVertexOf.resize(edit.cage.vertexCount());
    for (uint32_t v = 0; v < edit.cage.vertexCount(); ++v) edit.oldVertexOf[v] = v;
    return applyTopologyEdit(std::move(edit));
}

Result<EditReport> PlannedCage::removeFace(uint32_t face) {
    if (face >= cage_.faceCount()) return Error{"face " + std::to_string(face + 1) + " does not exist"};
    if (cage_.faceCount() == 1) return Error{"cannot remove the last face of the cage"};
    auto edit = deleteFaces(cage_, topology_, {&face, 1}, false);
    if (!edit) return edit.error();
    return applyTopologyEdit(std::move(edit).value());
}

std::vector<std::string> PlannedCage::differencesFromRebuild() const {
    std::vector<std::string> differences;
    Result<PlannedCage> fresh = create(cage_, *database_, options_, source_);
    if (!fresh) return {"rebuild failed: " + fresh.error().message};
    if (fresh->subfaceCount() != subfaceCount()) return {"sub-face count differs"};
    for (uint32_t s = 0; s < subfaceCount(); ++s) {
        std::string where = "sub-face " + std::to_string(s) + ": ";
        if (fresh->subfacePlan_[s] != subfacePlan_[s]) differences.push_back(where + "plan differs");
        else if (fresh->subfaceRotation_[s] != subfaceRotation_[s]) differences.push_back(where + "rotation differs");
        else if (fresh->subfaceRing_[s] != subfaceRing_[s]) differences.push_back(where + "1-ring differs");
        else if (fresh->subfaceControlPoints_[s] != subfaceControlPoints_[s]) differences.push_back(where + "control points differ");
    }
    return differences;
}

}  // namespace qp
