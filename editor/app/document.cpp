#include "document.h"


#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "displacement/displaced_topology_edit.h"
#include "displacement/displacement_edit.h"
#include "document_animation.h"
#include "document_objects.h"
#include "mesh/file_io.h"
#include "mesh/mesh_cage_write.h"
#include "mesh/obj_io.h"
#include "plans/plan_cache.h"

namespace qp::editor {

namespace {

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

std::string sharpnessText(float s) { return s >= kInfiniteSharpness ? "infinite" : number(s); }

std::string count(size_t n, const char* singular, const char* plural) {
    return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

Status checkVertex(const Cage& cage, uint32_t v) {
    if (v >= cage.vertexCount())
        return Error{"vertex " + std::to_string(v) + " does not exist (the cage has " +
                     std::to_string(cage.vertexCount()) + " vertices, numbered from 0)"};
    return success();
}

Status checkFace(const Cage& cage, uint32_t f) {
    if (f >= cage.faceCount())
        return Error{"face " + std::to_string(f) + " does not exist (the cage has " + std::to_string(cage.faceCount()) +
                     " faces, numbered from 0)"};
    return success();
}

Status checkEdge(const PlannedCage& planned, uint32_t a, uint32_t b) {
    if (Status s = checkVertex(planned.cage(), a); !s) return s;
    if (Status s = checkVertex(planned.cage(), b); !s) return s;
    if (planned.topology().findEdge(a, b) == UINT32_MAX)
        return Error{"vertices " + std::to_string(a) + " and " + std::to_string(b) + " (numbered from 0) share no edge"};
    return success();
}

Status checkSharpness(float s, const char* what) {
    if (!std::isfinite(s) || s < 0.0f) return Error{std::string(what) + " must be a number >= 0"};
    return success();
}

// ---- performing each kind of edit through the history ----------------------------------------

Result<EditReport> perform(Document& doc, const MoveVertices& move, const std::string& name) {
    if (move.vertices.size() != move.positions.size()) return Error{"move: one position per vertex is needed"};
    for (size_t i = 0; i < move.vertices.size(); ++i) {
        if (Status s = checkVertex(doc.planned->cage(), move.vertices[i]); !s) return s.error();
        const glm::vec3& p = move.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return Error{"move: the new position of vertex " + std::to_string(move.vertices[i]) + " is not finite"};
    }
    if (hasVertexKeys(activeObject(doc))) return performKeyedMove(doc, name, move.vertices, move.positions, move.continueDrag);
    return doc.history.moveVertices(*doc.planned, name, move.vertices, move.positions, move.continueDrag);
}

Result<EditReport> perform(Document& doc, const SetEdgeSharpness& crease, const std::string& name) {
    if (crease.edges.empty()) return Error{"no edges to crease: select edges first"};
    for (const EdgeCrease& e : crease.edges) {
        if (Status s = checkEdge(*doc.planned, e.v0, e.v1); !s) return s.error();
        if (Status s = checkSharpness(e.sharpness, "edge sharpness"); !s) return s.error();
    }
    return doc.history.setEdgeSharpness(*doc.planned, name, crease.edges);
}

Result<EditReport> perform(Document& doc, const SetVertexSharpness& corner, const std::string& name) {
    if (corner.corners.empty()) return Error{"no vertices for a corner: select vertices first"};
    for (const VertexCorner& c : corner.corners) {
        if (Status s = checkVertex(doc.planned->cage(), c.vertex); !s) return s.error();
        if (Status s = checkSharpness(c.sharpness, "corner sharpness"); !s) return s.error();
    }
    return doc.history.setVertexSharpness(*doc.planned, name, corner.corners);
}

Result<EditReport> perform(Document& doc, const SetHoles& holes, const std::string& name) {
    if (holes.faces.empty()) return Error{"no faces: select faces first"};
    for (uint32_t f : holes.faces)
        if (Status s = checkFace(doc.planned->cage(), f); !s) return s.error();
    return doc.history.setHoles(*doc.planned, name, holes.faces, holes.hole);
}

Result<EditReport> perform(Document& doc, const SetCreaseMethod& method, const std::string& name) {
    return doc.history.setCreaseMethod(*doc.planned, name, method.method);
}

Result<TopologyEdit> operation(const Document& doc, const ExtrudeFaces& e) {
    if (!std::isfinite(e.distance)) return Error{"extrude: the distance is not a number"};
    return extrudeFaces(doc.planned->cage(), doc.planned->topology(), e.faces, e.distance);
}
Result<TopologyEdit> operation(const Document& doc, const DeleteFaces& e) {
    return deleteFaces(doc.planned->cage(), doc.planned->topology(), e.faces, true);
}
Result<TopologyEdit> operation(const Document& doc, const SplitFace& e) {
    if (Status s = checkFace(doc.planned->cage(), e.face); !s) return s.error();
    return splitFace(doc.planned->cage(), doc.planned->topology(), e.face, e.a, e.b);
}
Result<TopologyEdit> operation(const Document& doc, const InsertEdgeLoop& e) {
    return insertEdgeLoop(doc.planned->cage(), doc.planned->topology(), e.a, e.b, e.t);
}
Result<TopologyEdit> operation(const Document& doc, const MergeVertices& e) {
    return mergeVertices(doc.planned->cage(), doc.planned->topology(), e.vertices, e.target);
}
Result<TopologyEdit> operation(const Document& doc, const MakeFace& e) {
    return makeFace(doc.planned->cage(), doc.planned->topology(), e.vertices);
}

// What a topology edit suggests selecting afterwards (TopologyEdit's result lists).
struct SuggestedSelection {
    std::vector<uint32_t> vertices;
    std::vector<EdgeKey> edges;
    std::vector<uint32_t> faces;
};

// With displacement the entry carries it to the new cage (displaced_topology_edit.h); an
// extrude by a distance is made in place, the sculpt projected, and then moved out.
template <class Op>
Result<EditReport> performTopology(Document& doc, const Op& op, const std::string& name, SuggestedSelection* suggested) {
    // A stroke's record and samples cache belong to the displacement's layout, which the edit
    // replaces.
    if (strokeActive(doc)) return Error{"finish the stroke first"};
    Result<TopologyEdit> edit = operation(doc, op);
    if (!edit) return edit.error();
    // Read after the history takes the edit (a copy of the whole edit would copy the cage).
    *suggested = {edit->resultVertices, edit->resultEdges, edit->resultFaces};
    const bool keyed = hasVertexKeys(activeObject(doc));
    Displacement& displacement = activeObject(doc).displacement;
    if (displacement.empty()) {
        if (keyed) return performAnimatedTopologyEdit(doc, name, animatedTopologyStep(doc, *edit));
        return doc.history.applyTopologyEdit(*doc.planned, name, std::move(edit).value());
    }
    FollowingMove move;
    if constexpr (std::is_same_v<Op, ExtrudeFaces>) {
        if (op.distance != 0.0f && !keyed) {
            Result<SplitExtrude> split = splitExtrude(doc.planned->cage(), doc.planned->topology(), op.faces, op.distance);
            if (!split) return split.error();
            edit = std::move(split->inPlace);
            move = std::move(split->move);
        }
    }
    std::unique_ptr<CustomEdit> step = keyed ? animatedTopologyStep(doc, *edit) : makeTopologyStep(*doc.planned, *edit);
    auto entry = makeDisplacedTopologyEdit(std::move(step), displacement, displacementListener(doc), std::move(move));
    if (keyed) return performAnimatedTopologyEdit(doc, name, std::move(entry));
    return doc.history.perform(*doc.planned, name, std::move(entry));
}

// After a topology edit: what the operation suggests, in the current mode when it has
// elements of that mode, else converted from what it has.
void selectResult(Document& doc, const SuggestedSelection& suggested) {
    const Cage& cage = doc.planned->cage();
    const Topology& topology = doc.planned->topology();
    Selection result;
    const SelectionMode mode = doc.selection.mode;
    if (mode == SelectionMode::Face && !suggested.faces.empty()) {
        result.mode = mode, result.faces = suggested.faces;
    } else if (mode == SelectionMode::Edge && !suggested.edges.empty()) {
        result.mode = mode, result.edges = suggested.edges;
    } else if (mode == SelectionMode::Vertex && !suggested.vertices.empty()) {
        result.mode = mode, result.vertices = suggested.vertices;
    } else {
        if (!suggested.faces.empty()) result.mode = SelectionMode::Face, result.faces = suggested.faces;
        else if (!suggested.edges.empty()) result.mode = SelectionMode::Edge, result.edges = suggested.edges;
        else result.mode = SelectionMode::Vertex, result.vertices = suggested.vertices;
        result = convertSelection(result, mode, cage, topology);
    }
    doc.selection = std::move(result);
}

// Drops selected elements that no longer exist (after an undo or redo renumbered the cage).
void pruneSelection(Document& doc) {
    const Cage& cage = doc.planned->cage();
    Selection& s = doc.selection;
    std::erase_if(s.vertices, [&](uint32_t v) { return v >= cage.vertexCount(); });
    std::erase_if(s.faces, [&](uint32_t f) { return f >= cage.faceCount(); });
    std::erase_if(s.edges, [&](const EdgeKey& e) {
        return e.v1 >= cage.vertexCount() || doc.planned->topology().findEdge(e.v0, e.v1) == UINT32_MAX;
    });
}

// After a new history entry: the saved state stays reachable through undo unless the entry
// dropped the redo entries leading to it, extended the entry that ended at it (a continued
// drag), or the history's budget dropped the oldest entries up to it.
void forgetUnreachableSave(Document& doc, bool extendedDrag, size_t before, size_t sizeBefore) {
    if (!doc.savedPosition) return;
    size_t& saved = *doc.savedPosition;
    const bool extended = extendedDrag && doc.history.position() == before && doc.history.size() == sizeBefore;
    if (extended) {
        if (saved >= before) doc.savedPosition.reset();
        return;
    }
    if (saved > before) {
        doc.savedPosition.reset();
        return;
    }
    const size_t trimmed = before + 1 > doc.history.position() ? before + 1 - doc.history.position() : 0;
    if (saved < trimmed) doc.savedPosition.reset();
    else saved -= trimmed;
}

// The brushes' sample cache after a change of the surface: moved sub-faces re-evaluated, a
// new topology or new plans a new cache.
void keepSculptSamples(Document& doc, const EditReport& report) {
    if (!doc.sculptSamples) return;
    if (report.topologyChanged || report.replannedFaces > 0) doc.sculptSamples.reset();
    else if (!report.updatedSubfaceList.empty()) doc.sculptSamples->refresh(*doc.planned, report.updatedSubfaceList);
}

// Dirty flag, the stats panel's record and the brushes' cache, after any history step.
void noteHistoryStep(Document& doc, const std::string& description, const EditReport& report, uint64_t frame) {
    doc.dirty = !(doc.savedPosition && *doc.savedPosition == doc.history.position());
    doc.lastEdit = LastEdit{description, report, frame};
    keepSculptSamples(doc, report);
}

// The same with the revisions the renderer and pickers watch, for any change to the cage.
// `positionsKept`: the change moved no vertex (a tag edit, or its undo or redo), recorded as a
// step of none so that consumers need not compare every position; applyEdit records a drag
// step after this.
void noteChange(Document& doc, const std::string& description, const EditReport& report, uint64_t frame,
                bool positionsKept = false) {
    ++doc.positionRevision;
    doc.lastMove = PositionStep{};
    if (positionsKept) doc.lastMove.from = doc.positionRevision - 1;
    if (report.replannedFaces > 0 || report.topologyChanged) {
        ++doc.planRevision;
        accumulateReport(doc.unsyncedPlanChange, report);
    }
    if (report.topologyChanged) ++doc.topologyRevision;
    if (report.topologyChanged && !doc.hiddenFaces.empty()) {  // hidden faces that were kept stay hidden
        std::vector<uint32_t> hidden;
        for (uint32_t f = 0; f < report.previousFaceOf.size(); ++f)
            if (report.previousFaceOf[f] != kNewElement &&
                std::binary_search(doc.hiddenFaces.begin(), doc.hiddenFaces.end(), report.previousFaceOf[f]))
                hidden.push_back(f);
        doc.hiddenFaces = std::move(hidden);
        ++doc.hiddenRevision;
    }
    noteHistoryStep(doc, description, report, frame);
}

}  // namespace

// The history's DisplacementEdit entries report here (performed, undone or redone), so the
// renderer and the brushes see every change whichever route made it.
DisplacementListener displacementListener(Document& doc) {
    return [&doc](const DisplacementChange& change) {
        if (change.newLayout) {
            ++doc.displacementRevision;
            ++doc.maskRevision;
            doc.unsyncedSamples.clear();
            doc.sculptSamples.reset();
            return;
        }
        if (change.maskOnly) {  // D did not change: nothing to upload or re-pick
            ++doc.maskRevision;
            return;
        }
        ++doc.sampleRevision;
        for (const SampleChange& c : change.samples) doc.unsyncedSamples.push_back(c.sample);
    };
}

// Records a displacement entry the history just took (the listener already bumped revisions).
Result<EditReport> performDisplacementEdit(Document& doc, const std::string& name, std::unique_ptr<CustomEdit> edit,
                                           uint64_t frame) {
    const size_t before = doc.history.position(), sizeBefore = doc.history.size();
    Result<EditReport> report = doc.history.perform(*doc.planned, name, std::move(edit));
    if (!report) return report;
    forgetUnreachableSave(doc, false, before, sizeBefore);
    noteHistoryStep(doc, name, *report, frame);
    return report;
}

std::string describeEdit(const Edit& edit) {
    struct Describe {
        std::string operator()(const MoveVertices& e) const {
            const std::string verb = e.name.empty() ? "move" : e.name;
            std::string lower = verb;
            std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            return e.vertices.size() == 1 ? lower + " vertex " + std::to_string(e.vertices[0])
                                          : lower + " " + std::to_string(e.vertices.size()) + " vertices";
        }
        std::string operator()(const SetEdgeSharpness& e) const {
            if (e.edges.size() == 1)
                return "sharpness of edge " + std::to_string(e.edges[0].v0) + "-" + std::to_string(e.edges[0].v1) + " = " +
                       sharpnessText(e.edges[0].sharpness);
            const bool same = std::all_of(e.edges.begin(), e.edges.end(),
                                          [&](const EdgeCrease& c) { return c.sharpness == e.edges[0].sharpness; });
            if (same && !e.edges.empty() && e.edges[0].sharpness == 0.0f) return "clear crease on " + count(e.edges.size(), "edge", "edges");
            return "sharpness " + (same && !e.edges.empty() ? sharpnessText(e.edges[0].sharpness) + " " : std::string()) +
                   "on " + count(e.edges.size(), "edge", "edges");
        }
        std::string operator()(const SetVertexSharpness& e) const {
            const bool clear = !e.corners.empty() && e.corners[0].sharpness == 0.0f;
            return (clear ? std::string("clear corner on ")
                          : "corner sharpness " + (e.corners.empty() ? std::string() : sharpnessText(e.corners[0].sharpness)) + " on ") +
                   count(e.corners.size(), "vertex", "vertices");
        }
        std::string operator()(const SetHoles& e) const {
            return std::string(e.hole ? "make hole of " : "fill hole of ") + count(e.faces.size(), "face", "faces");
        }
        std::string operator()(const SetCreaseMethod& e) const {
            return std::string("crease method ") + (e.method == CreaseMethod::Chaikin ? "Chaikin" : "normal");
        }
        std::string operator()(const ExtrudeFaces& e) const {
            return "extrude " + count(e.faces.size(), "face", "faces") + " by " + number(e.distance);
        }
        std::string operator()(const DeleteFaces& e) const { return "delete " + count(e.faces.size(), "face", "faces"); }
        std::string operator()(const SplitFace& e) const {
            return "split face " + std::to_string(e.face) + " (" + std::to_string(e.a) + "-" + std::to_string(e.b) + ")";
        }
        std::string operator()(const InsertEdgeLoop& e) const {
            return "edge loop through " + std::to_string(e.a) + "-" + std::to_string(e.b) + " at " + number(e.t);
        }
        std::string operator()(const MergeVertices& e) const {
            return "merge " + count(e.vertices.size(), "vertex", "vertices") +
                   (e.target == MergeTarget::Centroid ? " at the centre" : " at the last");
        }
        std::string operator()(const MakeFace& e) const { return "make face from " + count(e.vertices.size(), "vertex", "vertices"); }
    };
    return std::visit(Describe{}, edit);
}

Result<std::unique_ptr<Document>> createDocument(Scene scene, const std::string& path, const PlanOptions& options,
                                                 std::shared_ptr<const PlanDatabase> planCache) {
    if (Status valid = validateObjects(scene.objects, path.empty() ? "scene" : path); !valid) return valid.error();
    auto doc = std::make_unique<Document>();
    doc->activeObject = (*cageOwners(scene.objects))[0];
    doc->database = std::make_unique<PlanDatabase>();
    doc->database->setFallback(std::move(planCache));
    Result<PlannedCage> planned = PlannedCage::create(scene.objects[doc->activeObject].cage, *doc->database, options,
                                                      path.empty() ? "cage" : path);
    if (!planned) return planned.error();
    doc->planned.emplace(std::move(planned).value());
    const std::vector<uint32_t> owners = *cageOwners(scene.objects);
    doc->otherCageOfObject.assign(scene.objects.size(), kActiveCage);
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        if (owners[i] != i || i == doc->activeObject) continue;
        Result<PlannedCage> other = PlannedCage::create(scene.objects[i].cage, *doc->database, options,
                                                        (path.empty() ? "scene" : path) + ": object \"" + scene.objects[i].name + "\"");
        if (!other) return other.error();
        doc->otherCageOfObject[i] = uint32_t(doc->otherCages.size());
        doc->otherCageBounds.push_back(computeBounds(other->cage()));
        doc->otherCageOwnerIds.push_back(i + 1);
        doc->otherCages.push_back(std::move(other).value());
    }
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        doc->otherCageOfObject[i] = doc->otherCageOfObject[owners[i]];
        doc->objectIds.push_back(i + 1);
    }
    doc->nextObjectId = uint32_t(scene.objects.size()) + 1;
    doc->selectedObjectId = doc->objectIds[doc->activeObject];
    doc->history.setTag(doc->objectIds[doc->activeObject]);
    doc->planOptions = options;
    doc->scene = std::move(scene);
    doc->path = path;
    // An animated scene opens on its first frame (the cages were planned at rest).
    if (isAnimated(doc->scene))
        if (Result<EditReport> shown = goToFrame(*doc, documentTimeline(*doc).firstFrame); !shown) return shown.error();
    return doc;
}

