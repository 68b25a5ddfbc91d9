// SceneDocument: what the Python module's Scene holds — a scene (camera, viewports,
// tessellation, displacement), its planned cage and the undo history every edit goes through —
// and the edits a script can make, each returning the PlannedCage's EditReport.
//
// Plain C++ (no Python here): python/bindings_*.cpp wrap it. Rules it keeps:
//   - every edit goes through EditHistory, so undo/redo re-plan only what the edit re-planned;
//   - displacement strokes, resolution changes and clearing the displacement are history
//     entries too (CustomEdit), so one undo stack covers everything;
//   - a topology edit is refused while the scene has displacement: the samples follow the
//     current faces and no transfer across topology edits exists yet (the message says to
//     clear the displacement first, which is itself undoable);
//   - on failure nothing changes and the error carries the core's message (what the command
//     line prints); vertices and faces are 0-based here, 1-based in messages (as in OBJ).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "brush.h"
#include "displacement_edit.h"
#include "edit_history.h"
#include "planned_cage.h"
#include "scene.h"
#include "sculpt_samples.h"
#include "selection.h"
#include "transform.h"

namespace qp::py {

// The EditReport of an edit plus what a topology operation suggests selecting next.
struct EditOutcome {
    std::string name;
    EditReport report;
    std::vector<uint32_t> resultVertices, resultFaces;
    std::vector<EdgeKey> resultEdges;
    // Strokes: dabs applied and displacement samples changed.
    uint32_t dabs = 0, changedSamples = 0;
};

class SceneDocument {
public:
    // Plans the scene's cage (all cores), copying what the persistent plan cache has
    // (core/plan_cache.h) and storing what it had to build there. `source` names it in
    // messages (usually the path); a cache that could not be read or written adds a warning.
    static Result<std::unique_ptr<SceneDocument>> create(Scene scene, const PlanOptions& options, const std::string& source,
                                                         std::vector<std::string>* warnings = nullptr);
    static Result<std::unique_ptr<SceneDocument>> load(const std::string& path, const PlanOptions& options,
                                                       std::vector<std::string>* warnings);
    // A copy of the current state with an empty history (plans are shared with this one's
    // database).
    std::unique_ptr<SceneDocument> copy() const;

    const PlannedCage& planned() const { return *planned_; }
    const Cage& cage() const { return planned_->cage(); }
    const Scene& scene() const { return scene_; }
    Scene& settings() { return scene_; }  // camera, viewports, tessellation (not the cage)
    const Displacement& displacement() const { return scene_.displacement; }
    const EditHistory& history() const { return history_; }
    void setHistoryBudget(size_t bytes) { history_.setBudget(bytes); }
    const std::string& source() const { return source_; }

    // The scene as it would be saved now (its cage is the current one).
    Scene currentScene() const;
    // inlineCage: write the cage into the JSON; otherwise beside it as an OBJ (scene.cagePath).
    Status save(const std::string& path, bool inlineCage);
    Status saveObj(const std::string& path) const;

    // ---- edits (all recorded in the history) ----
    Result<EditOutcome> moveVertices(std::span<const uint32_t> vertices, std::span<const glm::vec3> positions,
                                     const std::string& name = "Move", bool mergeWithPrevious = false);
    // Transforms the vertices about their centroid (or `pivot`) in world or local axes.
    Result<EditOutcome> translate(std::span<const uint32_t> vertices, const glm::vec3& offset, TransformSpace space);
    Result<EditOutcome> rotate(std::span<const uint32_t> vertices, const glm::vec3& axis, float degrees,
                               TransformSpace space, const std::optional<glm::vec3>& pivot);
    Result<EditOutcome> scale(std::span<const uint32_t> vertices, const glm::vec3& factors, TransformSpace space,
                              const std::optional<glm::vec3>& pivot);
    Result<EditOutcome> setEdgeSharpness(std::span<const EdgeCrease> edges);
    Result<EditOutcome> setVertexSharpness(std::span<const VertexCorner> corners);
    Result<EditOutcome> setHoles(std::span<const uint32_t> faces, bool hole);
    Result<EditOutcome> setCreaseMethod(CreaseMethod method);

    Result<EditOutcome> extrude(std::span<const uint32_t> faces, float distance);
    Result<EditOutcome> deleteFaces(std::span<const uint32_t> faces, bool removeUnusedVertices);
    Result<EditOutcome> splitFace(uint32_t face, uint32_t a, uint32_t b);
    Result<EditOutcome> insertEdgeLoop(uint32_t a, uint32_t b, float t);
    Result<EditOutcome> mergeVertices(std::span<const uint32_t> vertices, MergeTarget target);
    Result<EditOutcome> makeFace(std::span<const uint32_t> vertices);

    // Displacement: a stroke (creates a zero displacement at `newResolution` first, as
    // `quadplan sculpt` does, when the scene has none: that is a separate history entry).
    Result<EditOutcome> stroke(const StrokeOptions& options, std::span<const glm::vec3> path, uint32_t newResolution);
    Result<EditOutcome> setDisplacementResolution(uint32_t resolution);
    Result<EditOutcome> clearDisplacement();

    Result<EditOutcome> undo();
    Result<EditOutcome> redo();
    Result<EditOutcome> jumpTo(size_t position);

    // Plans of the current cage vs planning it from scratch (empty when equal).
    std::vector<std::string> differencesFromRebuild() const { return planned_->differencesFromRebuild(); }

private:
    SceneDocument() = default;
    Result<EditOutcome> finish(const std::string& name, Result<EditReport> report);
    Result<EditOutcome> topologyEdit(const std::string& name, Result<TopologyEdit> edit);
    Result<EditOutcome> replaceDisplacement(const std::string& name, Displacement next);
    Result<EditOutcome> transform(const std::string& name, std::span<const uint32_t> vertices, const glm::mat4& matrix);
    // Keeps the brushes' sample cache in step with the surface after an edit.
    void afterEdit(const EditReport& report);
    // Frees the database's plans no sub-face uses once it has grown by as many plans as were in
    // use at the last release (at least kMinPlansBetweenReleases): a long session's memory then
    // follows the cage, not every configuration it ever had (PlanDatabase::releaseUnused).
    // Undoing to an older configuration rebuilds its plans.
    void releaseUnusedPlans();
    static constexpr uint32_t kMinPlansBetweenReleases = 256;
    const SculptSamples& sculptSamples();
    DisplacementListener listener();  // for DisplacementEdit: drops the cache on a new layout

    Scene scene_;  // its cage is not kept current: planned_ holds the cage
    std::shared_ptr<PlanDatabase> database_;
    std::optional<PlannedCage> planned_;
    EditHistory history_;
    std::string source_;
    std::optional<SculptSamples> samples_;
    uint32_t sizeAtLastRelease_ = 0, plansInUseAtLastRelease_ = 0;  // built on the first stroke after a change of layout
};

}  // namespace qp::py
