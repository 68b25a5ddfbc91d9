#include "planned_cage.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "osd_refiner.h"

namespace qp {

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// (u, v) of the face in the frame of a plan whose origin is corner `rotation`.
void toPlanFrame(uint32_t rotation, float u, float v, float& pu, float& pv) {
    switch (rotation) {
    case 1: pu = v; pv = 1.0f - u; break;
    case 2: pu = 1.0f - u; pv = 1.0f - v; break;
    case 3: pu = 1.0f - v; pv = u; break;
    default: pu = u; pv = v; break;
    }
}

void derivativesToFaceFrame(uint32_t rotation, LimitSample& s) {
    glm::vec3 du = s.du, dv = s.dv;
    switch (rotation) {
    case 1: s.du = -dv; s.dv = du; break;
    case 2: s.du = -du; s.dv = -dv; break;
    case 3: s.du = dv; s.dv = -du; break;
    default: break;
    }
}

}  // namespace

Result<PlannedCage> PlannedCage::create(Cage cage, PlanDatabase& database, const PlanOptions& options,
                                        const std::string& source) {
    if (Status valid = validateCage(cage, source); !valid) return valid.error();
    if (options.maxDepth < 1 || options.maxDepth > kMaxPlanDepth)
        return Error{"plan depth must be between 1 and " + std::to_string(kMaxPlanDepth)};
    if (auto refiner = createRefiner(cage, source); !refiner) return refiner.error();

    PlannedCage planned;
    planned.cage_ = std::move(cage);
    planned.topology_ = buildTopology(planned.cage_);
    planned.options_ = options;
    planned.database_ = &database;
    planned.source_ = source;
    std::vector<uint32_t> noOldFaces(planned.cage_.faceCount(), UINT32_MAX);
    planned.remapSubfaces(noOldFaces);

    std::vector<uint32_t> all(planned.cage_.faceCount());
    for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
    EditReport report;
    if (Status status = planned.replanFaces(all, report); !status) return status.error();
    return planned;
}

std::span<const uint32_t> PlannedCage::subfaceRing(uint32_t subface) const { return subfaceRing_[subface]; }

std::span<const glm::vec3> PlannedCage::subfaceControlPoints(uint32_t subface) const {
    return subfaceControlPoints_[subface];
}

void PlannedCage::remapSubfaces(const std::vector<uint32_t>& oldFaceOf) {
    std::vector<uint32_t> oldFirst = std::move(faceFirstSubface_);
    std::vector<uint32_t> oldPlan = std::move(subfacePlan_), oldRotation = std::move(subfaceRotation_);
    std::vector<std::vector<uint32_t>> oldRing = std::move(subfaceRing_);
    std::vector<std::vector<glm::vec3>> oldPoints = std::move(subfaceControlPoints_);

    faceFirstSubface_.assign(cage_.faceCount() + 1, 0);
    for (uint32_t f = 0; f < cage_.faceCount(); ++f)
        faceFirstSubface_[f + 1] = faceFirstSubface_[f] + qp::subfaceCount(cage_.faceSize(f));
    const uint32_t count = faceFirstSubface_.back();
    subfacePlan_.assign(count, kNoPlan);
    subfaceRotation_.assign(count, 0);
    subfaceRing_.assign(count, {});
    subfaceControlPoints_.assign(count, {});
    for (uint32_t f = 0; f < cage_.faceCount(); ++f) {
        uint32_t old = oldFaceOf[f];
        if (old == UINT32_MAX) continue;
        for (uint32_t k = 0; k < faceFirstSubface_[f + 1] - faceFirstSubface_[f]; ++k) {
            uint32_t from = oldFirst[old] + k, to = faceFirstSubface_[f] + k;
            subfacePlan_[to] = oldPlan[from];
            subfaceRotation_[to] = oldRotation[from];
            subfaceRing_[to] = std::move(oldRing[from]);
            subfaceControlPoints_[to] = std::move(oldPoints[from]);
        }
    }
}

