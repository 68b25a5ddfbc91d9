// SceneDocument's animation (scene_document.h, "animation"): the frame shown, keys set by moves
// and by hand, transform keys, interpolation, timeline and OBJ sequences, each key change a
// history entry (core/animation/animation_edits.h for the cage's keys).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "animation/animation_playback.h"
#include "animation/cage_sequence.h"
#include "document_checks.h"
#include "scene_document.h"

namespace qp::py {

namespace fs = std::filesystem;

namespace {

// A sequence pattern as an absolute path, as the scene reader keeps them (saveScene writes them
// relative to the scene again).
std::string absolutePattern(const fs::path& pattern) {
    std::error_code error;
    const fs::path absolute = fs::absolute(pattern, error);
    return error ? pattern.string() : absolute.lexically_normal().string();
}

std::string frameName(double frame) {
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", frame);
    return text;
}

Status checkKeyFrame(int64_t frame) {
    if (frame < -kMaxKeyFrame || frame > kMaxKeyFrame)
        return Error{"frame " + std::to_string(frame) + " is out of range (keys go on frames -1000000000 to 1000000000)"};
    return success();
}

Status checkPositions(std::span<const uint32_t> vertices, std::span<const glm::vec3> positions) {
    if (positions.size() != vertices.size())
        return Error{std::to_string(positions.size()) + " positions for " + std::to_string(vertices.size()) +
                     " vertices (one position per vertex)"};
    for (size_t i = 0; i < positions.size(); ++i)
        if (!std::isfinite(positions[i].x) || !std::isfinite(positions[i].y) || !std::isfinite(positions[i].z))
            return Error{"cannot move vertex " + std::to_string(uint64_t(vertices[i]) + 1) + " to a NaN or infinite position"};
    return success();
}

void showTransform(SceneObject& object, double frame) {
    if (!object.animation.transformKeys.empty())
        object.transform = evaluateTransform(object.animation, frame, object.transform);
}

// " (its keys are at frames 1, 5, 9)", at most a few of them named; `kind` names the keys when
// there are none (" (it has no vertex keys)") and, unless "vertex", when there are.
std::string keyedFramesNote(const std::vector<int32_t>& frames, const std::string& kind = "vertex") {
    if (frames.empty()) return " (it has no " + kind + " keys)";
    constexpr size_t kNamed = 8;
    std::string list;
    for (size_t i = 0; i < std::min(frames.size(), kNamed); ++i) list += (i ? ", " : "") + std::to_string(frames[i]);
    if (frames.size() > kNamed) list += ", ... " + std::to_string(frames.back());
    return " (its " + (kind == "vertex" ? std::string() : kind + " ") + "keys are at frames " + list + ")";
}

size_t keyBytes(const VertexKeys& keys) {
    return keys.offsets.size() * sizeof(uint32_t) + keys.frames.size() * (sizeof(int32_t) + sizeof(glm::vec3));
}

}  // namespace

AnimatedCageState SceneDocument::animatedState(uint32_t index) {
    return {&scene_.objects[index].animation, &rest_[planned_.cageOfObject[index]], frame_};
}

AnimationAccess SceneDocument::animationAccess() {
    const uint32_t id = ids_[active_];
    return [this, id] { return animatedState(indexOfId(id)); };
}

Result<EditReport> SceneDocument::showObject(uint32_t index) {
    SceneObject& object = scene_.objects[index];
    showTransform(object, frame_);
    if (object.isInstance()) return EditReport{};  // it shows its source's cage
    // Without keys the cage is at rest already, unless keys were just taken away.
    const uint32_t c = planned_.cageOfObject[index];
    return showFrame(planned_.cages[c], object.animation, rest_[c], frame_);
}

void SceneDocument::keepRest(uint32_t id) {
    for (uint32_t c = 0; c < cageOwnerIds_.size(); ++c)
        if (cageOwnerIds_[c] == id && scene_.objects[planned_.objectOfCage[c]].animation.vertexKeys.empty())
            rest_[c] = planned_.cages[c].cage().positions;
}

Result<int32_t> SceneDocument::keyFrame(const std::string& what) const {
    if (frame_ != std::floor(frame_))
        return Error{what + ": keys go on whole frames and the scene shows frame " + frameName(frame_) +
                     "; go to a whole frame first"};
    if (std::fabs(frame_) > double(kMaxKeyFrame))
        return Error{what + ": the scene shows frame " + frameName(frame_) + ", out of the range keys go on (-1000000000 to 1000000000)"};
    return int32_t(frame_);
}

Result<EditOutcome> SceneDocument::setFrame(double frame) {
    if (!std::isfinite(frame)) return Error{"the frame must be a finite number, not " + frameName(frame)};
    frame_ = frame;
    EditOutcome outcome;
    outcome.name = "Frame " + frameName(frame);
    EditReport& total = outcome.report;
    for (uint32_t i = 0; i < scene_.objects.size(); ++i) {
        if (scene_.objects[i].animation.empty()) continue;  // shown at rest already
        Result<EditReport> shown = showObject(i);
        if (!shown) return shown.error();
        if (i == active_) {  // sub-face numbers are per cage: the lists are the active object's
            afterEdit(*shown);
            total.replannedFaceList = shown->replannedFaceList;
            total.updatedSubfaceList = shown->updatedSubfaceList;
        }
        total.replannedFaces += shown->replannedFaces;
        total.updatedSubfaces += shown->updatedSubfaces;
        total.newPlans += shown->newPlans;
        total.milliseconds += shown->milliseconds;
    }
    return outcome;
}

Result<EditOutcome> SceneDocument::keyedMove(const std::string& name, int32_t frame, std::span<const uint32_t> vertices,
                                             std::span<const glm::vec3> positions, bool merge) {
    if (Status ok = checkVertices(cage(), vertices); !ok) return ok.error();
    if (Status ok = checkPositions(vertices, positions); !ok) return ok.error();
    std::vector<uint32_t> moved(vertices.begin(), vertices.end());
    const size_t newest = history_.size();
    // The entry's tag and name as well as its position: trimming the history to its budget may
    // have put another entry where the drag's was.
    const bool replacing = merge && keyedDrag_ && keyedDrag_->position == newest && history_.position() == newest &&
                           history_.tag(newest - 1) == ids_[active_] && history_.entry(newest - 1).name == name &&
                           keyedDrag_->vertices == moved;
    EditReport undone;
    if (replacing) {  // undone, then made again from where the drag started
        Result<EditReport> undo = history_.undo(activeCage());
        if (!undo) return undo.error();
        undone = std::move(undo).value();
    }
    Result<EditReport> done =
        history_.perform(activeCage(), name, makeKeyedMove(animatedState(active_), animationAccess(), frame, vertices, positions));
    if (!done) {
        if (replacing) (void)history_.redo(activeCage());
        return done.error();
    }
    accumulateReport(undone, *done);
    keyedDrag_ = KeyedDrag{history_.position(), std::move(moved)};
    return finish(name, std::move(undone));
}

Result<EditOutcome> SceneDocument::setKeys(std::span<const uint32_t> vertices, const std::optional<std::vector<glm::vec3>>& positions,
                                           std::optional<int64_t> frame) {
    if (frame)
        if (Status ok = checkKeyFrame(*frame); !ok) return ok.error();
    Result<int32_t> at = frame ? Result<int32_t>(int32_t(*frame)) : keyFrame("Key");
    if (!at) return at.error();
    if (Status ok = checkVertices(cage(), vertices); !ok) return ok.error();
    const std::string name = (positions ? "Move, key at frame " : "Key at frame ") + std::to_string(*at);
    if (positions) return keyedMove(name, *at, vertices, *positions, false);
    const std::vector<glm::vec3> all = positionsAtFrame(animation(), restPositions(), *at);
    std::vector<glm::vec3> keyed;
    keyed.reserve(vertices.size());
    for (uint32_t v : vertices) keyed.push_back(all[v]);
    return keyedMove(name, *at, vertices, keyed, false);
}

Result<EditOutcome> SceneDocument::removeKeys(int64_t frame) {
    if (Status ok = checkKeyFrame(frame); !ok) return ok.error();
    const std::vector<int32_t> keyed = keyedFrames(animation());
    if (!std::binary_search(keyed.begin(), keyed.end(), int32_t(frame)))
        return Error{"\"" + active().name + "\" has no vertex keys at frame " + std::to_string(frame) + keyedFramesNote(keyed)};
    const std::string name = "Remove keys at frame " + std::to_string(frame);
    return finish(name, history_.perform(activeCage(), name, makeKeyRemoval(animatedState(active_), animationAccess(), int32_t(frame))));
}

Status SceneDocument::setTransformKey(const std::string& name, int64_t frame, const ObjectTransform& transform) {
    Status error = success();
    const uint32_t index = objectIndex(name, error);
    if (index == UINT32_MAX) return error;
    if (Status ok = checkKeyFrame(frame); !ok) return ok;
    if (Status ok = checkTransform(name, transform); !ok) return ok;
    ObjectAnimation keyed;
    keyed.transformKeys = scene_.objects[index].animation.transformKeys;
    qp::setTransformKey(keyed, int32_t(frame), transform);
    return replaceTransformKeys(index, "Transform key " + name + " at frame " + std::to_string(frame),
                                std::move(keyed.transformKeys));
}

// One history entry replacing the object's transform keys. Without keys an object keeps the
// transform it shows when the entry is made.
Status SceneDocument::replaceTransformKeys(uint32_t index, const std::string& entryName, std::vector<TransformKey> keys) {
    const uint32_t id = ids_[index];
    const SceneObject& object = scene_.objects[index];
    auto put = [this, id, unkeyed = object.transform](const std::vector<TransformKey>& value) {
        SceneObject& o = scene_.objects[indexOfId(id)];
        o.animation.transformKeys = value;
        o.transform = unkeyed;
        showTransform(o, frame_);
        return success();
    };
    return performObjectEdit(entryName, [=, after = std::move(keys)] { return put(after); },
                             [=, before = object.animation.transformKeys] { return put(before); });
}

Status SceneDocument::removeTransformKey(const std::string& name, int64_t frame) {
    Status error = success();
    const uint32_t index = objectIndex(name, error);
    if (index == UINT32_MAX) return error;
    if (Status ok = checkKeyFrame(frame); !ok) return ok;
    const SceneObject& object = scene_.objects[index];
    std::vector<TransformKey> kept = object.animation.transformKeys;
    if (std::erase_if(kept, [&](const TransformKey& k) { return k.frame == frame; }) == 0) {
        std::vector<int32_t> frames;
        for (const TransformKey& k : object.animation.transformKeys) frames.push_back(k.frame);
        return Error{"\"" + name + "\" has no transform key at frame " + std::to_string(frame) +
                     keyedFramesNote(frames, "transform")};
    }
    return replaceTransformKeys(index, "Remove transform key " + name + " at frame " + std::to_string(frame), std::move(kept));
}

Result<EditOutcome> SceneDocument::setInterpolation(Interpolation interpolation) {
    const uint32_t id = ids_[active_];
    const Interpolation before = animation().interpolation;
    auto put = [this, id](Interpolation value) {
        const uint32_t index = indexOfId(id);
        scene_.objects[index].animation.interpolation = value;
        return showObject(index);
    };
    const std::string name = interpolation == Interpolation::Linear ? "Linear interpolation" : "Catmull-Rom interpolation";
    return performEdit(name, [=] { return put(interpolation); }, [=] { return put(before); }, 0);
}

Status SceneDocument::setTimeline(int64_t first, int64_t last, double framesPerSecond) {
    if (!(framesPerSecond > 0.0 && framesPerSecond <= 1000.0))
        return Error{"fps must be a positive number of at most 1000, not " + frameName(framesPerSecond)};
    if (Status ok = checkKeyFrame(first); !ok) return ok;
    if (Status ok = checkKeyFrame(last); !ok) return ok;
    if (last < first)
        return Error{"the last frame " + std::to_string(last) + " comes before the first, " + std::to_string(first)};
    const Timeline timeline{framesPerSecond, int32_t(first), int32_t(last)};
    auto put = [this](const std::optional<Timeline>& value) {
        scene_.timeline = value;
        return success();
    };
    return performObjectEdit("Timeline " + std::to_string(first) + " to " + std::to_string(last),
                             [=] { return put(timeline); }, [=, before = scene_.timeline] { return put(before); });
}

Result<EditOutcome> SceneDocument::loadSequence(const std::string& pattern) {
    Result<VertexKeys> loaded = loadSequenceKeys(pattern, cage());
    if (!loaded) return Error{"sequence " + loaded.error().message};
    struct Keys {
        VertexKeys keys;
        std::string pattern;
    };
    auto before = std::make_shared<const Keys>(Keys{animation().vertexKeys, animation().sequencePattern});
    auto after = std::make_shared<const Keys>(Keys{std::move(loaded).value(), absolutePattern(pattern)});
    const uint32_t id = ids_[active_];
    auto put = [this, id](const Keys& value) {
        const uint32_t index = indexOfId(id);
        scene_.objects[index].animation.vertexKeys = value.keys;
        scene_.objects[index].animation.sequencePattern = value.pattern;
        return showObject(index);
    };
    return performEdit("Sequence " + pattern, [=] { return put(*after); }, [=] { return put(*before); },
                       keyBytes(before->keys) + keyBytes(after->keys));
}

}  // namespace qp::py