std::optional<std::string> storeNewPlans(Document& doc) {
    if (!doc.database) return std::nullopt;
    const uint64_t misses = doc.database->misses();
    if (misses == doc.storedMisses) return std::nullopt;
    doc.storedMisses = misses;
    if (Status stored = storeInPlanCache(*doc.database); !stored) return stored.error().message;
    return std::nullopt;
}

std::string documentTitle(const Document& doc) {
    std::string name = doc.path.empty() ? "untitled" : std::filesystem::path(doc.path).filename().string();
    return doc.dirty ? name + "*" : name;
}

Result<EditReport> applyEdit(Document& doc, const Edit& edit, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    doc.animationNote = settleFrameForEdit(doc);
    const std::string name = describeEdit(edit);
    const size_t before = doc.history.position(), sizeBefore = doc.history.size();
    // A move of vertices alone (not through animation keys, which may move others) is a step
    // that consumers can follow vertex by vertex: the moved vertices and where they were.
    std::optional<PositionStep> moveStep;
    if (const auto* move = std::get_if<MoveVertices>(&edit); move && !hasVertexKeys(activeObject(doc))) {
        moveStep.emplace();
        moveStep->vertices = move->vertices;
        std::sort(moveStep->vertices.begin(), moveStep->vertices.end());
        moveStep->vertices.erase(std::unique(moveStep->vertices.begin(), moveStep->vertices.end()), moveStep->vertices.end());
        const Cage& cage = doc.planned->cage();
        for (uint32_t v : moveStep->vertices)
            if (v < cage.vertexCount()) moveStep->before.push_back(cage.positions[v]);
        if (moveStep->before.size() != moveStep->vertices.size()) moveStep.reset();  // refused below
    }
    std::optional<SuggestedSelection> topology;
    Result<EditReport> report = std::visit(
        [&](const auto& e) -> Result<EditReport> {
            using T = std::decay_t<decltype(e)>;
            if constexpr (std::is_same_v<T, MoveVertices> || std::is_same_v<T, SetEdgeSharpness> ||
                          std::is_same_v<T, SetVertexSharpness> || std::is_same_v<T, SetHoles> ||
                          std::is_same_v<T, SetCreaseMethod>) {
                return perform(doc, e, name);
            } else {
                topology.emplace();
                return performTopology(doc, e, name, &*topology);
            }
        },
        edit);
    if (!report) return report;
    const auto* move = std::get_if<MoveVertices>(&edit);
    forgetUnreachableSave(doc, move && move->continueDrag, before, sizeBefore);
    // A drag merged into the previous entry reports only its last step; the history keeps the
    // entry's name.
    const bool tagEdit = std::holds_alternative<SetEdgeSharpness>(edit) || std::holds_alternative<SetVertexSharpness>(edit) ||
                         std::holds_alternative<SetHoles>(edit) || std::holds_alternative<SetCreaseMethod>(edit);
    noteChange(doc, name, *report, frame, tagEdit);
    if (moveStep) {
        moveStep->from = doc.positionRevision - 1;
        doc.lastMove = std::move(*moveStep);
    }
    if (topology) selectResult(doc, *topology);
    return report;
}

