#include "document_animation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "animation/animation_playback.h"
#include "document_objects.h"

namespace qp::editor {

namespace {

// What the timeline shows before anything is keyed or a range is set: room to start keying.
constexpr int32_t kDefaultLastFrame = 100;

std::string count(size_t n, const char* singular, const char* plural) {
    return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

// The keys and rest of the object with `id`, at the document's frame when an entry runs (its
// index may have changed since the entry was made; the entry runs on its own cage, so the object
// is there: editCageOfTag fails first otherwise).
AnimationAccess accessOf(Document& doc, uint32_t id) {
    return [&doc, id] {
        SceneObject& object = doc.scene.objects.at(objectIndexOfId(doc, id));
        return AnimatedCageState{&object.animation, &object.cage.positions, doc.currentFrame};
    };
}

uint32_t editedId(const Document& doc) { return doc.objectIds[doc.activeObject]; }

// The edited cage's state for a new entry. A cage getting its first keys takes its rest from
// what it shows (its scene cage is stale while edited), and drops empty tracks left from keys
// undone or deleted, which may count another number of vertices.
AnimatedCageState editedState(Document& doc) {
    SceneObject& object = activeObject(doc);
    if (!hasVertexKeys(object)) {
        object.animation.vertexKeys = {};
        object.cage.positions = doc.planned->cage().positions;
    }
    return {&object.animation, &object.cage.positions, doc.currentFrame};
}

// Keys go on whole frames and an entry shows the current frame once it ran: between frames,
// the edit happens at the nearest one.
Status snapToKeyFrame(Document& doc) {
    const double whole = double(keyFrame(doc));
    if (doc.currentFrame == whole) return success();
    Result<EditReport> shown = goToFrame(doc, whole);
    if (!shown) return shown.error();
    return success();
}

void addCounts(EditReport& total, const EditReport& part) {
    total.replannedFaces += part.replannedFaces;
    total.updatedSubfaces += part.updatedSubfaces;
    total.milliseconds += part.milliseconds;
}

// Sets the keyed transforms at `frame`; whether any changed.
bool showTransforms(Document& doc, double frame) {
    bool changed = false;
    for (SceneObject& object : doc.scene.objects) {
        if (object.animation.transformKeys.empty()) continue;
        const ObjectTransform t = evaluateTransform(object.animation, frame, object.transform);
        changed |= t != object.transform;
        object.transform = t;
    }
    return changed;
}

// An object's transform keys, as one history entry from `before` to `after`.
Status replaceTransformKeys(Document& doc, uint32_t object, const std::string& name, std::vector<TransformKey> before,
                            std::vector<TransformKey> after, uint64_t frame) {
    const uint32_t id = doc.objectIds[object];
    auto set = [&doc, id](std::vector<TransformKey> keys) {
        return [&doc, id, keys]() -> Status {
            const uint32_t i = objectIndexOfId(doc, id);
            if (i == kNoObject) return Error{"the object is gone"};
            doc.scene.objects[i].animation.transformKeys = keys;
            if (showTransforms(doc, doc.currentFrame)) ++doc.sceneRevision;
            return success();
        };
    };
    const size_t bytes = (before.size() + after.size()) * sizeof(TransformKey) + 64;
    Result<EditReport> done = performObjectChange(doc, name, set(std::move(after)), set(std::move(before)), bytes, frame);
    if (!done) return done.error();
    return success();
}

}  // namespace

bool hasVertexKeys(const SceneObject& object) { return !object.animation.vertexKeys.empty(); }

int32_t keyFrame(const Document& doc) { return int32_t(std::lround(doc.currentFrame)); }

Timeline documentTimeline(const Document& doc) {
    if (doc.scene.timeline || isAnimated(doc.scene)) return timelineOf(doc.scene);
    Timeline timeline;
    timeline.lastFrame = kDefaultLastFrame;
    return timeline;
}

Result<EditReport> goToFrame(Document& doc, double frame) {
    doc.currentFrame = frame;
    EditReport total;
    if (!doc.planned) return total;
    SceneObject& active = activeObject(doc);
    if (hasVertexKeys(active)) {
        Result<EditReport> shown = showFrame(*doc.planned, active.animation, active.cage.positions, frame);
        if (!shown) return shown;
        if (!shown->updatedSubfaceList.empty()) {
            ++doc.positionRevision;  // the renderer finds what moved by diffing positions
            if (doc.sculptSamples) doc.sculptSamples->refresh(*doc.planned, shown->updatedSubfaceList);
        }
        addCounts(total, *shown);
    }
    bool othersMoved = false;
    for (uint32_t c = 0; c < doc.otherCages.size(); ++c) {
        const SceneObject& owner = doc.scene.objects[ownerOfOtherCage(doc, c)];
        if (!hasVertexKeys(owner)) continue;
        Result<EditReport> shown = showFrame(doc.otherCages[c], owner.animation, owner.cage.positions, frame);
        if (!shown) return shown;
        if (shown->updatedSubfaceList.empty()) continue;
        doc.otherCageBounds[c] = computeBounds(doc.otherCages[c].cage());
        othersMoved = true;
        addCounts(total, *shown);
    }
    if (othersMoved) ++doc.otherPositionRevision;
    if (showTransforms(doc, frame)) ++doc.sceneRevision;
    doc.lastFrameChange = total;
    return total;
}

Status showCurrentFrameOn(Document& doc, uint32_t object, PlannedCage& planned) {
    const SceneObject& o = doc.scene.objects[object];
    if (!hasVertexKeys(o)) return success();
    Result<EditReport> shown = showFrame(planned, o.animation, o.cage.positions, doc.currentFrame);
    if (!shown) return shown.error();
    return success();
}

Result<EditReport> performKeyedMove(Document& doc, const std::string& name, std::span<const uint32_t> vertices,
                                    std::span<const glm::vec3> positions, bool continueDrag) {
    const int32_t frame = keyFrame(doc);
    const uint32_t id = editedId(doc);
    const std::vector<uint32_t> moved(vertices.begin(), vertices.end());
    const std::optional<Document::KeyedDrag>& drag = doc.keyedDrag;
    const bool continuing = continueDrag && drag && drag->position == doc.history.position() &&
                            doc.history.position() == doc.history.size() && drag->tag == id && drag->frame == frame &&
                            drag->vertices == moved;
    // A drag's later steps replace its entry: undone, then made again from where it started.
    EditReport report;
    if (continuing) {
        Result<EditReport> undone = doc.history.undo(*doc.planned);
        if (!undone) return undone;
        report = std::move(undone).value();
    }
    Result<EditReport> done =
        doc.history.perform(*doc.planned, name, makeKeyedMove(editedState(doc), accessOf(doc, id), frame, vertices, positions));
    if (!done) {
        if (continuing) (void)doc.history.redo(*doc.planned);
        return done;
    }
    accumulateReport(report, *done);
    doc.keyedDrag = Document::KeyedDrag{doc.history.position(), id, frame, moved};
    doc.animationNote = "keyed " + count(moved.size(), "vertex", "vertices") + " at frame " + std::to_string(frame);
    return report;
}

std::unique_ptr<CustomEdit> animatedTopologyStep(Document& doc, const TopologyEdit& edit) {
    return makeAnimatedTopologyEdit(*doc.planned, editedState(doc), accessOf(doc, editedId(doc)), edit);
}

Result<EditReport> performAnimatedTopologyEdit(Document& doc, const std::string& name, std::unique_ptr<CustomEdit> step) {
    Result<EditReport> done = doc.history.perform(*doc.planned, name, std::move(step));
    if (done) doc.animationNote = "keys carried to every frame (made at frame " + std::to_string(keyFrame(doc)) + ")";
    return done;
}

std::string settleFrameForEdit(Document& doc) {
    std::string note;
    if (doc.playing) {
        doc.playing = false;
        note = "playback paused for the edit";
    }
    if (doc.planned && hasVertexKeys(activeObject(doc)) && doc.currentFrame != double(keyFrame(doc)) && snapToKeyFrame(doc))
        note += std::string(note.empty() ? "" : "; ") + "went to frame " + std::to_string(keyFrame(doc)) + ", where keys go";
    return note;
}

Result<EditReport> insertKeys(Document& doc, std::vector<uint32_t> vertices, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (Status snapped = snapToKeyFrame(doc); !snapped) return snapped.error();
    const Cage& cage = doc.planned->cage();
    if (vertices.empty())
        for (uint32_t v = 0; v < cage.vertexCount(); ++v) vertices.push_back(v);
    std::vector<glm::vec3> positions;
    for (uint32_t v : vertices) {
        if (v >= cage.vertexCount()) return Error{"vertex " + std::to_string(v) + " does not exist"};
        positions.push_back(cage.positions[v]);
    }
    // The range shown so far becomes the scene's, so that the first keys do not shrink it to
    // their one frame (timelineOf spans the keys of a scene without a range of its own).
    if (!doc.scene.timeline) doc.scene.timeline = documentTimeline(doc);
    const int32_t at = keyFrame(doc);
    const std::string name = "Insert key: " + count(vertices.size(), "vertex", "vertices") + " at frame " + std::to_string(at);
    Result<EditReport> done =
        performCageEdit(doc, name, makeKeyedMove(editedState(doc), accessOf(doc, editedId(doc)), at, vertices, positions), frame);
    if (done) doc.animationNote = "keyed " + count(vertices.size(), "vertex", "vertices") + " at frame " + std::to_string(at);
    return done;
}

Result<EditReport> deleteKeysAtFrame(Document& doc, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (Status snapped = snapToKeyFrame(doc); !snapped) return snapped.error();
    const int32_t at = keyFrame(doc);
    const std::vector<int32_t>& keyed = activeObject(doc).animation.vertexKeys.frames;
    if (std::find(keyed.begin(), keyed.end(), at) == keyed.end())
        return Error{"\"" + activeObject(doc).name + "\" has no vertex keys at frame " + std::to_string(at)};
    Result<EditReport> done = performCageEdit(
        doc, "Delete keys at frame " + std::to_string(at), makeKeyRemoval(editedState(doc), accessOf(doc, editedId(doc)), at), frame);
    if (done) doc.animationNote = "deleted the keys at frame " + std::to_string(at);
    return done;
}

Status insertTransformKey(Document& doc, uint32_t object, uint64_t frame) {
    if (object >= doc.scene.objects.size()) return Error{"no object is selected"};
    if (Status snapped = snapToKeyFrame(doc); !snapped) return snapped;
    const SceneObject& o = doc.scene.objects[object];
    ObjectAnimation keyed = o.animation;
    setTransformKey(keyed, keyFrame(doc), o.transform);
    if (!doc.scene.timeline) doc.scene.timeline = documentTimeline(doc);
    return replaceTransformKeys(doc, object, "Key transform of " + o.name + " at frame " + std::to_string(keyFrame(doc)),
                                o.animation.transformKeys, keyed.transformKeys, frame);
}

Status deleteTransformKey(Document& doc, uint32_t object, uint64_t frame) {
    if (object >= doc.scene.objects.size()) return Error{"no object is selected"};
    if (Status snapped = snapToKeyFrame(doc); !snapped) return snapped;
    const SceneObject& o = doc.scene.objects[object];
    const int32_t at = keyFrame(doc);
    std::vector<TransformKey> kept = o.animation.transformKeys;
    if (std::erase_if(kept, [&](const TransformKey& k) { return k.frame == at; }) == 0)
        return Error{"\"" + o.name + "\" has no transform key at frame " + std::to_string(at)};
    return replaceTransformKeys(doc, object, "Delete transform key of " + o.name + " at frame " + std::to_string(at),
                                o.animation.transformKeys, std::move(kept), frame);
}

Status setInterpolation(Document& doc, uint32_t object, Interpolation interpolation, uint64_t frame) {
    if (!doc.planned) return Error{"no scene is open"};
    if (object >= doc.scene.objects.size()) return Error{"no object is selected"};
    const SceneObject& o = doc.scene.objects[object];
    const Interpolation before = o.animation.interpolation;
    if (before == interpolation) return success();
    const uint32_t id = doc.objectIds[object];
    // The object's keys now evaluate otherwise between keys: the frame is shown again (every
    // cage and transform; those not this object's stay where they are).
    auto set = [&doc, id](Interpolation value) {
        return [&doc, id, value]() -> Status {
            const uint32_t i = objectIndexOfId(doc, id);
            if (i == kNoObject) return Error{"the object is gone"};
            doc.scene.objects[i].animation.interpolation = value;
            Result<EditReport> shown = goToFrame(doc, doc.currentFrame);
            if (!shown) return shown.error();
            return success();
        };
    };
    const std::string name =
        std::string(interpolation == Interpolation::CatmullRom ? "Catmull-Rom" : "Linear") + " interpolation of " + o.name;
    Result<EditReport> done = performObjectChange(doc, name, set(interpolation), set(before), 64, frame);
    if (!done) return done.error();
    return success();
}

Status setTimeline(Document& doc, const Timeline& timeline, uint64_t frame) {
    if (!doc.planned) return Error{"no scene is open"};
    if (timeline.firstFrame > timeline.lastFrame)
        return Error{"the first frame (" + std::to_string(timeline.firstFrame) + ") is after the last (" +
                     std::to_string(timeline.lastFrame) + ")"};
    if (!std::isfinite(timeline.framesPerSecond) || timeline.framesPerSecond <= 0.0 || timeline.framesPerSecond > 1000.0)
        return Error{"the frame rate must be above 0 and at most 1000 frames per second"};
    if (doc.scene.timeline == timeline) return success();
    auto set = [&doc](std::optional<Timeline> t) {
        return [&doc, t]() -> Status {
            doc.scene.timeline = t;
            return success();
        };
    };
    char rate[32];
    std::snprintf(rate, sizeof rate, "%g", timeline.framesPerSecond);
    const std::string name = "Timeline " + std::to_string(timeline.firstFrame) + "-" + std::to_string(timeline.lastFrame) +
                             " at " + rate + " fps";
    Result<EditReport> done = performObjectChange(doc, name, set(timeline), set(doc.scene.timeline), 64, frame);
    if (!done) return done.error();
    return success();
}

}  // namespace qp::editor
