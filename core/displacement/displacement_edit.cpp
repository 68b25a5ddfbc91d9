#include "displacement/displacement_edit.h"

#include <string>

namespace qp {

DisplacementEdit::DisplacementEdit(Displacement& target, StrokeRecord stroke, DisplacementListener listener)
    : target_(target), stroke_(std::move(stroke)), listener_(std::move(listener)) {}

DisplacementEdit::DisplacementEdit(Displacement& target, Displacement before, Displacement after,
                                   DisplacementListener listener)
    : target_(target), swap_(Swap{std::move(before), std::move(after)}), listener_(std::move(listener)) {}

size_t DisplacementEdit::bytes() const {
    return swap_ ? displacementBytes(swap_->before) + displacementBytes(swap_->after)
                 : stroke_.changes.capacity() * sizeof(SampleChange);
}

Result<EditReport> DisplacementEdit::apply(bool forward) {
    DisplacementChange change;
    if (swap_) {
        target_ = forward ? swap_->after : swap_->before;
        change.newLayout = true;
    } else {
        if (forward) redoStroke(target_, stroke_);
        else undoStroke(target_, stroke_);
        change.samples = stroke_.changes;
        change.maskOnly = stroke_.mask;
    }
    if (listener_) listener_(change);
    return EditReport{};
}

size_t displacementBytes(const Displacement& d) {
    return (d.samples.capacity() + d.mask.capacity()) * sizeof(float) + d.layout.tiles.capacity() * sizeof(DisplacementTile) +
           d.layout.padded.capacity() * sizeof(uint32_t) + d.layout.homes.capacity() * sizeof(SampleHome) +
           d.layout.adjacency.subfaces.capacity() * sizeof(DisplacementSubface) +
           d.layout.adjacency.segments.capacity() * sizeof(DisplacementSegment);
}

Status checkDisplacementResolution(uint32_t resolution) {
    if (!isPowerOfTwo(resolution) || resolution > kMaxDisplacementResolution)
        return Error{"the displacement resolution must be a power of two between 1 and " +
                     std::to_string(kMaxDisplacementResolution) + ", got " + std::to_string(resolution)};
    return success();
}

}  // namespace qp