Result<EditReport> performCageEdit(Document& doc, const std::string& name, std::unique_ptr<CustomEdit> edit, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    const size_t before = doc.history.position(), sizeBefore = doc.history.size();
    Result<EditReport> report = doc.history.perform(*doc.planned, name, std::move(edit));
    if (!report) return report;
    forgetUnreachableSave(doc, false, before, sizeBefore);
    noteChange(doc, name, *report, frame);
    return report;
}

namespace {

// Undoes (back) or redoes the next history entry on the cage it was made on: edit mode moves to
// that object's cage first when it is another (Blender's undo across objects).
// `positionsKept` tells whether the step moved no vertex of the cage edited before it.
Result<EditReport> historyStep(Document& doc, bool back, bool& positionsKept) {
    const size_t entry = back ? doc.history.position() - 1 : doc.history.position();
    const uint64_t cageBefore = doc.editedCageRevision;
    if (Status moved = editCageOfTag(doc, doc.history.tag(entry)); !moved) return moved.error();
    positionsKept = doc.editedCageRevision == cageBefore && doc.history.keepsPositions(entry);
    return back ? doc.history.undo(*doc.planned) : doc.history.redo(*doc.planned);
}

}  // namespace

Result<EditReport> undoEdit(Document& doc, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (!doc.history.canUndo()) return Error{"nothing to undo"};
    const std::string name = doc.history.entry(doc.history.position() - 1).name;
    bool positionsKept = false;
    Result<EditReport> report = historyStep(doc, true, positionsKept);
    if (!report) return report;
    noteChange(doc, "undo " + name, *report, frame, positionsKept);
    pruneSelection(doc);
    return report;
}