Status PlannedCage::replanFaces(const std::vector<uint32_t>& faces, EditReport& report) {
    std::vector<uint32_t> subfaces;
    for (uint32_t f : faces)
        for (uint32_t s = faceFirstSubface_[f]; s < faceFirstSubface_[f + 1]; ++s) subfaces.push_back(s);

    const uint64_t missesBefore = database_->misses();
    std::vector<std::string> errors(subfaces.size());
    tbb::parallel_for(size_t(0), subfaces.size(), [&](size_t i) {
        uint32_t s = subfaces[i];
        uint32_t face = uint32_t(std::upper_bound(faceFirstSubface_.begin(), faceFirstSubface_.end(), s) -
                                 faceFirstSubface_.begin()) - 1;
        if (cage_.isHole(face)) {
            subfacePlan_[s] = kNoPlan;
            subfaceRotation_[s] = 0;
            subfaceRing_[s].clear();
            return;
        }
        FaceConfig config = gatherFaceConfig(cage_, topology_, face, s - faceFirstSubface_[face], options_);
        Result<uint32_t> id = database_->findOrBuild(config);
        if (!id) {
            errors[i] = source_ + ": face " + std::to_string(face + 1) + ": " + id.error().message;
            return;
        }
        subfacePlan_[s] = *id;
        subfaceRotation_[s] = config.rotation;
        subfaceRing_[s] = std::move(config.ring);
    });
    for (const std::string& e : errors)
        if (!e.empty()) return Error{e};
    report.replannedFaces += uint32_t(faces.size());
    report.newPlans += uint32_t(database_->misses() - missesBefore);
    updateControlPoints(subfaces);
    report.updatedSubfaces += uint32_t(subfaces.size());
    return success();
}

void PlannedCage::updateControlPoints(const std::vector<uint32_t>& subfaces) {
    tbb::parallel_for(size_t(0), subfaces.size(), [&](size_t i) {
        uint32_t s = subfaces[i];
        if (subfacePlan_[s] == kNoPlan) {
            subfaceControlPoints_[s].clear();
            return;
        }
        const Plan& plan = database_->plan(subfacePlan_[s]);
        std::vector<glm::vec3> ring(subfaceRing_[s].size());
        for (size_t j = 0; j < ring.size(); ++j) ring[j] = cage_.positions[subfaceRing_[s][j]];
        subfaceControlPoints_[s].resize(plan.stencilCount());
        applyStencils(plan, ring.data(), plan.stencilCount(), subfaceControlPoints_[s].data());
    });
}

LimitSample PlannedCage::evaluate(uint32_t subface, float u, float v) const {
    uint32_t rotation = subfaceRotation_[subface];
    float pu, pv;
    toPlanFrame(rotation, u, v, pu, pv);
    LimitSample sample =
        evaluatePlan(database_->plan(subfacePlan_[subface]), subfaceControlPoints_[subface].data(), pu, pv);
    derivativesToFaceFrame(rotation, sample);
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

    // Faces whose 1-ring holds a moved vertex: the faces at any vertex of a face at it.
    std::vector<uint32_t> touching = facesSharingVertexWith(vertices);
    std::vector<uint32_t> ringVertices;
    for (uint32_t f : touching) ringVertices.insert(ringVertices.end(), cage_.faceBegin(f), cage_.faceBegin(f) + cage_.faceSize(f));
    std::sort(ringVertices.begin(), ringVertices.end());
    ringVertices.erase(std::unique(ringVertices.begin(), ringVertices.end()), ringVertices.end());
    std::vector<uint32_t> subfaces;
    for (uint32_t f : facesSharingVertexWith(ringVertices))
        for (uint32_t s = faceFirstSubface_[f]; s < faceFirstSubface_[f + 1]; ++s) subfaces.push_back(s);
    updateControlPoints(subfaces);

    EditReport report;
    report.updatedSubfaces = uint32_t(subfaces.size());
    report.milliseconds = millisecondsSince(start);
    return report;
}

Result<EditReport> PlannedCage::setEdgeSharpness(uint32_t a, uint32_t b, float sharpness) {
    auto start = std::chrono::steady_clock::now();
    if (topology_.findEdge(a, b) == UINT32_MAX)
        return Error{"there is no edge between vertices " + std::to_string(a + 1) + " and " + std::to_string(b + 1)};
    if (!std::isfinite(sharpness) || sharpness < 0.0f)
        return Error{"edge sharpness must be a number >= 0 (got " + std::to_string(sharpness) + ")"};
    cage_.setEdgeSharpness(a, b, std::min(sharpness, kInfiniteSharpness));
    uint32_t ends[2] = {a, b};
    EditReport report;
    if (Status s = replanFaces(facesSharingVertexWith(ends), report); !s) return s.error();
    report.milliseconds = millisecondsSince(start);
    return report;
}

