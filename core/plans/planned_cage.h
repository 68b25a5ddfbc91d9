// PlannedCage: a cage together with the plan of every (sub-)face and the control points those
// plans produce, kept current by edits that re-plan only the faces they affect.
//
// Sub-faces are numbered like OpenSubdiv's Ptex faces: a quad is one sub-face, an n-gon n
// (see face_config.h). Hole faces are planned too, as if they were not holes (a hole changes no
// neighbour's limit surface), but have no surface: a renderer can keep them in its tables and
// hide them, so that making or filling a hole moves nothing else.
//
// What an edit re-plans (the limit over a face depends on its face + 1-ring only, face_config.h):
//   - moving vertices: nothing; faces whose 1-ring holds a moved vertex get new control points;
//   - edge sharpness (a, b): the faces at a or at b;
//   - vertex sharpness v: the faces at v;
//   - hole flag of f: f only (its plan stays; it is looked up again);
//   - crease method (or any SubdivisionOptions change): every face (the options are part of
//     every configuration key);
//   - a topology edit (applyTopologyEdit; addFace and removeFace are two): the faces at the
//     "dirty" vertices, i.e. exactly the faces whose configuration may have changed. A vertex is
//     dirty when a face at it was created, removed or got a new vertex list, or when the
//     sharpness of an edge at it or its corner sharpness changed. Faces whose hole flag changed
//     are re-planned too. Every other face keeps its plan and control points (its 1-ring is
//     only renumbered), except that sub-faces whose 1-ring holds a vertex the edit moved get
//     new control points, as for a move.
// Each edit validates its input first and leaves everything unchanged when it fails.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "mesh/cage.h"
#include "mesh/topology.h"
#include "mesh/topology_edits.h"
#include "plans/plan_database.h"

namespace qp {

struct EditReport {
    uint32_t replannedFaces = 0;     // faces whose configuration was gathered and looked up again
    uint32_t updatedSubfaces = 0;    // sub-faces whose control points were recomputed
    uint32_t newPlans = 0;           // database misses caused by the edit
    double milliseconds = 0.0;
    // The same sets, sorted, in the numbering after the edit (a renderer re-uploads these).
    std::vector<uint32_t> replannedFaceList;
    std::vector<uint32_t> updatedSubfaceList;
    // Faces or vertices were renumbered (a topology edit). Then, per face and per sub-face after
    // the edit, its number before it, or kNewElement where nothing of it was kept: a sub-face
    // that maps keeps its plan, rotation and control points unless the lists above name it (its
    // 1-ring may only be renumbered), so data held outside can be carried over instead of rebuilt.
    bool topologyChanged = false;
    std::vector<uint32_t> previousFaceOf, previousSubfaceOf;
};

// Adds `next` (an edit made after `into`'s) to `into`: counts and times add up; the lists are
// united in the numbering after `next` (what `into` listed is carried through next's maps), and
// the maps compose, so the sum describes both edits as one.
void accumulateReport(EditReport& into, const EditReport& next);

inline constexpr uint32_t kNoPlan = UINT32_MAX;

class PlannedCage {
public:
    // Plans every face (in parallel). Fails when the cage is invalid or OpenSubdiv rejects it.
    static Result<PlannedCage> create(Cage cage, PlanDatabase& database, const PlanOptions& options,
                                      const std::string& source = "cage");

    const Cage& cage() const { return cage_; }
    const Topology& topology() const { return topology_; }
    const PlanOptions& options() const { return options_; }
    PlanDatabase& database() const { return *database_; }

    uint32_t subfaceCount() const { return uint32_t(subfacePlan_.size()); }
    uint32_t firstSubface(uint32_t face) const { return faceFirstSubface_[face]; }
    uint32_t subfacePlan(uint32_t subface) const { return subfacePlan_[subface]; }
    // False for holes and for faces without a limit surface (boundary rule "none").
    bool hasSurface(uint32_t subface) const { return !subfaceHole_[subface] && hasPlannedSurface(subface); }
    // The same with holes counted as the surface they would have without the tag (false where
    // a hole's plan could not be built): what renderers keep in their tables, hiding holes.
    bool hasPlannedSurface(uint32_t subface) const {
        return subfacePlan_[subface] != kNoPlan && database_->plan(subfacePlan_[subface]).hasSurface();
    }
    uint32_t subfaceRotation(uint32_t subface) const { return subfaceRotation_[subface]; }
    std::span<const uint32_t> subfaceRing(uint32_t subface) const;
    // Control points are relative to the sub-face's origin, the position of its first 1-ring
    // vertex (a corner of its face). Deep in a plan's quadtree the derivatives are differences of
    // control points a few 2^-depth of the face apart, times 2^depth: in the cage's absolute
    // coordinates float keeps only the precision of the model's size for them, which at depth 8-10
    // next to an extraordinary vertex is the size of the differences themselves (normals off by
    // degrees, flipped at depth 10); relative to a corner of the face it is the face's size.
    //
    // Each sub-face stores only the prefix of its control points that tessellation factors up
    // to 2^kStoredControlPointLevel read (Plan::stencilCountByLevel): the factors at which whole
    // cages are evaluated (far views, screen-adaptive factors on large cages). Deeper points,
    // which only evaluations close to an extraordinary vertex read, are computed when asked for;
    // at a million faces the prefix is 33 points a sub-face against 59, 330 MiB less.
    static constexpr uint32_t kStoredControlPointLevel = 2;
    std::span<const glm::vec3> storedControlPoints(uint32_t subface) const;
    // The control points that evaluating the sub-face on a grid of factor <= 2^level reads
    // (level >= kMaxPlanDepth: at every (u, v)): the stored ones where they serve it, else all
    // of them, computed into `scratch` (the span then points into it).
    std::span<const glm::vec3> controlPointsFor(uint32_t subface, uint32_t level, std::vector<glm::vec3>& scratch) const;
    glm::vec3 subfaceOrigin(uint32_t subface) const { return cage_.positions[subfaceRing_[subface][0]]; }