Result<EditReport> redoEdit(Document& doc, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (!doc.history.canRedo()) return Error{"nothing to redo"};
    const std::string name = doc.history.entry(doc.history.position()).name;
    bool positionsKept = false;
    Result<EditReport> report = historyStep(doc, false, positionsKept);
    if (!report) return report;
    noteChange(doc, "redo " + name, *report, frame, positionsKept);
    pruneSelection(doc);
    return report;
}

Result<EditReport> jumpToHistory(Document& doc, size_t position, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (position > doc.history.size())
        return Error{"the history has " + std::to_string(doc.history.size()) + " entries; position " +
                     std::to_string(position) + " does not exist"};
    if (position == doc.history.position()) return EditReport{};
    EditReport total;
    bool positionsKept = true;
    while (doc.history.position() != position) {
        bool stepKept = false;
        Result<EditReport> step = historyStep(doc, position < doc.history.position(), stepKept);
        if (!step) return step;
        positionsKept = positionsKept && stepKept;
        accumulateReport(total, *step);
    }
    noteChange(doc, "jump to history position " + std::to_string(position), total, frame, positionsKept);
    pruneSelection(doc);
    return total;
}

Result<EditReport> performObjectEdit(Document& doc, const std::string& name, std::unique_ptr<CustomEdit> edit,
                                     uint64_t frame) {
    if (!doc.planned) return Error{"no scene is open"};
    const size_t before = doc.history.position(), sizeBefore = doc.history.size();
    doc.history.setTag(0);
    Result<EditReport> report = doc.history.perform(*doc.planned, name, std::move(edit));
    doc.history.setTag(doc.objectIds[doc.activeObject]);
    if (!report) return report;
    forgetUnreachableSave(doc, false, before, sizeBefore);
    noteHistoryStep(doc, name, *report, frame);
    return report;
}

