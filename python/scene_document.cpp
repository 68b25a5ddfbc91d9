#include "scene_document.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "animation/animation_playback.h"
#include "animation/cage_sequence.h"
#include "document_checks.h"
#include "mesh/file_io.h"
#include "mesh/mesh_cage_write.h"
#include "mesh/mesh_import.h"
#include "mesh/obj_io.h"
#include "plans/plan_cache.h"

namespace qp::py {

namespace fs = std::filesystem;


Result<std::unique_ptr<SceneDocument>> SceneDocument::create(Scene scene, const PlanOptions& options,
                                                             const std::string& source, std::vector<std::string>* warnings) {
    if (Status valid = validateObjects(scene.objects, source); !valid) return valid.error();
    std::unique_ptr<SceneDocument> document(new SceneDocument());
    document->options_ = options;
    document->database_ = std::make_shared<PlanDatabase>();
    std::string cacheWarning;
    document->database_->setFallback(sharedPlanCache(&cacheWarning));
    Result<PlannedScene> planned = PlannedScene::create(scene, *document->database_, options, source);
    if (!planned) return planned.error();
    if (document->database_->misses() > 0)
        if (Status stored = storeInPlanCache(*document->database_); !stored && cacheWarning.empty())
            cacheWarning = stored.error().message;
    if (!cacheWarning.empty() && warnings) warnings->push_back(cacheWarning);
    document->planned_ = std::move(planned).value();
    for (uint32_t i = 0; i < scene.objects.size(); ++i) document->ids_.push_back(document->nextId_++);
    for (uint32_t owner : document->planned_.objectOfCage) {
        document->cageOwnerIds_.push_back(document->ids_[owner]);
        document->rest_.push_back(std::move(scene.objects[owner].cage.positions));
        scene.objects[owner].cage = Cage{};  // planned_ holds the cages from now on
    }
    document->active_ = document->planned_.objectOfCage[0];
    document->history_.setTag(document->ids_[document->active_]);
    document->scene_ = std::move(scene);
    document->source_ = source;
    // An animated scene opens at its first frame (the cages were planned at rest).
    document->frame_ = timelineOf(document->scene_).firstFrame;
    for (uint32_t i = 0; i < document->scene_.objects.size(); ++i)
        if (Result<EditReport> shown = document->showObject(i); !shown) return shown.error();
    return document;
}

Result<std::unique_ptr<SceneDocument>> SceneDocument::load(const std::string& path, const PlanOptions& options,
                                                           std::vector<std::string>* warnings) {
    Result<Scene> scene = loadSceneOrCage(path, warnings);
    if (!scene) return scene.error();
    return create(std::move(scene).value(), options, path, warnings);
}

std::unique_ptr<SceneDocument> SceneDocument::copy() const {
    std::unique_ptr<SceneDocument> document(new SceneDocument());
    document->scene_ = scene_;
    document->planned_ = planned_;
    document->ids_ = ids_;
    document->cageOwnerIds_ = cageOwnerIds_;
    document->rest_ = rest_;
    document->frame_ = frame_;
    document->nextId_ = nextId_;
    document->active_ = active_;
    document->options_ = options_;
    document->database_ = database_;
    document->source_ = source_;
    document->history_.setTag(ids_[active_]);
    return document;
}

Scene SceneDocument::currentScene() const {
    Scene scene = scene_;
    for (uint32_t c = 0; c < planned_.cages.size(); ++c) {
        Cage& cage = scene.objects[planned_.objectOfCage[c]].cage = planned_.cages[c].cage();
        cage.positions = rest_[c];  // an animated cage at rest: its keys hold the frames' positions
    }
    return scene;
}

Status SceneDocument::save(const std::string& path, CageStorage storage, std::vector<std::string>* lost) {
    const std::string ext = lowercaseExtension(path);
    if (ext == ".json") {
        // A save under another name leaves the files the scene was read from alone.
        Scene scene = currentScene();
        nameCagesAfterNewScene(scene, source_, path);
        return saveScene(scene, path, storage);
    }
    if (ext == ".obj" || isMeshCageExtension(ext)) return saveMeshCage(cage(), path, lost);
    return Error{"cannot save as '" + path + "': the name must end in .json (the scene) or .obj, .om, .ply, .off or .stl (the cage)"};
}

// ---- objects ----------------------------------------------------------------------------

namespace {

// An object edit in the history: the scene changes through the document's own functions, which
// find what they change by id (the planned cage the history passes may not be the one).
class ObjectEdit : public CustomEdit {
public:
    using Step = std::function<Result<EditReport>()>;
    ObjectEdit(Step apply, Step revert, size_t bytes) : apply_(std::move(apply)), revert_(std::move(revert)), bytes_(bytes) {}
    Result<EditReport> redo(PlannedCage&) override { return apply_(); }
    Result<EditReport> undo(PlannedCage&) override { return revert_(); }
    size_t bytes() const override { return bytes_; }

private:
    Step apply_, revert_;
    size_t bytes_;
};

constexpr size_t kObjectEditBytes = 256;  // the entry and its two functions

ObjectEdit::Step reporting(std::function<Status()> step) {
    return [step = std::move(step)]() -> Result<EditReport> {
        if (Status s = step(); !s) return s.error();
        return EditReport{};
    };
}

}  // namespace

uint32_t SceneDocument::objectIndex(const std::string& name, Status& error) const {
    const uint32_t i = findObject(scene_.objects, name);
    if (i == UINT32_MAX) {
        std::string names;
        for (const SceneObject& o : scene_.objects) names += (names.empty() ? "" : ", ") + o.name;
        error = Error{"no object is called \"" + name + "\" (the scene has " + names + ")"};
    }
    return i;
}

Status SceneDocument::setActive(const std::string& name) {
    Status error = success();
    const uint32_t i = objectIndex(name, error);
    if (i == UINT32_MAX) return error;
    if (scene_.objects[i].isInstance())
        return Error{"\"" + name + "\" is an instance of \"" + scene_.objects[i].instanceOf +
                     "\" and has no cage of its own: make \"" + scene_.objects[i].instanceOf + "\" active to edit it"};
    if (i != active_) samples_.reset();
    active_ = i;
    history_.setTag(ids_[active_]);
    return success();
}

uint32_t SceneDocument::indexOfId(uint32_t id) const {
    return uint32_t(std::find(ids_.begin(), ids_.end(), id) - ids_.begin());
}

PlannedCage& SceneDocument::cageOfTag(uint32_t tag) {
    for (uint32_t c = 0; c < cageOwnerIds_.size(); ++c)
        if (cageOwnerIds_[c] == tag) return planned_.cages[c];
    return activeCage();
}

void SceneDocument::reindex() {
    Result<std::vector<uint32_t>> owners = cageOwners(scene_.objects);
    assert(owners && "object edits keep the instance links valid");
    planned_.cageOfObject.assign(scene_.objects.size(), UINT32_MAX);
    planned_.objectOfCage.assign(planned_.cages.size(), UINT32_MAX);
    for (uint32_t c = 0; c < cageOwnerIds_.size(); ++c) {
        const uint32_t owner = indexOfId(cageOwnerIds_[c]);
        planned_.objectOfCage[c] = owner;
        planned_.cageOfObject[owner] = c;
    }
    for (uint32_t i = 0; i < scene_.objects.size(); ++i) planned_.cageOfObject[i] = planned_.cageOfObject[(*owners)[i]];
}

Status SceneDocument::insertObject(uint32_t index, SceneObject object, uint32_t id) {
    const uint32_t activeId = ids_[active_];
    if (!object.isInstance()) {
        Result<PlannedCage> cage = PlannedCage::create(object.cage, *database_, options_, source_ + ": object \"" + object.name + "\"");
        if (!cage) return cage.error();
        planned_.cages.push_back(std::move(cage).value());
        planned_.newPlansOfCage.push_back(0);
        cageOwnerIds_.push_back(id);
        rest_.push_back(std::move(object.cage.positions));
        object.cage = Cage{};
    }
    scene_.objects.insert(scene_.objects.begin() + index, std::move(object));
    ids_.insert(ids_.begin() + index, id);
    reindex();
    active_ = indexOfId(activeId);
    // An object taken out at another frame comes back at this one.
    if (Result<EditReport> shown = showObject(index); !shown) return shown.error();
    return success();
}

SceneObject SceneDocument::takeObject(uint32_t index) {
    const uint32_t id = ids_[index], activeId = ids_[active_];
    SceneObject object = scene_.objects[index];
    for (uint32_t c = 0; c < cageOwnerIds_.size(); ++c) {
        if (cageOwnerIds_[c] != id) continue;
        object.cage = planned_.cages[c].cage();
        object.cage.positions = std::move(rest_[c]);  // kept at rest, as a saved scene holds it
        rest_.erase(rest_.begin() + c);
        planned_.cages.erase(planned_.cages.begin() + c);
        planned_.newPlansOfCage.erase(planned_.newPlansOfCage.begin() + c);
        cageOwnerIds_.erase(cageOwnerIds_.begin() + c);
        break;
    }
    scene_.objects.erase(scene_.objects.begin() + index);
    ids_.erase(ids_.begin() + index);
    reindex();
    if (id == activeId) {
        samples_.reset();
        active_ = planned_.objectOfCage[0];
    } else {
        active_ = indexOfId(activeId);
    }
    return object;
}

Status SceneDocument::performObjectEdit(const std::string& name, std::function<Status()> apply,
                                        std::function<Status()> revert) {
    Result<EditReport> done = history_.perform(
        activeCage(), name, std::make_unique<ObjectEdit>(reporting(std::move(apply)), reporting(std::move(revert)), kObjectEditBytes));
    history_.setTag(ids_[active_]);
    if (!done) return done.error();
    return success();
}

Result<EditOutcome> SceneDocument::performEdit(const std::string& name, std::function<Result<EditReport>()> apply,
                                               std::function<Result<EditReport>()> revert, size_t bytes) {
    return finish(name, history_.perform(activeCage(), name,
                                         std::make_unique<ObjectEdit>(std::move(apply), std::move(revert), kObjectEditBytes + bytes)));
}

Result<std::string> SceneDocument::addObject(Cage cage, const std::string& name, const ObjectTransform& transform) {
    SceneObject object;
    object.name = uniqueObjectName(scene_.objects, name.empty() ? "object" : name);
    object.cage = std::move(cage);
    object.transform = transform;
    std::vector<SceneObject> check{object};
    if (Status valid = validateObjects(check, source_); !valid) return valid.error();
    if (Status valid = validateCage(object.cage, "object \"" + object.name + "\""); !valid) return valid.error();
    const std::string added = object.name;
    if (Status done = appendObject("Add object " + added, std::move(object)); !done) return done.error();
    if (database_->misses() > 0) (void)storeInPlanCache(*database_);
    return added;
}

Status SceneDocument::appendObject(const std::string& entryName, SceneObject object) {
    const uint32_t id = nextId_++;
    return performObjectEdit(
        entryName, [this, object, id]() { return insertObject(uint32_t(scene_.objects.size()), object, id); },
        [this, id]() {
            takeObject(indexOfId(id));
            return success();
        });
}

Result<std::string> SceneDocument::addInstance(const std::string& source, const std::string& name,
                                               const ObjectTransform& transform) {
    Status error = success();
    if (objectIndex(source, error) == UINT32_MAX) return error.error();
    SceneObject object;
    object.name = uniqueObjectName(scene_.objects, name.empty() ? source : name);
    object.instanceOf = source;
    object.transform = transform;
    std::vector<SceneObject> check = scene_.objects;
    check.push_back(object);
    if (Status valid = validateObjects(check, source_); !valid) return valid.error();
    const std::string added = object.name;
    if (Status done = appendObject("Instance " + source, std::move(object)); !done) return done.error();
    return added;
}

Status SceneDocument::removeObject(const std::string& name) {
    Status error = success();
    const uint32_t index = objectIndex(name, error);
    if (index == UINT32_MAX) return error;
    std::string users;
    for (const SceneObject& o : scene_.objects)
        if (o.instanceOf == name) users += (users.empty() ? "\"" : ", \"") + o.name + "\"";
    if (!users.empty()) return Error{"cannot remove \"" + name + "\": " + users + " instance it (remove them first)"};
    if (planned_.cages.size() == 1 && !scene_.objects[index].isInstance())
        return Error{"cannot remove \"" + name + "\": a scene keeps at least one object with a cage"};
    const uint32_t id = ids_[index];
    auto removed = std::make_shared<SceneObject>();
    return performObjectEdit(
        "Remove object " + name,
        [this, id, removed]() {
            *removed = takeObject(indexOfId(id));
            return success();
        },
        [this, id, index, removed]() { return insertObject(index, *removed, id); });
}

Status SceneDocument::renameObject(const std::string& name, const std::string& newName) {
    Status error = success();
    const uint32_t index = objectIndex(name, error);
    if (index == UINT32_MAX) return error;
    if (newName.empty()) return Error{"an object's name must not be empty"};
    if (newName == name) return success();
    if (findObject(scene_.objects, newName) != UINT32_MAX) return Error{"an object is already called \"" + newName + "\""};
    auto rename = [this](const std::string& from, const std::string& to) {
        for (SceneObject& o : scene_.objects) {
            if (o.name == from) o.name = to;
            if (o.instanceOf == from) o.instanceOf = to;  // the links follow the name
        }
        return success();
    };
    return performObjectEdit("Rename " + name, [=] { return rename(name, newName); }, [=] { return rename(newName, name); });
}

Status SceneDocument::setTransform(const std::string& name, const ObjectTransform& transform) {
    Status error = success();
    const uint32_t index = objectIndex(name, error);
    if (index == UINT32_MAX) return error;
    if (!scene_.objects[index].animation.transformKeys.empty()) {  // an animated transform is keyed
        Result<int32_t> frame = keyFrame("Transform " + name);
        if (!frame) return frame.error();
        return setTransformKey(name, *frame, transform);
    }
    if (Status valid = checkTransform(name, transform); !valid) return valid;
    const uint32_t id = ids_[index];
    const ObjectTransform before = scene_.objects[index].transform;
    auto put = [this, id](const ObjectTransform& t) {
        scene_.objects[indexOfId(id)].transform = t;
        return success();
    };
    return performObjectEdit("Transform " + name, [=] { return put(transform); }, [=] { return put(before); });
}

Status SceneDocument::setVisible(const std::string& name, bool visible) {
    Status error = success();
    const uint32_t index = objectIndex(name, error);
    if (index == UINT32_MAX) return error;
    const uint32_t id = ids_[index];
    const bool before = scene_.objects[index].visible;
    auto put = [this, id](bool v) {
        scene_.objects[indexOfId(id)].visible = v;
        return success();
    };
    return performObjectEdit(std::string(visible ? "Show " : "Hide ") + name, [=] { return put(visible); },
                             [=] { return put(before); });
}

void SceneDocument::afterEdit(const EditReport& report) {
    if (report.newPlans > 0) releaseUnusedPlans();
    if (!samples_) return;
    if (report.topologyChanged || report.replannedFaces > 0)
        samples_.reset();  // sites or limit positions changed beyond a refresh
    else if (!report.updatedSubfaceList.empty())
        samples_->refresh(activeCage(), report.updatedSubfaceList);
}

void SceneDocument::releaseUnusedPlans() {
    // A database shared with a copy() may hold plans the copy uses.
    if (database_.use_count() != 1) return;
    const uint32_t grown = database_->size() - sizeAtLastRelease_;
    if (grown < std::max(kMinPlansBetweenReleases, plansInUseAtLastRelease_)) return;
    // Every object's cage counts; plans of removed objects may go (undoing the removal plans its
    // cage again).
    std::vector<bool> inUse(database_->size(), false);
    uint32_t used = 0;
    for (const PlannedCage& cage : planned_.cages)
        for (uint32_t s = 0; s < cage.subfaceCount(); ++s)
            if (const uint32_t id = cage.subfacePlan(s); id != kNoPlan && !inUse[id]) inUse[id] = true, ++used;
    database_->releaseUnused(inUse);
    sizeAtLastRelease_ = database_->size();
    plansInUseAtLastRelease_ = used;
}

DisplacementListener SceneDocument::listener() {
    return [this](const DisplacementChange& change) {
        if (change.newLayout) samples_.reset();  // a new layout needs a new cache
    };
}

const SculptSamples& SceneDocument::sculptSamples() {
    if (!samples_) samples_.emplace(SculptSamples::build(activeCage(), active().displacement.layout));
    return *samples_;
}

Result<EditOutcome> SceneDocument::finish(const std::string& name, Result<EditReport> report) {
    if (!report) return report.error();
    keepRest(ids_[active_]);
    afterEdit(*report);
    EditOutcome outcome;
    outcome.name = name;
    outcome.report = std::move(report).value();
    return outcome;
}

// ---- moves and transforms ---------------------------------------------------------------

Result<EditOutcome> SceneDocument::moveVertices(std::span<const uint32_t> vertices, std::span<const glm::vec3> positions,
                                                const std::string& name, bool mergeWithPrevious) {
    if (activeHasVertexKeys()) {  // keys the moved vertices at the current frame
        Result<int32_t> frame = keyFrame(name);
        if (!frame) return frame.error();
        return keyedMove(name + ", key at frame " + std::to_string(*frame), *frame, vertices, positions, mergeWithPrevious);
    }
    return finish(name, history_.moveVertices(activeCage(), name, vertices, positions, mergeWithPrevious));
}

Result<EditOutcome> SceneDocument::transform(const std::string& name, std::span<const uint32_t> vertices,
                                             const glm::mat4& matrix) {
    Result<std::vector<glm::vec3>> moved = transformPoints(positionsOf(cage(), vertices), matrix);
    if (!moved) return moved.error();
    return moveVertices(vertices, *moved, name);
}

Result<EditOutcome> SceneDocument::translate(std::span<const uint32_t> vertices, const glm::vec3& offset,
                                             TransformSpace space) {
    if (Status ok = checkVertices(cage(), vertices); !ok) return ok.error();
    const TransformFrame frame = makeTransformFrame(cage(), activeCage().topology(), vertices, space);
    return transform("Move", vertices, translation(frame, offset));
}

Result<EditOutcome> SceneDocument::rotate(std::span<const uint32_t> vertices, const glm::vec3& axis, float degrees,
                                          TransformSpace space, const std::optional<glm::vec3>& pivot) {
    if (Status ok = checkVertices(cage(), vertices); !ok) return ok.error();
    if (!(glm::length(axis) > 0.0f) || !std::isfinite(glm::length(axis)))
        return Error{"the rotation axis must be a non-zero finite vector"};
    const TransformFrame frame =
        makeTransformFrame(cage(), activeCage().topology(), vertices, space, pivot ? &*pivot : nullptr);
    return transform("Rotate", vertices, rotation(frame, axis, degrees));
}

Result<EditOutcome> SceneDocument::scale(std::span<const uint32_t> vertices, const glm::vec3& factors,
                                         TransformSpace space, const std::optional<glm::vec3>& pivot) {
    if (Status ok = checkVertices(cage(), vertices); !ok) return ok.error();
    const TransformFrame frame =
        makeTransformFrame(cage(), activeCage().topology(), vertices, space, pivot ? &*pivot : nullptr);
    return transform("Scale", vertices, scaling(frame, factors));
}

// ---- tags -------------------------------------------------------------------------------

Result<EditOutcome> SceneDocument::setEdgeSharpness(std::span<const EdgeCrease> edges) {
    return finish("Crease", history_.setEdgeSharpness(activeCage(), "Crease", edges));
}

Result<EditOutcome> SceneDocument::setVertexSharpness(std::span<const VertexCorner> corners) {
    return finish("Corner", history_.setVertexSharpness(activeCage(), "Corner", corners));
}

Result<EditOutcome> SceneDocument::setHoles(std::span<const uint32_t> faces, bool hole) {
    const std::string name = hole ? "Make hole" : "Fill hole";
    return finish(name, history_.setHoles(activeCage(), name, faces, hole));
}

Result<EditOutcome> SceneDocument::setCreaseMethod(CreaseMethod method) {
    return finish("Crease method", history_.setCreaseMethod(activeCage(), "Crease method", method));
}

// ---- topology ---------------------------------------------------------------------------

Result<EditOutcome> SceneDocument::topologyEdit(const std::string& name, Result<TopologyEdit> edit, FollowingMove move) {
    if (!edit) return edit.error();
    std::vector<uint32_t> resultVertices = edit->resultVertices, resultFaces = edit->resultFaces;
    std::vector<EdgeKey> resultEdges = edit->resultEdges;
    const bool keyed = activeHasVertexKeys();
    auto step = [&]() -> std::unique_ptr<CustomEdit> {
        if (keyed) return makeAnimatedTopologyEdit(activeCage(), animatedState(active_), animationAccess(), *edit);
        return makeTopologyStep(activeCage(), *edit);
    };
    Result<EditOutcome> outcome =
        !active().displacement.empty()
            ? finish(name, history_.perform(activeCage(), name,
                                            makeDisplacedTopologyEdit(step(), active().displacement, listener(), std::move(move))))
        : keyed ? finish(name, history_.perform(activeCage(), name, step()))
                : finish(name, history_.applyTopologyEdit(activeCage(), name, std::move(edit).value()));
    if (outcome) {
        outcome->resultVertices = std::move(resultVertices);
        outcome->resultFaces = std::move(resultFaces);
        outcome->resultEdges = std::move(resultEdges);
    }
    return outcome;
}

Result<EditOutcome> SceneDocument::extrude(std::span<const uint32_t> faces, float distance) {
    // With displacement: extruded in place (the sculpt projected from the old surface), then moved
    // out, so the region takes its sculpt along.
    if (!active().displacement.empty() && distance != 0.0f && !activeHasVertexKeys()) {
        Result<SplitExtrude> split = splitExtrude(cage(), activeCage().topology(), faces, distance);
        if (!split) return split.error();
        return topologyEdit("Extrude", std::move(split->inPlace), std::move(split->move));
    }
    return topologyEdit("Extrude", extrudeFaces(cage(), activeCage().topology(), faces, distance));
}

Result<EditOutcome> SceneDocument::deleteFaces(std::span<const uint32_t> faces, bool removeUnusedVertices) {
    return topologyEdit("Delete faces", qp::deleteFaces(cage(), activeCage().topology(), faces, removeUnusedVertices));
}

Result<EditOutcome> SceneDocument::splitFace(uint32_t face, uint32_t a, uint32_t b) {
    return topologyEdit("Split face", qp::splitFace(cage(), activeCage().topology(), face, a, b));
}

Result<EditOutcome> SceneDocument::insertEdgeLoop(uint32_t a, uint32_t b, float t) {
    return topologyEdit("Edge loop", qp::insertEdgeLoop(cage(), activeCage().topology(), a, b, t));
}

Result<EditOutcome> SceneDocument::mergeVertices(std::span<const uint32_t> vertices, MergeTarget target) {
    return topologyEdit("Merge vertices", qp::mergeVertices(cage(), activeCage().topology(), vertices, target));
}

Result<EditOutcome> SceneDocument::makeFace(std::span<const uint32_t> vertices) {
    return topologyEdit("Make face", qp::makeFace(cage(), activeCage().topology(), vertices));
}

// ---- displacement -----------------------------------------------------------------------

Result<EditOutcome> SceneDocument::replaceDisplacement(const std::string& name, Displacement next) {
    auto edit = std::make_unique<DisplacementEdit>(active().displacement, active().displacement, std::move(next), listener());
    return finish(name, history_.perform(activeCage(), name, std::move(edit)));
}

Result<EditOutcome> SceneDocument::setDisplacementResolution(uint32_t resolution) {
    if (Status ok = checkDisplacementResolution(resolution); !ok) return ok.error();
    if (active().displacement.empty())
        return replaceDisplacement("New displacement", makeDisplacement(cage(), activeCage().topology(), resolution));
    return replaceDisplacement("Displacement resolution", resampleDisplacement(active().displacement, resolution));
}

Result<EditOutcome> SceneDocument::clearDisplacement() {
    if (active().displacement.empty()) return Error{"the scene has no displacement to clear"};
    return replaceDisplacement("Clear displacement", Displacement{});
}

Result<EditOutcome> SceneDocument::maskOperation(const std::string& name, Result<StrokeRecord> record) {
    if (!record) return record.error();
    const uint32_t changed = uint32_t(record->changes.size());
    if (changed == 0) return EditOutcome{name};
    auto edit = std::make_unique<DisplacementEdit>(active().displacement, std::move(record).value(), listener());
    Result<EditOutcome> outcome = finish(name, history_.perform(activeCage(), name, std::move(edit)));
    if (outcome) outcome->changedSamples = changed;
    return outcome;
}

Result<EditOutcome> SceneDocument::invertMask() { return maskOperation("Invert mask", qp::invertMask(active().displacement)); }

Result<EditOutcome> SceneDocument::clearMask() { return maskOperation("Clear mask", qp::clearMask(active().displacement)); }

Result<EditOutcome> SceneDocument::stroke(const StrokeOptions& options, std::span<const glm::vec3> path,
                                            uint32_t newResolution) {
    if (Status valid = validateBrush(options.brush); !valid) return valid.error();
    if (!(options.spacing >= 0.0f) || !std::isfinite(options.spacing))
        return Error{"stroke spacing must be >= 0 (0: a quarter of the radius)"};
    if (path.empty()) return Error{"a stroke needs at least one point"};
    for (size_t i = 0; i < path.size(); ++i)
        if (!std::isfinite(path[i].x) || !std::isfinite(path[i].y) || !std::isfinite(path[i].z))
            return Error{"point " + std::to_string(i + 1) + " of the stroke is not a finite position"};
    if (active().displacement.empty()) {
        if (Status ok = checkDisplacementResolution(newResolution); !ok) return ok.error();
        Result<EditOutcome> created =
            replaceDisplacement("New displacement", makeDisplacement(cage(), activeCage().topology(), newResolution));
        if (!created) return created.error();
    }
    StrokeRecord record = applyStroke(active().displacement, sculptSamples(), options, path);
    const uint32_t dabs = record.dabs, changed = uint32_t(record.changes.size());
    auto edit = std::make_unique<DisplacementEdit>(active().displacement, std::move(record), listener());
    Result<EditOutcome> outcome = finish("Stroke", history_.perform(activeCage(), "Stroke", std::move(edit)));
    if (outcome) outcome->dabs = dabs, outcome->changedSamples = changed;
    return outcome;
}

// ---- history ----------------------------------------------------------------------------

Result<EditOutcome> SceneDocument::undo() {
    if (!history_.canUndo()) return Error{"there is nothing to undo"};
    return step(history_.position() - 1, false);
}

Result<EditOutcome> SceneDocument::redo() {
    if (!history_.canRedo()) return Error{"there is nothing to redo"};
    return step(history_.position(), true);
}

Result<EditOutcome> SceneDocument::step(size_t entry, bool forward) {
    const std::string name = (forward ? "Redo " : "Undo ") + history_.entry(entry).name;
    const uint32_t tag = history_.tag(entry);
    PlannedCage& cage = cageOfTag(tag);
    const bool onActive = &cage == &activeCage();
    Result<EditReport> report = forward ? history_.redo(cage) : history_.undo(cage);
    history_.setTag(ids_[active_]);  // an object edit undone or redone may have changed the active object
    if (onActive) return finish(name, std::move(report));
    // Another object's cage: the active one's brush samples are still right.
    if (!report) return report.error();
    keepRest(tag);
    if (report->newPlans > 0) releaseUnusedPlans();
    EditOutcome outcome;
    outcome.name = name;
    outcome.report = std::move(report).value();
    return outcome;
}

// Entry by entry: consecutive entries may belong to different objects' cages.
Result<EditOutcome> SceneDocument::jumpTo(size_t position) {
    if (position > history_.size())
        return Error{"history position " + std::to_string(position) + " is past the newest entry (" +
                     std::to_string(history_.size()) + ")"};
    EditReport total;
    while (history_.position() != position) {
        Result<EditOutcome> step = history_.position() > position ? undo() : redo();
        if (!step) return step.error();
        accumulateReport(total, step->report);
    }
    EditOutcome outcome;
    outcome.name = "Jump to " + std::to_string(position);
    outcome.report = std::move(total);
    return outcome;
}

}  // namespace qp::py