    // Limit position and derivatives at (u, v) of a sub-face, in the sub-face's own frame
    // (quads: u from corner 0 to 1, v from corner 0 to 3). The sub-face must have a surface.
    // Thread-safe; each thread keeps the last sub-face's computed control points (see
    // storedControlPoints), so evaluating many points of one sub-face computes them once.
    LimitSample evaluate(uint32_t subface, float u, float v) const;
    // The same from control points controlPointsFor returned for a level that serves (u, v).
    LimitSample evaluate(uint32_t subface, std::span<const glm::vec3> controlPoints, float u, float v) const;

    Result<EditReport> moveVertices(std::span<const uint32_t> vertices, std::span<const glm::vec3> positions);
    // Sharpness 0 clears the tag; values above kInfiniteSharpness are clamped to it.
    Result<EditReport> setEdgeSharpness(uint32_t a, uint32_t b, float sharpness);
    // Several edges at once (v0, v1 in any order), re-planning the union of their faces once.
    Result<EditReport> setEdgeSharpness(std::span<const EdgeCrease> edges);
    Result<EditReport> setVertexSharpness(uint32_t vertex, float sharpness);
    Result<EditReport> setVertexSharpness(std::span<const VertexCorner> vertices);
    Result<EditReport> setHole(uint32_t face, bool hole);
    Result<EditReport> setCreaseMethod(CreaseMethod method);

    // Replaces the cage by edit.cage (made from this cage by an operation of topology_edits.h,
    // or by hand with oldFaceOf / oldVertexOf filled as that header describes) and re-plans the
    // faces whose configuration may have changed (see the top of this file). Fails, changing
    // nothing, when the maps are inconsistent, the new cage is invalid or OpenSubdiv rejects it.
    Result<EditReport> applyTopologyEdit(TopologyEdit edit);
    // The same for an edit that has just passed finishTopologyEdit against cage() (EditHistory
    // finishes every edit before it records it): validating a large cage twice per edit cost
    // as much as the rest of the plan engine's work.
    Result<EditReport> applyFinishedTopologyEdit(TopologyEdit edit);
    // Appends a face with these vertices, in this order (no orientation fix-up: see makeFace).
    Result<EditReport> addFace(std::span<const uint32_t> vertices);
    // Removes one face; its vertices stay (see deleteFaces for more).
    Result<EditReport> removeFace(uint32_t face);

    // Per sub-face differences from planning the current cage from scratch (empty when equal):
    // plan, rotation, 1-ring and control points must all match.
    std::vector<std::string> differencesFromRebuild() const;

private:
    PlannedCage() = default;
    struct SubfacePlan {
        uint32_t plan = kNoPlan, rotation = 0;
        std::vector<uint32_t> ring;
    };
    // Looks up (or builds) the plans of every sub-face of the faces of `cage`, changing nothing
    // here; in face order, then sub-face order.
    Result<std::vector<SubfacePlan>> planFaces(const Cage& cage, const Topology& topology,
                                               const std::vector<uint32_t>& faces, EditReport& report) const;
    // Stores plans from planFaces (for the current cage) and refreshes those control points.
    void installPlans(const std::vector<uint32_t>& faces, std::vector<SubfacePlan>& plans, EditReport& report);
    // planFaces + installPlans on the current cage: re-plans the faces (sorted, unique).
    Status replanFaces(const std::vector<uint32_t>& faces, EditReport& report);
    void updateControlPoints(const std::vector<uint32_t>& subfaces);
    std::vector<uint32_t> facesSharingVertexWith(std::span<const uint32_t> vertices) const;
    // Sub-faces whose 1-ring holds one of the vertices (sorted).
    bool movesEveryVertex(std::span<const uint32_t> vertices) const;
    std::vector<uint32_t> allSubfaces() const;
    std::vector<uint32_t> subfacesSeeing(std::span<const uint32_t> vertices) const;
    // Rebuilds the sub-face arrays after a topology change; `oldFaceOf[f]` is the face's index
    // before the change (UINT32_MAX for a new face) so unaffected faces keep their plans.
    // Returns, per sub-face now, the sub-face it was before (kNewElement: none kept).
    std::vector<uint32_t> remapSubfaces(const std::vector<uint32_t>& oldFaceOf);

    Cage cage_;
    Topology topology_;
    PlanOptions options_;
    PlanDatabase* database_ = nullptr;
    std::string source_;

    std::vector<uint32_t> faceFirstSubface_;  // faces + 1
    std::vector<uint32_t> subfacePlan_, subfaceRotation_;
    std::vector<uint8_t> subfaceHole_;  // 1 where the sub-face's face is a hole
    std::vector<std::vector<uint32_t>> subfaceRing_;
    std::vector<std::vector<glm::vec3>> subfaceControlPoints_;  // the stored prefix
    // A value no other state of any PlannedCage's control points had: what evaluate's
    // per-thread copy of computed control points is keyed by.
    uint64_t controlPointsGeneration_ = 0;
};

}  // namespace qp
