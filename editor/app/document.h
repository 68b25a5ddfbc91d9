// Document: what the editor has open — the scene settings, the planned cage with its edit
// history, where it came from, whether it has unsaved changes and the selection — and the one
// function every edit goes through.
//
// applyEdit is the single route from any tool, shortcut or automation command to the cage: it
// builds the edit (topology operations of core/mesh/topology_edits.h from the current cage), performs
// it through the EditHistory (core/edit/edit_history.h: PlannedCage re-plans only the affected faces,
// and the entry can be undone), bumps the revisions the renderer and the pickers watch, marks
// the document dirty, updates the selection and records the report for the stats panel.
// undoEdit / redoEdit / jumpToHistory go through the same bookkeeping. Indices are 0-based.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/vec3.hpp>

#include "displacement/brush.h"
#include "displacement/displacement_edit.h"
#include "displacement/sculpt_samples.h"
#include "edit/edit_history.h"
#include "edit/selection.h"
#include "plans/plan_database.h"
#include "plans/planned_cage.h"
#include "scene/scene.h"

#include "cage_extent.h"

namespace qp::editor {

// Move, rotate and scale all arrive as new absolute positions. A drag sends one per frame with
// `continueDrag` set after the first, so the history keeps one entry per drag.
struct MoveVertices {
    std::vector<uint32_t> vertices;
    std::vector<glm::vec3> positions;  // new absolute positions, one per vertex
    bool continueDrag = false;
    std::string name{};  // history entry ("Move", "Rotate", "Scale"); empty: "move N vertices"
};
struct SetEdgeSharpness {
    std::vector<EdgeCrease> edges;  // sharpness 0 clears; >= kInfiniteSharpness is infinitely sharp
};
struct SetVertexSharpness {
    std::vector<VertexCorner> corners;  // sharpness 0 clears
};
struct SetHoles {
    std::vector<uint32_t> faces;
    bool hole = true;
};
struct SetCreaseMethod {
    CreaseMethod method = CreaseMethod::Normal;
};
struct ExtrudeFaces {
    std::vector<uint32_t> faces;
    float distance = 0.0f;  // along each region's normal
};
struct DeleteFaces {
    std::vector<uint32_t> faces;
};
struct SplitFace {
    uint32_t face = 0, a = 0, b = 0;
};
struct InsertEdgeLoop {
    uint32_t a = 0, b = 0;
    float t = 0.5f;  // where the loop crosses edge a-b, from a
};
struct MergeVertices {
    std::vector<uint32_t> vertices;  // the last survives
    MergeTarget target = MergeTarget::Centroid;
};
struct MakeFace {
    std::vector<uint32_t> vertices;  // in order around the face (reversed if its neighbours say so)
};
using Edit = std::variant<MoveVertices, SetEdgeSharpness, SetVertexSharpness, SetHoles, SetCreaseMethod, ExtrudeFaces,
                          DeleteFaces, SplitFace, InsertEdgeLoop, MergeVertices, MakeFace>;

// The history entry's name: "move vertex 3", "extrude 2 faces", "sharpness 2.5 on 4 edges", ...
std::string describeEdit(const Edit& edit);

inline constexpr uint32_t kActiveCage = UINT32_MAX;

struct LastEdit {
    std::string description;
    EditReport report;
    uint64_t frame = 0;  // frame counter when it was applied
};

struct Document {
    // Objects, camera, viewports, tessellation. The active object's `cage` is stale after edits:
    // `planned` holds it (sceneToSave puts them together).
    Scene scene;
    // The object edit mode acts on (an object with a cage of its own; its displacement is the
    // one sculpted). The editor draws and edits this object; the others are kept as loaded and
    // saved with the scene.
    uint32_t activeObject = 0;
    std::unique_ptr<PlanDatabase> database;  // heap: `planned` points at it
    // The other objects' cages (shown, not edited, in this editor): planned at open through the
    // same database; per object, the index of the cage it draws in otherCages, or kActiveCage
    // for the active object and its instances (they draw `planned`).
    std::vector<PlannedCage> otherCages;
    std::vector<Bounds> otherCageBounds;  // of each, in its own coordinates (they do not change)
    std::vector<uint32_t> otherCageOwnerIds;  // of each, the id of the object owning it
    std::vector<uint32_t> otherCageOfObject;
    // Per object, a stable id (objects are renumbered when one is added or removed): history
    // entries carry the id of the object whose cage they changed, object edits 0.
    std::vector<uint32_t> objectIds;
    uint32_t nextObjectId = 1;
    // The object picked in object mode (any object, an instance too); 0: none.
    uint32_t selectedObjectId = 0;
    PlanOptions planOptions;  // what every cage of the document is planned with
    // objectsRevision changes when objects are added or removed or edit mode moves to another
    // cage (otherCages is rebuilt: what was made from it starts afresh); editedCageRevision when
    // edit mode moves to another cage (what was made from `planned` starts afresh too);
    // sceneRevision with any object edit (a transform, visibility, a name) as well.
    uint64_t objectsRevision = 0, editedCageRevision = 0, sceneRevision = 0;
    uint64_t storedMisses = 0;               // plans built when the plan cache was last written
    std::optional<PlannedCage> planned;
    EditHistory history;
    std::string path;  // file loaded from or last saved to; empty: untitled
    bool dirty = false;
    // The history position of the state last loaded or saved; unset when no undo or redo can
    // return to it (a new edit dropped it). Undoing or redoing back to it makes `dirty` false.
    std::optional<size_t> savedPosition = 0;
    // Revisions the renderer and the pickers compare with what they were built from. Every
    // applied edit, undo or redo bumps positionRevision (a consumer diffs the positions to find
    // which vertices moved); planRevision when plans or tags changed; topologyRevision when
    // faces or vertices were renumbered (then planRevision too).
    uint64_t positionRevision = 0;
    uint64_t planRevision = 0;
    uint64_t topologyRevision = 0;
    // The latest change of positions when it was a move of some vertices and nothing else (a drag
    // step): consumers one revision behind update those vertices instead of comparing every
    // position (PositionStep::from is the revision it started from; kNone after any other change).
    PositionStep lastMove;
    // The edited cage's extent, computed when first asked for at a revision (cageExtent).
    mutable CageExtent extent;
    Selection selection;
    std::optional<LastEdit> lastEdit;

