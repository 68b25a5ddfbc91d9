#include "displacement/displaced_topology_edit.h"

#include <cassert>

#include "edit/cage_delta.h"

namespace qp {

namespace {

class TopologyStep final : public CustomEdit {
public:
    explicit TopologyStep(TopologyDelta delta) : delta_(std::move(delta)) {}
    Result<EditReport> redo(PlannedCage& planned) override { return run(planned, DeltaDirection::Forward); }
    Result<EditReport> undo(PlannedCage& planned) override { return run(planned, DeltaDirection::Backward); }
    size_t bytes() const override { return sizeof(*this) + delta_.bytes(); }

private:
    Result<EditReport> run(PlannedCage& planned, DeltaDirection direction) {
        Result<TopologyEdit> edit = applyTopologyDelta(planned.cage(), delta_, direction);
        if (!edit) return edit.error();
        return planned.applyFinishedTopologyEdit(std::move(edit).value());
    }

    TopologyDelta delta_;
};

// A displacement as a history entry keeps it: its samples, mask and R. The layout is a function of
// the cage's topology and R, rebuilt when the entry is applied (a layout is several times the
// samples' size: two of them per topology edit would fill the history's budget).
class StoredDisplacement {
public:
    StoredDisplacement() = default;
    explicit StoredDisplacement(const Displacement& d)
        : resolution_(d.empty() ? 0 : d.layout.resolution), samples_(d.samples), mask_(d.mask) {}

    // For the cage `planned` holds now (the one this displacement was made for).
    Displacement restore(const PlannedCage& planned) const {
        Displacement d;
        if (resolution_ == 0) return d;
        d.layout = buildDisplacementLayout(planned.cage(), planned.topology(), resolution_);
        assert(d.layout.sampleCount == samples_.size());
        d.samples = samples_;
        d.mask = mask_;
        return d;
    }
    size_t bytes() const { return (samples_.capacity() + mask_.capacity()) * sizeof(float); }

private:
    uint32_t resolution_ = 0;
    std::vector<float> samples_, mask_;
};

class DisplacedTopologyEdit final : public CustomEdit {
public:
    DisplacedTopologyEdit(std::unique_ptr<CustomEdit> step, Displacement& target, DisplacementListener listener,
                          FollowingMove move)
        : step_(std::move(step)), target_(target), listener_(std::move(listener)), move_(std::move(move)) {}

    Result<EditReport> redo(PlannedCage& planned) override {
        std::optional<PlannedCage> before;
        if (!after_) before = planned;  // the first time: the transfer projects from the old surface
        Result<EditReport> report = step_->redo(planned);
        if (!report) return report;
        if (!after_) {
            before_ = StoredDisplacement(target_);
            after_ = StoredDisplacement(transferDisplacement(*before, target_, planned, *report).displacement);
        }
        target_ = after_->restore(planned);
        if (!move_.vertices.empty()) {
            if (inPlace_.empty())
                for (uint32_t v : move_.vertices) inPlace_.push_back(planned.cage().positions[v]);
            Result<EditReport> moved = planned.moveVertices(move_.vertices, move_.positions);
            if (!moved) return undoStep(planned, moved.error());
            accumulateReport(*report, *moved);
        }
        listener_(DisplacementChange{true, {}});
        return report;
    }

    Result<EditReport> undo(PlannedCage& planned) override {
        EditReport total;
        if (!move_.vertices.empty()) {
            Result<EditReport> moved = planned.moveVertices(move_.vertices, inPlace_);
            if (!moved) return moved;
            total = std::move(moved).value();
        }
        Result<EditReport> report = step_->undo(planned);
        if (!report) return report;
        accumulateReport(total, *report);
        target_ = before_.restore(planned);
        listener_(DisplacementChange{true, {}});
        return total;
    }

    size_t bytes() const override {
        return sizeof(*this) + step_->bytes() + before_.bytes() + (after_ ? after_->bytes() : 0) +
               move_.vertices.size() * (sizeof(uint32_t) + 2 * sizeof(glm::vec3));
    }

private:
    // A failed move after the topology step: the step is taken back, so nothing changed.
    Result<EditReport> undoStep(PlannedCage& planned, Error error) {
        if (Result<EditReport> back = step_->undo(planned); !back) return back.error();
        target_ = before_.restore(planned);
        return error;
    }

    std::unique_ptr<CustomEdit> step_;
    Displacement& target_;
    DisplacementListener listener_;
    FollowingMove move_;
    std::vector<glm::vec3> inPlace_;  // the moved vertices' positions before the move
    StoredDisplacement before_;
    std::optional<StoredDisplacement> after_;
};

}  // namespace

std::unique_ptr<CustomEdit> makeTopologyStep(const PlannedCage& planned, const TopologyEdit& edit) {
    return std::make_unique<TopologyStep>(makeTopologyDelta(planned.cage(), edit));
}

std::unique_ptr<CustomEdit> makeDisplacedTopologyEdit(std::unique_ptr<CustomEdit> topologyStep, Displacement& target,
                                                      DisplacementListener listener, FollowingMove move) {
    return std::make_unique<DisplacedTopologyEdit>(std::move(topologyStep), target, std::move(listener), std::move(move));
}

Result<SplitExtrude> splitExtrude(const Cage& cage, const Topology& topology, std::span<const uint32_t> faces,
                                  float distance) {
    Result<TopologyEdit> inPlace = extrudeFaces(cage, topology, faces, 0.0f);
    if (!inPlace) return inPlace.error();
    Result<TopologyEdit> moved = extrudeFaces(cage, topology, faces, distance);
    if (!moved) return moved.error();
    SplitExtrude out{std::move(inPlace).value(), {}};
    out.move.vertices = out.inPlace.resultVertices;
    for (uint32_t v : out.move.vertices) out.move.positions.push_back(moved->cage.positions[v]);
    return out;
}

}  // namespace qp
