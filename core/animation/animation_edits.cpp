#include "animation/animation_edits.h"

#include <algorithm>

#include "animation/animation_playback.h"
#include "edit/cage_delta.h"

namespace qp {

namespace {

size_t tracksBytes(const std::vector<VertexTrack>& tracks) {
    size_t bytes = 0;
    for (const VertexTrack& t : tracks) bytes += sizeof(t) + t.frames.size() * (sizeof(int32_t) + sizeof(glm::vec3));
    return bytes;
}

size_t animationBytes(const ObjectAnimation& a, const std::vector<glm::vec3>& rest) {
    return a.vertexKeys.offsets.size() * sizeof(uint32_t) + a.vertexKeys.frames.size() * (sizeof(int32_t) + sizeof(glm::vec3)) +
           a.transformKeys.size() * sizeof(TransformKey) + rest.size() * sizeof(glm::vec3);
}

// After any entry ran: the cage shows the document's frame of the keys now in place.
Result<EditReport> showCurrentFrame(PlannedCage& planned, const AnimatedCageState& state, EditReport report) {
    Result<EditReport> shown = showFrame(planned, *state.animation, *state.rest, state.frame);
    if (!shown) return shown.error();
    accumulateReport(report, *shown);
    return report;
}

// Keys changed on some vertices' tracks: the tracks before and after.
class TrackSwap final : public CustomEdit {
public:
    // `sequenceBefore`: the animation's sequence pattern before the change (an undo restores it:
    // the keys are then the sequence's again).
    TrackSwap(AnimationAccess access, std::vector<VertexTrack> before, std::vector<VertexTrack> after,
              std::string sequenceBefore)
        : access_(std::move(access)), before_(std::move(before)), after_(std::move(after)),
          sequenceBefore_(std::move(sequenceBefore)) {}
    Result<EditReport> redo(PlannedCage& planned) override { return swap(planned, after_, ""); }
    Result<EditReport> undo(PlannedCage& planned) override { return swap(planned, before_, sequenceBefore_); }
    size_t bytes() const override { return sizeof(*this) + tracksBytes(before_) + tracksBytes(after_); }

private:
    Result<EditReport> swap(PlannedCage& planned, const std::vector<VertexTrack>& tracks, const std::string& sequence) {
        const AnimatedCageState state = access_();
        replaceVertexTracks(*state.animation, planned.cage().vertexCount(), tracks);
        state.animation->sequencePattern = sequence;
        return showCurrentFrame(planned, state, EditReport{});
    }

    AnimationAccess access_;
    std::vector<VertexTrack> before_, after_;
    std::string sequenceBefore_;
};

// A topology edit and the animation carried through it.
class AnimatedTopologySwap final : public CustomEdit {
public:
    AnimatedTopologySwap(AnimationAccess access, TopologyDelta delta, ObjectAnimation animationBefore,
                         std::vector<glm::vec3> restBefore, ObjectAnimation animationAfter, std::vector<glm::vec3> restAfter)
        : access_(std::move(access)), delta_(std::move(delta)), animationBefore_(std::move(animationBefore)),
          animationAfter_(std::move(animationAfter)), restBefore_(std::move(restBefore)), restAfter_(std::move(restAfter)) {}
    Result<EditReport> redo(PlannedCage& planned) override { return run(planned, true); }
    Result<EditReport> undo(PlannedCage& planned) override { return run(planned, false); }
    size_t bytes() const override {
        return sizeof(*this) + delta_.bytes() + animationBytes(animationBefore_, restBefore_) +
               animationBytes(animationAfter_, restAfter_);
    }

private:
    Result<EditReport> run(PlannedCage& planned, bool forward) {
        Result<TopologyEdit> edit =
            applyTopologyDelta(planned.cage(), delta_, forward ? DeltaDirection::Forward : DeltaDirection::Backward);
        if (!edit) return edit.error();
        Result<EditReport> report = planned.applyFinishedTopologyEdit(std::move(edit).value());
        if (!report) return report.error();
        const AnimatedCageState state = access_();
        *state.animation = forward ? animationAfter_ : animationBefore_;
        *state.rest = forward ? restAfter_ : restBefore_;
        return showCurrentFrame(planned, state, std::move(report).value());
    }

    AnimationAccess access_;
    TopologyDelta delta_;
    ObjectAnimation animationBefore_, animationAfter_;
    std::vector<glm::vec3> restBefore_, restAfter_;
};

}  // namespace

std::unique_ptr<CustomEdit> makeKeyedMove(const AnimatedCageState& state, AnimationAccess access, int32_t frame,
                                          std::span<const uint32_t> vertices, std::span<const glm::vec3> positions) {
    std::vector<VertexTrack> after = keyedTracks(state.animation->vertexKeys, frame, vertices, positions);
    std::vector<uint32_t> keyed;
    for (const VertexTrack& t : after) keyed.push_back(t.vertex);
    std::vector<VertexTrack> before = vertexTracks(state.animation->vertexKeys, keyed);
    return std::make_unique<TrackSwap>(std::move(access), std::move(before), std::move(after),
                                       state.animation->sequencePattern);
}

std::unique_ptr<CustomEdit> makeKeyRemoval(const AnimatedCageState& state, AnimationAccess access, int32_t frame) {
    const VertexKeys& keys = state.animation->vertexKeys;
    std::vector<uint32_t> keyedHere;
    for (uint32_t v = 0; v + 1 < keys.offsets.size(); ++v)
        for (uint32_t k = keys.offsets[v]; k < keys.offsets[v + 1]; ++k)
            if (keys.frames[k] == frame) keyedHere.push_back(v);
    std::vector<VertexTrack> before = vertexTracks(keys, keyedHere), after = before;
    for (VertexTrack& t : after) {
        const size_t at = size_t(std::find(t.frames.begin(), t.frames.end(), frame) - t.frames.begin());
        t.frames.erase(t.frames.begin() + long(at));
        t.positions.erase(t.positions.begin() + long(at));
    }
    return std::make_unique<TrackSwap>(std::move(access), std::move(before), std::move(after),
                                       state.animation->sequencePattern);
}

std::unique_ptr<CustomEdit> makeAnimatedTopologyEdit(const PlannedCage& planned, const AnimatedCageState& state,
                                                     AnimationAccess access, const TopologyEdit& edit) {
    ObjectAnimation animationAfter = *state.animation;
    std::vector<glm::vec3> restAfter = *state.rest;
    applyTopologyEditToAnimation(animationAfter, restAfter, planned.cage(), edit, state.frame);
    return std::make_unique<AnimatedTopologySwap>(std::move(access), makeTopologyDelta(planned.cage(), edit), *state.animation,
                                                  *state.rest, std::move(animationAfter), std::move(restAfter));
}

}  // namespace qp