    // Sculpted displacement (the active object's; the functions under "Displacement" below).
    // displacementRevision changes whenever it was replaced whole (new, resampled, cleared, or
    // such an edit undone); sampleRevision whenever samples changed in place (a dab, a stroke
    // undone or redone), the samples then being appended to unsyncedSamples until the renderer
    // has taken them (takeUnsyncedSamples).
    uint64_t displacementRevision = 0, sampleRevision = 0;
    // maskRevision changes whenever the sculpting mask changed (a mask stroke, invert, clear, one
    // undone or redone, a new displacement): the mask overlay redraws then. Mask changes leave
    // sampleRevision alone (D did not change; renderers ignore the mask).
    uint64_t maskRevision = 0;
    std::vector<uint32_t> unsyncedSamples;
    // A second reader of the same list, the displaced picker (editor/app/pick_cache.h), reads
    // it as a stream: entry k of everything ever listed is takenSamples[k - takenBefore] while
    // k is among those takeUnsyncedSamples handed over (kept here as listed), then
    // unsyncedSamples. What was handed over is dropped, but for the latest batch, once it
    // outgrows the samples: a reader that far behind starts afresh. A new layout (which clears
    // unsyncedSamples) makes readers start afresh too.
    std::vector<uint32_t> takenSamples;
    uint64_t takenBefore = 0;
    // What tag and topology edits (and their undo and redo) re-planned since the renderer last
    // took it (takeUnsyncedPlanChange): the sub-faces a scheme may update in place.
    EditReport unsyncedPlanChange;
    // Where the samples lie on the limit surface (built on the first stroke of a layout,
    // refreshed after vertex moves, dropped after new plans or a new layout), and the stroke
    // in progress.
    std::optional<SculptSamples> sculptSamples;
    std::optional<Sculptor> sculptor;
    // The stroke in progress made the displacement (the scene had none): its history entry
    // then replaces "no displacement" by the stroke's result, so one undo removes both.
    bool strokeMadeDisplacement = false;

    // Faces hidden from view and from picking (H / Alt+H; sorted). Not an edit and not saved:
    // a view of the cage. A topology edit (or its undo) carries it to the faces' new numbers;
    // faces it removes or rebuilds leave it.
    // hiddenRevision changes with it.
    std::vector<uint32_t> hiddenFaces;
    uint64_t hiddenRevision = 0;

