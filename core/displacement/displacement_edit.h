// DisplacementEdit: an EditHistory entry (edit_history.h) that changes the sculpted displacement
// and nothing else: one brush stroke (its StrokeRecord: samples changed in place, brush.h) or a
// whole new displacement (a new, resampled or cleared one: the layout changes). The cage and its
// plans are untouched, so the report is empty.
//
// The owner of the Displacement hears of every change, when the entry is performed, undone or
// redone, through the listener: to drop a sample cache built for an old layout, or to send the
// changed samples to the GPU. The Displacement and the listener's captures must outlive the
// history entry (both usually live in the document that owns the history).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>

#include "displacement/brush.h"
#include "displacement/displacement.h"
#include "edit/edit_history.h"

namespace qp {

struct DisplacementChange {
    bool newLayout = false;                 // replaced whole: every sample may differ
    std::span<const SampleChange> samples;  // otherwise: the samples changed in place
    bool maskOnly = false;                  // `samples` are mask values: D did not change
};
using DisplacementListener = std::function<void(const DisplacementChange&)>;

class DisplacementEdit final : public CustomEdit {
public:
    // A stroke already applied to `target`: redo() sets its `after` values (so perform() right
    // after the stroke changes nothing), undo() its `before` values.
    DisplacementEdit(Displacement& target, StrokeRecord stroke, DisplacementListener listener);
    // A replacement: redo() makes `target` equal `after`, undo() equal `before`.
    DisplacementEdit(Displacement& target, Displacement before, Displacement after, DisplacementListener listener);

    Result<EditReport> redo(PlannedCage&) override { return apply(true); }
    Result<EditReport> undo(PlannedCage&) override { return apply(false); }
    size_t bytes() const override;

private:
    Result<EditReport> apply(bool forward);

    struct Swap {
        Displacement before, after;
    };
    Displacement& target_;
    StrokeRecord stroke_;
    std::optional<Swap> swap_;
    DisplacementListener listener_;
};

// Memory a displacement holds (for history budgets).
size_t displacementBytes(const Displacement& displacement);

// Resolutions a user may choose for a whole displacement: a power of two in
// 1..kMaxDisplacementResolution; the error says so.
Status checkDisplacementResolution(uint32_t resolution);

}  // namespace qp