Result<EditReport> PlannedCage::setVertexSharpness(uint32_t vertex, float sharpness) {
    auto start = std::chrono::steady_clock::now();
    if (vertex >= cage_.vertexCount()) return Error{"vertex " + std::to_string(vertex + 1) + " does not exist"};
    if (!std::isfinite(sharpness) || sharpness < 0.0f)
        return Error{"vertex sharpness must be a number >= 0 (got " + std::to_string(sharpness) + ")"};
    cage_.setVertexSharpness(vertex, std::min(sharpness, kInfiniteSharpness));
    EditReport report;
    if (Status s = replanFaces(facesSharingVertexWith({&vertex, 1}), report); !s) return s.error();
    report.milliseconds = millisecondsSince(start);
    return report;
}

Result<EditReport> PlannedCage::setHole(uint32_t face, bool hole) {
    auto start = std::chrono::steady_clock::now();
    if (face >= cage_.faceCount()) return Error{"face " + std::to_string(face + 1) + " does not exist"};
    cage_.setHole(face, hole);
    EditReport report;
    if (Status s = replanFaces({face}, report); !s) return s.error();
    report.milliseconds = millisecondsSince(start);
    return report;
}

Result<EditReport> PlannedCage::addFace(std::span<const uint32_t> vertices) {
    auto start = std::chrono::steady_clock::now();
    Cage edited = cage_;
    edited.addFace(vertices.data(), uint32_t(vertices.size()));
    if (Status valid = validateCage(edited, source_); !valid) return valid.error();
    if (auto refiner = createRefiner(edited, source_); !refiner) return refiner.error();

    std::vector<uint32_t> affected = facesSharingVertexWith(vertices);  // before the new face exists
    cage_ = std::move(edited);
    topology_ = buildTopology(cage_);
    std::vector<uint32_t> oldFaceOf(cage_.faceCount());
    for (uint32_t f = 0; f + 1 < cage_.faceCount(); ++f) oldFaceOf[f] = f;
    oldFaceOf.back() = UINT32_MAX;
    remapSubfaces(oldFaceOf);
    affected.push_back(cage_.faceCount() - 1);

    EditReport report;
    if (Status s = replanFaces(affected, report); !s) return s.error();
    report.milliseconds = millisecondsSince(start);
    return report;
}

Result<EditReport> PlannedCage::removeFace(uint32_t face) {
    auto start = std::chrono::steady_clock::now();
    if (face >= cage_.faceCount()) return Error{"face " + std::to_string(face + 1) + " does not exist"};
    if (cage_.faceCount() == 1) return Error{"cannot remove the last face of the cage"};
    std::vector<uint32_t> corners(cage_.faceBegin(face), cage_.faceBegin(face) + cage_.faceSize(face));

    Cage edited = cage_;
    uint32_t begin = edited.faceOffsets[face], end = edited.faceOffsets[face + 1];
    edited.faceVertices.erase(edited.faceVertices.begin() + begin, edited.faceVertices.begin() + end);
    edited.faceOffsets.erase(edited.faceOffsets.begin() + face + 1);
    for (size_t f = face + 1; f < edited.faceOffsets.size(); ++f) edited.faceOffsets[f] -= end - begin;
    if (!edited.faceUVIndices.empty())
        edited.faceUVIndices.erase(edited.faceUVIndices.begin() + begin, edited.faceUVIndices.begin() + end);
    std::erase(edited.holes, face);
    for (uint32_t& h : edited.holes) h -= h > face ? 1 : 0;
    // Creases on edges that no longer exist go with the face.
    Topology after = buildTopology(edited);
    std::erase_if(edited.creases, [&](const EdgeCrease& c) { return after.findEdge(c.v0, c.v1) == UINT32_MAX; });
    if (auto refiner = createRefiner(edited, source_); !refiner) return refiner.error();

    std::vector<uint32_t> affected;
    for (uint32_t f : facesSharingVertexWith(corners))
        if (f != face) affected.push_back(f > face ? f - 1 : f);
    cage_ = std::move(edited);
    topology_ = std::move(after);
    std::vector<uint32_t> oldFaceOf(cage_.faceCount());
    for (uint32_t f = 0; f < cage_.faceCount(); ++f) oldFaceOf[f] = f < face ? f : f + 1;
    remapSubfaces(oldFaceOf);

    EditReport report;
    if (Status s = replanFaces(affected, report); !s) return s.error();
    report.milliseconds = millisecondsSince(start);
    return report;
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