Result<EditReport> replaceLastEdit(Document& doc, const Edit& edit, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (!doc.history.canUndo()) return applyEdit(doc, edit, frame);
    if (Result<EditReport> undone = undoEdit(doc, frame); !undone) return undone;
    Result<EditReport> report = applyEdit(doc, edit, frame);
    if (!report) (void)redoEdit(doc, frame);
    return report;
}

Result<EditReport> revertTo(Document& doc, size_t position, uint64_t frame) {
    Result<EditReport> report = jumpToHistory(doc, position, frame);
    if (!report) return report;
    doc.history.dropRedo();
    if (doc.savedPosition && *doc.savedPosition > position) doc.savedPosition.reset();
    doc.dirty = !(doc.savedPosition && *doc.savedPosition == doc.history.position());
    return report;
}

Status hideFaces(Document& doc, std::span<const uint32_t> faces) {
    if (!doc.planned) return Error{"no cage is open"};
    for (uint32_t f : faces)
        if (Status s = checkFace(doc.planned->cage(), f); !s) return s;
    std::vector<uint32_t> hidden = doc.hiddenFaces;
    hidden.insert(hidden.end(), faces.begin(), faces.end());
    std::sort(hidden.begin(), hidden.end());
    hidden.erase(std::unique(hidden.begin(), hidden.end()), hidden.end());
    if (hidden == doc.hiddenFaces) return success();
    doc.hiddenFaces = std::move(hidden);
    ++doc.hiddenRevision;
    dropHidden(doc, doc.selection);
    return success();
}

