#include "scene_document.h"

#include <cmath>

#include "obj_io.h"
#include "plan_cache.h"

namespace qp::py {

namespace {

Status checkVertices(const Cage& cage, std::span<const uint32_t> vertices) {
    for (uint32_t v : vertices)
        if (v >= cage.vertexCount())
            return Error{"vertex " + std::to_string(uint64_t(v) + 1) + " does not exist (the cage has " +
                         std::to_string(cage.vertexCount()) + " vertices)"};
    return success();
}

bool endsWith(const std::string& text, const std::string& suffix) {
    return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

Result<std::unique_ptr<SceneDocument>> SceneDocument::create(Scene scene, const PlanOptions& options,
                                                             const std::string& source, std::vector<std::string>* warnings) {
    std::unique_ptr<SceneDocument> document(new SceneDocument());
    document->database_ = std::make_shared<PlanDatabase>();
    std::string cacheWarning;
    document->database_->setFallback(sharedPlanCache(&cacheWarning));
    Result<PlannedCage> planned = PlannedCage::create(scene.cage, *document->database_, options, source);
    if (!planned) return planned.error();
    if (document->database_->misses() > 0)
        if (Status stored = storeInPlanCache(*document->database_); !stored && cacheWarning.empty())
            cacheWarning = stored.error().message;
    if (!cacheWarning.empty() && warnings) warnings->push_back(cacheWarning);
    document->planned_.emplace(std::move(planned).value());
    scene.cage = Cage{};  // planned_ holds the cage from now on
    document->scene_ = std::move(scene);
    document->source_ = source;
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
    document->database_ = database_;
    document->planned_ = planned_;
    document->source_ = source_;
    return document;
}

Scene SceneDocument::currentScene() const {
    Scene scene = scene_;
    scene.cage = planned_->cage();
    return scene;
}

Status SceneDocument::save(const std::string& path, bool inlineCage) {
    if (endsWith(path, ".obj")) return saveObj(path);
    return saveScene(currentScene(), path, inlineCage);
}

Status SceneDocument::saveObj(const std::string& path) const { return qp::saveObj(planned_->cage(), path); }

void SceneDocument::afterEdit(const EditReport& report) {
    if (report.newPlans > 0) releaseUnusedPlans();
    if (!samples_) return;
    if (report.topologyChanged || report.replannedFaces > 0)
        samples_.reset();  // sites or limit positions changed beyond a refresh
    else if (!report.updatedSubfaceList.empty())
        samples_->refresh(*planned_, report.updatedSubfaceList);
}

void SceneDocument::releaseUnusedPlans() {
    // A database shared with a copy() may hold plans the copy uses.
    if (database_.use_count() != 1) return;
    const uint32_t grown = database_->size() - sizeAtLastRelease_;
    if (grown < std::max(kMinPlansBetweenReleases, plansInUseAtLastRelease_)) return;
    std::vector<bool> inUse(database_->size(), false);
    uint32_t used = 0;
    for (uint32_t s = 0; s < planned_->subfaceCount(); ++s)
        if (const uint32_t id = planned_->subfacePlan(s); id != kNoPlan && !inUse[id]) inUse[id] = true, ++used;
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
    if (!samples_) samples_.emplace(SculptSamples::build(*planned_, scene_.displacement.layout));
    return *samples_;
}

Result<EditOutcome> SceneDocument::finish(const std::string& name, Result<EditReport> report) {
    if (!report) return report.error();
    afterEdit(*report);
    EditOutcome outcome;
    outcome.name = name;
    outcome.report = std::move(report).value();
    return outcome;
}

// ---- moves and transforms ---------------------------------------------------------------

Result<EditOutcome> SceneDocument::moveVertices(std::span<const uint32_t> vertices, std::span<const glm::vec3> positions,
                                                const std::string& name, bool mergeWithPrevious) {
    return finish(name, history_.moveVertices(*planned_, name, vertices, positions, mergeWithPrevious));
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
    const TransformFrame frame = makeTransformFrame(cage(), planned_->topology(), vertices, space);
    return transform("Move", vertices, translation(frame, offset));
}

Result<EditOutcome> SceneDocument::rotate(std::span<const uint32_t> vertices, const glm::vec3& axis, float degrees,
                                          TransformSpace space, const std::optional<glm::vec3>& pivot) {
    if (Status ok = checkVertices(cage(), vertices); !ok) return ok.error();
    if (!(glm::length(axis) > 0.0f) || !std::isfinite(glm::length(axis)))
        return Error{"the rotation axis must be a non-zero finite vector"};
    const TransformFrame frame =
        makeTransformFrame(cage(), planned_->topology(), vertices, space, pivot ? &*pivot : nullptr);
    return transform("Rotate", vertices, rotation(frame, axis, degrees));
}

Result<EditOutcome> SceneDocument::scale(std::span<const uint32_t> vertices, const glm::vec3& factors,
                                         TransformSpace space, const std::optional<glm::vec3>& pivot) {
    if (Status ok = checkVertices(cage(), vertices); !ok) return ok.error();
    const TransformFrame frame =
        makeTransformFrame(cage(), planned_->topology(), vertices, space, pivot ? &*pivot : nullptr);
    return transform("Scale", vertices, scaling(frame, factors));
}

// ---- tags -------------------------------------------------------------------------------

Result<EditOutcome> SceneDocument::setEdgeSharpness(std::span<const EdgeCrease> edges) {
    return finish("Crease", history_.setEdgeSharpness(*planned_, "Crease", edges));
}

Result<EditOutcome> SceneDocument::setVertexSharpness(std::span<const VertexCorner> corners) {
    return finish("Corner", history_.setVertexSharpness(*planned_, "Corner", corners));
}

Result<EditOutcome> SceneDocument::setHoles(std::span<const uint32_t> faces, bool hole) {
    const std::string name = hole ? "Make hole" : "Fill hole";
    return finish(name, history_.setHoles(*planned_, name, faces, hole));
}

Result<EditOutcome> SceneDocument::setCreaseMethod(CreaseMethod method) {
    return finish("Crease method", history_.setCreaseMethod(*planned_, "Crease method", method));
}

// ---- topology ---------------------------------------------------------------------------

Result<EditOutcome> SceneDocument::topologyEdit(const std::string& name, Result<TopologyEdit> edit) {
    if (!scene_.displacement.empty())
        return Error{name + ": the scene has sculpted displacement, whose samples follow the current faces and cannot "
                            "be carried across a topology edit yet; clear the displacement first (an undoable edit)"};
    if (!edit) return edit.error();
    std::vector<uint32_t> resultVertices = edit->resultVertices, resultFaces = edit->resultFaces;
    std::vector<EdgeKey> resultEdges = edit->resultEdges;
    Result<EditOutcome> outcome = finish(name, history_.applyTopologyEdit(*planned_, name, std::move(edit).value()));
    if (outcome) {
        outcome->resultVertices = std::move(resultVertices);
        outcome->resultFaces = std::move(resultFaces);
        outcome->resultEdges = std::move(resultEdges);
    }
    return outcome;
}

Result<EditOutcome> SceneDocument::extrude(std::span<const uint32_t> faces, float distance) {
    return topologyEdit("Extrude", extrudeFaces(cage(), planned_->topology(), faces, distance));
}

Result<EditOutcome> SceneDocument::deleteFaces(std::span<const uint32_t> faces, bool removeUnusedVertices) {
    return topologyEdit("Delete faces", qp::deleteFaces(cage(), planned_->topology(), faces, removeUnusedVertices));
}

Result<EditOutcome> SceneDocument::splitFace(uint32_t face, uint32_t a, uint32_t b) {
    return topologyEdit("Split face", qp::splitFace(cage(), planned_->topology(), face, a, b));
}

Result<EditOutcome> SceneDocument::insertEdgeLoop(uint32_t a, uint32_t b, float t) {
    return topologyEdit("Edge loop", qp::insertEdgeLoop(cage(), planned_->topology(), a, b, t));
}

Result<EditOutcome> SceneDocument::mergeVertices(std::span<const uint32_t> vertices, MergeTarget target) {
    return topologyEdit("Merge vertices", qp::mergeVertices(cage(), planned_->topology(), vertices, target));
}

Result<EditOutcome> SceneDocument::makeFace(std::span<const uint32_t> vertices) {
    return topologyEdit("Make face", qp::makeFace(cage(), planned_->topology(), vertices));
}

// ---- displacement -----------------------------------------------------------------------

Result<EditOutcome> SceneDocument::replaceDisplacement(const std::string& name, Displacement next) {
    auto edit = std::make_unique<DisplacementEdit>(scene_.displacement, scene_.displacement, std::move(next), listener());
    return finish(name, history_.perform(*planned_, name, std::move(edit)));
}

Result<EditOutcome> SceneDocument::setDisplacementResolution(uint32_t resolution) {
    if (Status ok = checkDisplacementResolution(resolution); !ok) return ok.error();
    if (scene_.displacement.empty())
        return replaceDisplacement("New displacement", makeDisplacement(cage(), planned_->topology(), resolution));
    const std::vector<uint32_t> resolutions(scene_.displacement.layout.subfaces.size(), resolution);
    return replaceDisplacement("Displacement resolution", resampleDisplacement(scene_.displacement, resolutions));
}

Result<EditOutcome> SceneDocument::clearDisplacement() {
    if (scene_.displacement.empty()) return Error{"the scene has no displacement to clear"};
    return replaceDisplacement("Clear displacement", Displacement{});
}

Result<EditOutcome> SceneDocument::stroke(const StrokeOptions& options, std::span<const glm::vec3> path,
                                            uint32_t newResolution) {
    if (Status valid = validateBrush(options.brush); !valid) return valid.error();
    if (!(options.spacing >= 0.0f) || !std::isfinite(options.spacing))
        return Error{"stroke spacing must be >= 0 (0: a quarter of the radius)"};
    if (path.empty()) return Error{"a stroke needs at least one point"};
    for (size_t i = 0; i < path.size(); ++i)
        if (!std::isfinite(path[i].x) || !std::isfinite(path[i].y) || !std::isfinite(path[i].z))
            return Error{"point " + std::to_string(i + 1) + " of the stroke is not a finite position"};
    if (scene_.displacement.empty()) {
        if (Status ok = checkDisplacementResolution(newResolution); !ok) return ok.error();
        Result<EditOutcome> created =
            replaceDisplacement("New displacement", makeDisplacement(cage(), planned_->topology(), newResolution));
        if (!created) return created.error();
    }
    StrokeRecord record = applyStroke(scene_.displacement, sculptSamples(), options, path);
    const uint32_t dabs = record.dabs, changed = uint32_t(record.changes.size());
    auto edit = std::make_unique<DisplacementEdit>(scene_.displacement, std::move(record), listener());
    Result<EditOutcome> outcome = finish("Stroke", history_.perform(*planned_, "Stroke", std::move(edit)));
    if (outcome) outcome->dabs = dabs, outcome->changedSamples = changed;
    return outcome;
}

// ---- history ----------------------------------------------------------------------------

Result<EditOutcome> SceneDocument::undo() {
    const std::string name = history_.canUndo() ? history_.entry(history_.position() - 1).name : "";
    return finish("Undo " + name, history_.undo(*planned_));
}

Result<EditOutcome> SceneDocument::redo() {
    const std::string name = history_.canRedo() ? history_.entry(history_.position()).name : "";
    return finish("Redo " + name, history_.redo(*planned_));
}

Result<EditOutcome> SceneDocument::jumpTo(size_t position) {
    return finish("Jump to " + std::to_string(position), history_.jumpTo(*planned_, position));
}

}  // namespace qp::py
