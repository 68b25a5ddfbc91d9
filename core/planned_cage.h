// PlannedCage: a cage together with the plan of every (sub-)face and the control points those
// plans produce, kept current by edits that re-plan only the faces they affect.
//
// Sub-faces are numbered like OpenSubdiv's Ptex faces: a quad is one sub-face, an n-gon n
// (see face_config.h); hole faces keep their sub-face numbers but have no plan.
//
// What an edit re-plans (the limit over a face depends on its 1-ring only, face_config.h):
//   - moving vertices: nothing; faces whose 1-ring holds a moved vertex get new control points;
//   - edge sharpness (a, b): the faces at a or at b;
//   - vertex sharpness v: the faces at v;
//   - hole flag of f: f only;
//   - adding or removing face g: g and the faces that share a vertex with g.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "cage.h"
#include "plan_database.h"
#include "topology.h"

namespace qp {

struct EditReport {
    uint32_t replannedFaces = 0;     // faces whose configuration was gathered and looked up again
    uint32_t updatedSubfaces = 0;    // sub-faces whose control points were recomputed
    uint32_t newPlans = 0;           // database misses caused by the edit
    double milliseconds = 0.0;
};

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
    bool hasSurface(uint32_t subface) const {
        return subfacePlan_[subface] != kNoPlan && database_->plan(subfacePlan_[subface]).hasSurface();
    }
    uint32_t subfaceRotation(uint32_t subface) const { return subfaceRotation_[subface]; }
    std::span<const uint32_t> subfaceRing(uint32_t subface) const;
    std::span<const glm::vec3> subfaceControlPoints(uint32_t subface) const;

    // Limit position and derivatives at (u, v) of a sub-face, in the sub-face's own frame
    // (quads: u from corner 0 to 1, v from corner 0 to 3). The sub-face must have a surface.
    LimitSample evaluate(uint32_t subface, float u, float v) const;

    Result<EditReport> moveVertices(std::span<const uint32_t> vertices, std::span<const glm::vec3> positions);
    Result<EditReport> setEdgeSharpness(uint32_t a, uint32_t b, float sharpness);
    Result<EditReport> setVertexSharpness(uint32_t vertex, float sharpness);
    Result<EditReport> setHole(uint32_t face, bool hole);
    Result<EditReport> addFace(std::span<const uint32_t> vertices);
    Result<EditReport> removeFace(uint32_t face);

    // Per sub-face differences from planning the current cage from scratch (empty when equal):
    // plan, rotation, 1-ring and control points must all match.
    std::vector<std::string> differencesFromRebuild() const;

private:
    PlannedCage() = default;
    // Re-plans the given faces (sorted, unique) and refreshes their control points.
    Status replanFaces(const std::vector<uint32_t>& faces, EditReport& report);
    void updateControlPoints(const std::vector<uint32_t>& subfaces);
    std::vector<uint32_t> facesSharingVertexWith(std::span<const uint32_t> vertices) const;
    // Rebuilds the sub-face arrays after a topology change; `oldFaceOf[f]` is the face's index
    // before the change (UINT32_MAX for a new face) so unaffected faces keep their plans.
    void remapSubfaces(const std::vector<uint32_t>& oldFaceOf);

    Cage cage_;
    Topology topology_;
    PlanOptions options_;
    PlanDatabase* database_ = nullptr;
    std::string source_;

    std::vector<uint32_t> faceFirstSubface_;  // faces + 1
    std::vector<uint32_t> subfacePlan_, subfaceRotation_;
    std::vector<std::vector<uint32_t>> subfaceRing_;
    std::vector<std::vector<glm::vec3>> subfaceControlPoints_;
};

}  // namespace qp
