// SceneDocument: what the Python module's Scene holds — a scene (its objects, camera, viewports,
// tessellation), the planned cage of every object with a cage of its own (one plan database for
// all of them), and the one undo history every edit goes through — and the edits a script can
// make, each returning the PlannedCage's EditReport.
//
// Objects: edits of cages, tags and displacement act on the *active* object (setActive; an
// object with a cage of its own), as Blender's edit mode acts on its active object. Object edits
// (add, instance, remove, rename, transform, visibility) act on the scene; a transform or
// visibility change re-plans nothing. Undo and redo go through every kind in order.
//
// Animation (core/animation/cage_animation.h): the scene shows one current frame. Every object with vertex
// keys has its planned cage moved there (a vertex move: nothing is re-planned) from its rest
// positions, which the document keeps per planned cage (what a saved scene holds as the cage);
// every object with transform keys has its transform evaluated there. On an object with vertex
// keys a move keys the moved vertices at the current frame and a topology edit carries the keys
// (core/animation/animation_edits.h); objects without keys are edited as if nothing were animated.
//
// Plain C++ (no Python here): python/bindings_*.cpp wrap it. Rules it keeps:
//   - every edit goes through EditHistory, so undo/redo re-plan only what the edit re-planned;
//   - displacement strokes, resolution changes and clearing the displacement are history
//     entries too (CustomEdit), so one undo stack covers everything;
//   - a topology edit on an object with displacement carries it to the new cage in the same
//     entry (core/displacement/displaced_topology_edit.h), so one undo brings both back;
//   - on failure nothing changes and the error carries the core's message (what the command
//     line prints); vertices and faces are 0-based here, 1-based in messages (as in OBJ).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "animation/animation_edits.h"
#include "displacement/brush.h"
#include "displacement/displaced_topology_edit.h"
#include "displacement/displacement_edit.h"
#include "displacement/sculpt_samples.h"
#include "edit/edit_history.h"
#include "edit/selection.h"
#include "edit/transform.h"
#include "plans/planned_cage.h"
#include "scene/planned_scene.h"
#include "scene/scene.h"

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
    // (core/plans/plan_cache.h) and storing what it had to build there. `source` names it in
    // messages (usually the path); a cache that could not be read or written adds a warning.
    static Result<std::unique_ptr<SceneDocument>> create(Scene scene, const PlanOptions& options, const std::string& source,
                                                         std::vector<std::string>* warnings = nullptr);
    static Result<std::unique_ptr<SceneDocument>> load(const std::string& path, const PlanOptions& options,
                                                       std::vector<std::string>* warnings);
    // A copy of the current state with an empty history (plans are shared with this one's
    // database).
    std::unique_ptr<SceneDocument> copy() const;

    // The active object's planned cage, cage and displacement.
    const PlannedCage& planned() const { return planned_.cages[planned_.cageOfObject[active_]]; }
    const Cage& cage() const { return planned().cage(); }
    const Displacement& displacement() const { return scene_.objects[active_].displacement; }
    // The objects (their own cages are stale: plannedScene() holds them), camera, viewports.
    const Scene& scene() const { return scene_; }
    const PlannedScene& plannedScene() const { return planned_; }
    Scene& settings() { return scene_; }  // camera, viewports, tessellation (not the objects)

    // ---- objects (every change but setActive is a history entry) ----
    uint32_t activeObject() const { return active_; }
    Status setActive(const std::string& name);
    // Plans `cage` (through the scene's database) as a new object; the name it got.
    Result<std::string> addObject(Cage cage, const std::string& name, const ObjectTransform& transform);
    Result<std::string> addInstance(const std::string& source, const std::string& name, const ObjectTransform& transform);
    // Refused while other objects instance it, and for the last object.
    Status removeObject(const std::string& name);
    Status renameObject(const std::string& name, const std::string& newName);
    Status setTransform(const std::string& name, const ObjectTransform& transform);
    Status setVisible(const std::string& name, bool visible);
    const EditHistory& history() const { return history_; }
    void setHistoryBudget(size_t bytes) { history_.setBudget(bytes); }
    const std::string& source() const { return source_; }

    // The scene as it would be saved now: the current cages, animated ones at rest; transforms as
    // shown at the current frame.
    Scene currentScene() const;
    // `.json`: the scene, its cages stored as `storage` says and OBJ sequences referenced relative
    // to it; `.obj`, `.om`, `.ply`, `.off`, `.stl`: the active object's cage alone as the current
    // frame shows it (core/mesh/mesh_cage_write.h; `lost` names what PLY, OFF and STL cannot hold). Any
    // other name is refused.
    Status save(const std::string& path, CageStorage storage, std::vector<std::string>* lost = nullptr);

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
    // The sculpting mask as a whole: inverted (m -> 1 - m) or cleared, one entry each; clearing a
    // mask that masks nothing makes no entry (changedSamples 0).
    Result<EditOutcome> invertMask();
    Result<EditOutcome> clearMask();

    Result<EditOutcome> undo();
    Result<EditOutcome> redo();
    Result<EditOutcome> jumpTo(size_t position);

    // ---- animation ----
    double frame() const { return frame_; }
    Timeline timeline() const { return timelineOf(scene_); }
    const ObjectAnimation& animation() const { return scene_.objects[active_].animation; }
    // The active object's rest positions (its positions when it has no vertex keys).
    const std::vector<glm::vec3>& restPositions() const { return rest_[planned_.cageOfObject[active_]]; }
    // Shows `frame` (any finite number; between keys it is interpolated). Re-plans nothing; the
    // report's counts add up every object's, its lists are the active object's.
    Result<EditOutcome> setFrame(double frame);
    // Keys `vertices` of the active object at `frame` (none: the current frame, which must then
    // be whole) at `positions`, or, without them, where the animation has them at that frame.
    Result<EditOutcome> setKeys(std::span<const uint32_t> vertices, const std::optional<std::vector<glm::vec3>>& positions,
                                std::optional<int64_t> frame);
    // Removes every vertex key of the active object at `frame` (refused when it has none there).
    Result<EditOutcome> removeKeys(int64_t frame);
    Status setTransformKey(const std::string& name, int64_t frame, const ObjectTransform& transform);
    // Removes object `name`'s transform key at `frame` (refused, naming both, when it has none
    // there); without keys left the object keeps the transform it shows now.
    Status removeTransformKey(const std::string& name, int64_t frame);
    Result<EditOutcome> setInterpolation(Interpolation interpolation);
    Status setTimeline(int64_t first, int64_t last, double framesPerSecond);
    // Makes an OBJ sequence (core/animation/cage_sequence.h) the active object's vertex keys, one per
    // vertex per file, keyed at the file's number; all frames are read before anything changes
    // and a bad one is refused naming it.
    Result<EditOutcome> loadSequence(const std::string& pattern);

    // Plans of the current cage vs planning it from scratch (empty when equal).
    std::vector<std::string> differencesFromRebuild() const { return planned().differencesFromRebuild(); }