void unhideAll(Document& doc) {
    if (doc.hiddenFaces.empty()) return;
    doc.hiddenFaces.clear();
    ++doc.hiddenRevision;
}

bool isFaceHidden(const Document& doc, uint32_t face) {
    return std::binary_search(doc.hiddenFaces.begin(), doc.hiddenFaces.end(), face);
}

bool isVertexHidden(const Document& doc, uint32_t vertex) {
    if (doc.hiddenFaces.empty() || !doc.planned) return false;
    const Topology& t = doc.planned->topology();
    if (vertex >= doc.planned->cage().vertexCount() || t.vertexFaceCount(vertex) == 0) return false;
    for (uint32_t k = t.vertexFaceOffsets[vertex]; k < t.vertexFaceOffsets[vertex + 1]; ++k)
        if (!isFaceHidden(doc, t.vertexFaces[k])) return false;
    return true;
}

bool isEdgeHidden(const Document& doc, EdgeKey edge) {
    if (doc.hiddenFaces.empty() || !doc.planned) return false;
    const Topology& t = doc.planned->topology();
    const uint32_t e = t.findEdge(edge.v0, edge.v1);
    if (e == UINT32_MAX) return false;
    for (uint32_t k = t.edgeFaceOffsets[e]; k < t.edgeFaceOffsets[e + 1]; ++k)
        if (!isFaceHidden(doc, t.edgeFaces[k])) return false;
    return true;
}