    // Cage animation (document_animation.h). The frame every animated cage and keyed transform
    // shows (keys sit on whole frames; between them the tracks interpolate), whether the
    // editor's clock is playing it, and whether playback wraps at the timeline's end.
    double currentFrame = 1.0;
    bool playing = false, loopPlayback = true;
    // What showing the last frame did (every animated cage moved: no face re-planned).
    EditReport lastFrameChange;
    // Changes when the cages in otherCages moved (they animate too): the renderer updates their
    // instances and the object picker rebuilds.
    uint64_t otherPositionRevision = 0;
    // The keyed drag in progress (its entry is the newest): later steps replace the entry, so a
    // drag on an animated cage stays one entry as on any other.
    struct KeyedDrag {
        size_t position = 0;  // history position just after the entry
        uint32_t tag = 0;
        int32_t frame = 0;
        std::vector<uint32_t> vertices;
    };
    std::optional<KeyedDrag> keyedDrag;
    // What the last applyEdit did to the animation ("keyed 3 vertices at frame 12"); empty for
    // a cage without keys. The status line shows it.
    std::string animationNote;
};

// The object edit mode acts on; only while a document is open (`planned` set).
SceneObject& activeObject(Document& document);
const SceneObject& activeObject(const Document& document);
// Its displacement, or an empty one while nothing is open (a recovery offer, a load).
const Displacement& displacementOf(const Document& document);
// The world bounds of every visible object (the active cage's when nothing else is set up).
Bounds documentBounds(const Document& document);
// The edited cage's bounds and mean edge length (cage_extent.h), carried through drag steps.
const CageExtent& cageExtent(const Document& document);

// Plans the cage of `scene`'s first object (or of the object it instances) into a new document (planning runs in parallel; can take seconds).
// `planCache`: the persistent plan cache to copy plans from before building any (core/plans/plan_cache.h).
Result<std::unique_ptr<Document>> createDocument(Scene scene, const std::string& path, const PlanOptions& options,
                                                 std::shared_ptr<const PlanDatabase> planCache = nullptr);
// Writes the plans the document built since the last call into the persistent plan cache; the
// reason when that failed (nothing is lost but the cache's copy).
std::optional<std::string> storeNewPlans(Document& doc);

// "name.json" or "untitled", with "*" when dirty.
std::string documentTitle(const Document& document);

// Performs an edit of the scene's objects (document_objects.h: its redo applies it) and records
// it as a history entry with tag 0 (no cage: undo does not switch the cage edit mode acts on).
Result<EditReport> performObjectEdit(Document& document, const std::string& name, std::unique_ptr<CustomEdit> edit,
                                     uint64_t frame);

// Applies the edit (see the header comment). Fails, changing nothing, on bad input: indices out
// of range, no such edge, a negative or non-finite value, an operation the cage refuses. On a
// cage with keys, a move keys the moved vertices at the current frame and a topology edit
// carries the keys (document_animation.h); an edit while playing pauses first.
Result<EditReport> applyEdit(Document& document, const Edit& edit, uint64_t frame);
// Records an entry of the edited cage made elsewhere (inserting or deleting keys) with the same
// bookkeeping as applyEdit: revisions, dirty flag, the last edit.
Result<EditReport> performCageEdit(Document& document, const std::string& name, std::unique_ptr<CustomEdit> edit,
                                   uint64_t frame);
Result<EditReport> undoEdit(Document& document, uint64_t frame);
Result<EditReport> redoEdit(Document& document, uint64_t frame);
// Undoes or redoes until `position` entries are applied (0: before the oldest kept entry).
Result<EditReport> jumpToHistory(Document& document, size_t position, uint64_t frame);
// Interactive tools that preview their edit (a live slider, the interactive extrude):
// replaceLastEdit undoes the newest entry and applies `edit` in its place (on failure the
// entry is redone), so a slider drag stays one entry; revertTo goes back to `position`
// entries and forgets the undone ones, leaving no trace of a cancelled preview.
Result<EditReport> replaceLastEdit(Document& document, const Edit& edit, uint64_t frame);
Result<EditReport> revertTo(Document& document, size_t position, uint64_t frame);

// Hiding faces: hideFaces adds faces to the hidden set (and drops them, and the vertices and
// edges no shown face uses, from the selection); unhideAll clears it. isFaceHidden is a binary
// search; elementHidden says whether a vertex or an edge has no shown face around it.
Status hideFaces(Document& document, std::span<const uint32_t> faces);
void unhideAll(Document& document);
bool isFaceHidden(const Document& document, uint32_t face);
bool isVertexHidden(const Document& document, uint32_t vertex);
bool isEdgeHidden(const Document& document, EdgeKey edge);
// Drops hidden elements from a selection of the document's cage.
void dropHidden(const Document& document, Selection& selection);

// Selection. selectElements checks the indices (edges must exist) and combines them with `op`
// in `mode` (switching the selection to that mode first, as setSelectionMode does).
Status selectElements(Document& document, SelectionMode mode, std::span<const uint32_t> elements, SelectOp op);
Status selectEdges(Document& document, std::span<const EdgeKey> edges, SelectOp op);
// Converts the selection (Blender's rules, core/edit/selection.h).
void setSelectionMode(Document& document, SelectionMode mode);
void clearSelection(Document& document);
// Phase-1 helpers, kept for scripts: one vertex (add: toggle it), one edge.
Status selectVertex(Document& document, uint32_t vertex, bool add);
Status selectEdge(Document& document, uint32_t a, uint32_t b);
// The selection's faces (face mode: as selected; otherwise faces with every corner selected).
std::vector<uint32_t> selectedFaces(const Document& document);
std::vector<EdgeKey> selectedEdges(const Document& document);  // edge mode, or edges between selected vertices

// ---- Displacement ------------------------------------------------------------------------
// A stroke spans many frames: beginStroke, dabs as the cursor moves, then endStroke records
// the whole stroke as ONE history entry (undo per stroke) or cancelStroke restores the samples.
// A scene without displacement gets a zero one at `newResolution` on the first stroke, in the
// same history entry as the stroke (undoing it removes both). Strokes reach across faces, creases and extraordinary
// vertices without seams (core/displacement/brush.h); they move no cage vertex and re-plan nothing.
Status beginStroke(Document& document, uint32_t newResolution, uint64_t frame);
bool strokeActive(const Document& document);
// Continues the stroke to a point near the limit surface (Sculptor::dabTo: the first call dabs
// there, later ones every spacing along the way). Returns the samples changed.
uint32_t strokeTo(Document& document, const StrokeOptions& options, const glm::vec3& point);
// One dab at `centre` within the stroke, wherever the previous one was (measurements, tests).
uint32_t strokeDab(Document& document, const StrokeOptions& options, const glm::vec3& centre);
// Ends the stroke: a history entry called `name` when it changed any sample (the report says
// nothing was re-planned), nothing otherwise.
Result<EditReport> endStroke(Document& document, const std::string& name, uint64_t frame);
void cancelStroke(Document& document);
// Every sub-face at `resolution` (resampled: the shape stays), or a new zero displacement.
Result<EditReport> setDisplacementResolution(Document& document, uint32_t resolution, uint64_t frame);
Result<EditReport> clearDisplacement(Document& document, uint64_t frame);
// Where the mirror planes of mirrored strokes pass (the samples' bounding-box centre, as the
// brushes use; the cage's before the first stroke).
glm::vec3 mirrorCentreOf(const Document& document);
// The samples cache for the current layout (built on first use).
const SculptSamples& sculptSamplesOf(Document& document);
// The samples changed in place since the last call (sorted, each once).
std::vector<uint32_t> takeUnsyncedSamples(Document& document);
// The sculpting mask (Displacement::mask; mask strokes are strokes with a mask brush): every
// sample's mask m -> 1 - m, or every mask value to 0. Each is one history entry; they fail
// without a displacement or during a stroke, and clearing a mask that masks nothing makes no
// entry (the report is empty then).
Result<EditReport> invertSculptMask(Document& document, uint64_t frame);
Result<EditReport> clearSculptMask(Document& document, uint64_t frame);
// What DisplacementEdit entries report to (revisions, the samples to upload), and how
// document_sculpt.cpp records one (dirty flag, the last edit).
DisplacementListener displacementListener(Document& document);
Result<EditReport> performDisplacementEdit(Document& document, const std::string& name, std::unique_ptr<CustomEdit> edit,
                                           uint64_t frame);
// The plans changed since the last call (EditReport lists sorted; topologyChanged after a
// renumbering), reset to nothing.
EditReport takeUnsyncedPlanChange(Document& document);

// The scene as it would be saved now: the document's scene with the current cage.
Scene sceneToSave(const Document& document);

// Saves to `path` atomically (.json: scene, with the cage inline unless the scene references
// an OBJ, which is then written too; .obj: the cage alone). On success `path` becomes the
// document's path and it is no longer dirty.
Status saveDocument(Document& document, const std::string& path);

}  // namespace qp::editor