private:
    SceneDocument() = default;
    // Records the outcome of an edit of the active object's cage (keeping its rest positions).
    Result<EditOutcome> finish(const std::string& name, Result<EditReport> report);
    // Undoes (or redoes) history entry `entry` on the cage it was made on.
    Result<EditOutcome> step(size_t entry, bool forward);
    Result<EditOutcome> topologyEdit(const std::string& name, Result<TopologyEdit> edit, FollowingMove move = {});
    Result<EditOutcome> replaceDisplacement(const std::string& name, Displacement next);
    Result<EditOutcome> maskOperation(const std::string& name, Result<StrokeRecord> record);
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

    SceneObject& active() { return scene_.objects[active_]; }
    PlannedCage& activeCage() { return planned_.cages[planned_.cageOfObject[active_]]; }
    uint32_t objectIndex(const std::string& name, Status& error) const;
    // The planned cage history entries tagged `tag` (an object id) were made on; the active one
    // for object edits.
    PlannedCage& cageOfTag(uint32_t tag);
    // One history entry giving object `index` these transform keys (set or remove one).
    Status replaceTransformKeys(uint32_t index, const std::string& entryName, std::vector<TransformKey> keys);
    // Object edits: `apply` and `revert` change the scene; recorded as one history entry.
    Status performObjectEdit(const std::string& name, std::function<Status()> apply, std::function<Status()> revert);
    // The same for a change that moves the active object's cage (`apply` and `revert` report the
    // move); `bytes` is what the two hold.
    Result<EditOutcome> performEdit(const std::string& name, std::function<Result<EditReport>()> apply,
                                    std::function<Result<EditReport>()> revert, size_t bytes);

    // Animation.
    bool activeHasVertexKeys() const { return !animation().vertexKeys.empty(); }
    AnimatedCageState animatedState(uint32_t index);
    // The active object's state, looked up by its id whenever a history entry runs.
    AnimationAccess animationAccess();
    // Object `index` at the current frame: its cage shown there (at rest without vertex keys),
    // its transform evaluated there when it has transform keys.
    Result<EditReport> showObject(uint32_t index);
    // The current frame as the frame keys go on: refused (naming `what`) between frames.
    Result<int32_t> keyFrame(const std::string& what) const;
    // With `merge`, a move of the same vertices as the newest entry, a keyed move named `name`
    // (the same frame), replaces that entry: one drag, one entry, as for unkeyed moves.
    Result<EditOutcome> keyedMove(const std::string& name, int32_t frame, std::span<const uint32_t> vertices,
                                  std::span<const glm::vec3> positions, bool merge);
    // Rest positions follow the cage of an object (`id`) without vertex keys, so that keys set
    // later, or an undo back to keys, start from where it is.
    void keepRest(uint32_t id);
    // An object edit that appends `object` (taken out again on undo).
    Status appendObject(const std::string& entryName, SceneObject object);
    uint32_t indexOfId(uint32_t id) const;
    // Inserts an object (with its cage when it has one, planned here) at `index`, or takes it
    // out again; both keep plannedScene()'s indices and the active object valid.
    Status insertObject(uint32_t index, SceneObject object, uint32_t id);
    SceneObject takeObject(uint32_t index);
    void reindex();

    Scene scene_;  // owners' cages are not kept current: planned_ holds them
    PlannedScene planned_;
    std::vector<uint32_t> ids_;           // per object: a stable id (history tags)
    std::vector<uint32_t> cageOwnerIds_;  // per planned cage: the id of the object owning it
    std::vector<std::vector<glm::vec3>> rest_;  // per planned cage: its rest positions
    double frame_ = 1.0;                        // the frame shown
    struct KeyedDrag {
        size_t position;  // the history position after it
        std::vector<uint32_t> vertices;
    };
    std::optional<KeyedDrag> keyedDrag_;  // the newest keyed move, which a merged one may replace
    uint32_t nextId_ = 1;
    uint32_t active_ = 0;  // the object edits act on (one with a cage of its own)
    PlanOptions options_;
    std::shared_ptr<PlanDatabase> database_;
    EditHistory history_;
    std::string source_;
    std::optional<SculptSamples> samples_;
    uint32_t sizeAtLastRelease_ = 0, plansInUseAtLastRelease_ = 0;  // built on the first stroke after a change of layout
};

}  // namespace qp::py