void dropHidden(const Document& doc, Selection& s) {
    if (doc.hiddenFaces.empty()) return;
    std::erase_if(s.faces, [&](uint32_t f) { return isFaceHidden(doc, f); });
    std::erase_if(s.vertices, [&](uint32_t v) { return isVertexHidden(doc, v); });
    std::erase_if(s.edges, [&](const EdgeKey& e) { return isEdgeHidden(doc, e); });
}

Status selectElements(Document& doc, SelectionMode mode, std::span<const uint32_t> elements, SelectOp op) {
    if (!doc.planned) return Error{"no cage is open"};
    if (mode == SelectionMode::Edge) return Error{"edges are selected by their two vertices"};
    const Cage& cage = doc.planned->cage();
    for (uint32_t e : elements)
        if (Status s = mode == SelectionMode::Vertex ? checkVertex(cage, e) : checkFace(cage, e); !s) return s;
    setSelectionMode(doc, mode);
    applyPick(doc.selection, op, elements);
    return success();
}

Status selectEdges(Document& doc, std::span<const EdgeKey> edges, SelectOp op) {
    if (!doc.planned) return Error{"no cage is open"};
    for (const EdgeKey& e : edges)
        if (Status s = checkEdge(*doc.planned, e.v0, e.v1); !s) return s;
    setSelectionMode(doc, SelectionMode::Edge);
    applyPick(doc.selection, op, edges);
    return success();
}

void setSelectionMode(Document& doc, SelectionMode mode) {
    if (doc.selection.mode == mode) return;
    if (!doc.planned) {
        doc.selection = Selection{mode};
        return;
    }
    doc.selection = convertSelection(doc.selection, mode, doc.planned->cage(), doc.planned->topology());
}

void clearSelection(Document& doc) { doc.selection = Selection{doc.selection.mode}; }

Status selectVertex(Document& doc, uint32_t vertex, bool add) {
    const uint32_t one[] = {vertex};
    return selectElements(doc, SelectionMode::Vertex, one, add ? SelectOp::Toggle : SelectOp::Replace);
}

Status selectEdge(Document& doc, uint32_t a, uint32_t b) {
    const EdgeKey one[] = {makeEdgeKey(a, b)};
    return selectEdges(doc, one, SelectOp::Replace);
}

std::vector<uint32_t> selectedFaces(const Document& doc) {
    if (!doc.planned) return {};
    if (doc.selection.mode == SelectionMode::Face) return doc.selection.faces;
    return convertSelection(doc.selection, SelectionMode::Face, doc.planned->cage(), doc.planned->topology()).faces;
}

std::vector<EdgeKey> selectedEdges(const Document& doc) {
    if (!doc.planned) return {};
    if (doc.selection.mode == SelectionMode::Edge) return doc.selection.edges;
    return convertSelection(doc.selection, SelectionMode::Edge, doc.planned->cage(), doc.planned->topology()).edges;
}

EditReport takeUnsyncedPlanChange(Document& doc) {
    return std::exchange(doc.unsyncedPlanChange, {});
}

SceneObject& activeObject(Document& doc) {
    assert(doc.activeObject < doc.scene.objects.size() && "no document is open");
    return doc.scene.objects[doc.activeObject];
}
const SceneObject& activeObject(const Document& doc) { return doc.scene.objects[doc.activeObject]; }

const Displacement& displacementOf(const Document& doc) {
    static const Displacement kNone;
    return doc.activeObject < doc.scene.objects.size() ? activeObject(doc).displacement : kNone;
}

const CageExtent& cageExtent(const Document& doc) {
    CageExtent& extent = doc.extent;
    if (extent.revision == doc.positionRevision && extent.cage == doc.editedCageRevision) return extent;
    const Cage& cage = doc.planned->cage();
    const PositionStep& step = doc.lastMove;
    if (extent.cage == doc.editedCageRevision && step.leads(extent.revision, doc.positionRevision))
        carryExtent(extent, cage, doc.planned->topology(), step);
    else
        extent = measureCage(cage);
    extent.revision = doc.positionRevision;
    extent.cage = doc.editedCageRevision;
    return extent;
}

Bounds documentBounds(const Document& doc) {
    if (!doc.planned) return Bounds{glm::vec3(-1), glm::vec3(1)};
    const Bounds active = cageExtent(doc).bounds;
    Bounds out{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (uint32_t i = 0; i < doc.scene.objects.size() && i < doc.otherCageOfObject.size(); ++i) {
        const SceneObject& o = doc.scene.objects[i];
        if (!o.visible && i != doc.activeObject) continue;
        const uint32_t c = doc.otherCageOfObject[i];
        const Bounds b = transformBounds(c == kActiveCage ? active : doc.otherCageBounds[c], o.transform.matrix());
        out.min = glm::min(out.min, b.min);
        out.max = glm::max(out.max, b.max);
    }
    return out.min.x > out.max.x ? active : out;
}

Scene sceneToSave(const Document& doc) {
    Scene scene = doc.scene;
    SceneObject& active = scene.objects[doc.activeObject];
    std::vector<glm::vec3> rest = std::move(active.cage.positions);
    active.cage = doc.planned->cage();
    if (hasVertexKeys(active)) active.cage.positions = std::move(rest);  // the cage shows a frame
    return scene;
}

Status saveDocument(Document& doc, const std::string& path) {
    if (!doc.planned) return Error{"nothing to save"};
    const std::string ext = lowercaseExtension(path);
    Status saved = success();
    if (ext == ".obj" || ext == ".om") {
        saved = saveMeshCage(doc.planned->cage(), path);
    } else if (ext == ".json") {
        // Save As leaves the files the open scene was read from alone (its cages go to NAME.obj).
        Scene scene = sceneToSave(doc);
        const bool renamed = nameCagesAfterNewScene(scene, doc.path, path);
        saved = saveScene(scene, path, CageStorage::AsLoaded);
        if (saved && renamed)  // later saves write where this one did
            for (uint32_t i = 0; i < scene.objects.size(); ++i) doc.scene.objects[i].cagePath = scene.objects[i].cagePath;
    } else {
        return Error{"cannot save as '" + path + "': the name must end in .json (scene), or .obj or .om (the cage only)"};
    }
    if (!saved) return saved;
    doc.path = path;
    doc.dirty = false;
    doc.savedPosition = doc.history.position();
    return success();
}

}  // namespace qp::editor
