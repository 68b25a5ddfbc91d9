// The document's sculpting: strokes, the displacement's resolution, the mask (document.h,
// "Displacement"). Every change goes through a DisplacementEdit history entry whose listener
// (displacementListener) tells the renderer, the pickers and the mask overlay what changed.
#include <algorithm>
#include <cassert>

#include "displacement/displacement_edit.h"
#include "document.h"
#include "document_objects.h"

namespace qp::editor {

namespace {

// An entry whose change is already made (the first stroke made and painted the displacement):
// the history's perform() must not apply it again (that would re-send every sample to the
// renderer); later redos do.
class AlreadyDone final : public CustomEdit {
public:
    explicit AlreadyDone(std::unique_ptr<CustomEdit> edit) : edit_(std::move(edit)) {}
    Result<EditReport> redo(PlannedCage& planned) override {
        if (std::exchange(first_, false)) return EditReport{};
        return edit_->redo(planned);
    }
    Result<EditReport> undo(PlannedCage& planned) override { return edit_->undo(planned); }
    size_t bytes() const override { return edit_->bytes(); }

private:
    std::unique_ptr<CustomEdit> edit_;
    bool first_ = true;
};

Result<EditReport> replaceDisplacement(Document& doc, const std::string& name, Displacement next, uint64_t frame) {
    auto edit = std::make_unique<DisplacementEdit>(activeObject(doc).displacement, activeObject(doc).displacement, std::move(next),
                                                   displacementListener(doc));
    return performDisplacementEdit(doc, name, std::move(edit), frame);
}

}  // namespace

// ---- displacement ---------------------------------------------------------------------------

Status beginStroke(Document& doc, uint32_t newResolution, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (doc.sculptor) return Error{"a stroke is already in progress"};
    doc.strokeMadeDisplacement = activeObject(doc).displacement.empty();
    if (doc.strokeMadeDisplacement) {
        // Not a history entry of its own: endStroke records it with the stroke.
        if (Status ok = checkDisplacementResolution(newResolution); !ok) return ok;
        activeObject(doc).displacement = makeDisplacement(doc.planned->cage(), doc.planned->topology(), newResolution);
        displacementListener(doc)(DisplacementChange{true, {}});
    }
    doc.sculptor.emplace(activeObject(doc).displacement, sculptSamplesOf(doc));
    doc.sculptor->beginStroke();
    return success();
}

bool strokeActive(const Document& doc) { return doc.sculptor.has_value(); }

uint32_t strokeTo(Document& doc, const StrokeOptions& options, const glm::vec3& point) {
    assert(doc.sculptor && "strokeTo outside beginStroke / endStroke");
    if (isMaskBrush(options.brush.kind)) {  // the mask only: nothing for the renderer
        std::vector<uint32_t> reached;
        const uint32_t changed = doc.sculptor->dabTo(options, point, &reached);
        if (!reached.empty()) ++doc.maskRevision;
        return changed;
    }
    const size_t before = doc.unsyncedSamples.size();
    const uint32_t changed = doc.sculptor->dabTo(options, point, &doc.unsyncedSamples);
    if (doc.unsyncedSamples.size() != before) ++doc.sampleRevision;
    return changed;
}

uint32_t strokeDab(Document& doc, const StrokeOptions& options, const glm::vec3& centre) {
    assert(doc.sculptor && "strokeDab outside beginStroke / endStroke");
    const uint32_t changed = doc.sculptor->dab(options.brush, options.mirror, centre);
    const std::span<const uint32_t> reached = doc.sculptor->lastDabSamples();
    if (isMaskBrush(options.brush.kind)) {
        if (!reached.empty()) ++doc.maskRevision;
        return changed;
    }
    doc.unsyncedSamples.insert(doc.unsyncedSamples.end(), reached.begin(), reached.end());
    if (!reached.empty()) ++doc.sampleRevision;
    return changed;
}

Result<EditReport> endStroke(Document& doc, const std::string& name, uint64_t frame) {
    if (!doc.sculptor) return Error{"no stroke is in progress"};
    StrokeRecord record = doc.sculptor->endStroke();
    doc.sculptor.reset();
    if (std::exchange(doc.strokeMadeDisplacement, false)) {
        if (record.changes.empty()) {  // nothing painted: back to no displacement, no entry
            activeObject(doc).displacement = Displacement{};
            displacementListener(doc)(DisplacementChange{true, {}});
            return EditReport{};
        }
        // One entry from "none" to the painted displacement, already in place.
        auto replace = std::make_unique<DisplacementEdit>(activeObject(doc).displacement, Displacement{}, activeObject(doc).displacement,
                                                          displacementListener(doc));
        return performDisplacementEdit(doc, name, std::make_unique<AlreadyDone>(std::move(replace)), frame);
    }
    if (record.changes.empty()) return EditReport{};
    // perform() re-applies the `after` values: the listener then lists the samples once more,
    // which costs one idempotent upload.
    auto edit = std::make_unique<DisplacementEdit>(activeObject(doc).displacement, std::move(record), displacementListener(doc));
    return performDisplacementEdit(doc, name, std::move(edit), frame);
}

void cancelStroke(Document& doc) {
    if (!doc.sculptor) return;
    const StrokeRecord record = doc.sculptor->endStroke();
    doc.sculptor.reset();
    if (std::exchange(doc.strokeMadeDisplacement, false)) {
        activeObject(doc).displacement = Displacement{};
        displacementListener(doc)(DisplacementChange{true, {}});
        return;
    }
    undoStroke(activeObject(doc).displacement, record);
    displacementListener(doc)(DisplacementChange{false, record.changes, record.mask});
}

Result<EditReport> setDisplacementResolution(Document& doc, uint32_t resolution, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (doc.sculptor) return Error{"finish the stroke first"};
    if (Status ok = checkDisplacementResolution(resolution); !ok) return ok.error();
    const Displacement& d = activeObject(doc).displacement;
    if (d.empty())
        return replaceDisplacement(doc, "New displacement",
                                   makeDisplacement(doc.planned->cage(), doc.planned->topology(), resolution), frame);
    return replaceDisplacement(doc, "Displacement resolution " + std::to_string(resolution),
                               resampleDisplacement(d, resolution), frame);
}

Result<EditReport> clearDisplacement(Document& doc, uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (doc.sculptor) return Error{"finish the stroke first"};
    if (activeObject(doc).displacement.empty()) return Error{"the scene has no displacement to clear"};
    return replaceDisplacement(doc, "Clear displacement", Displacement{}, frame);
}

namespace {

// One history entry for a whole-mask operation (invertMask, clearMask of core/displacement/brush.h), whose
// change is already made: perform() applies the `after` values again, which changes nothing.
Result<EditReport> recordMaskOperation(Document& doc, const char* name, Result<StrokeRecord> (*operation)(Displacement&),
                                       uint64_t frame) {
    if (!doc.planned) return Error{"no cage is open"};
    if (doc.sculptor) return Error{"finish the stroke first"};
    Displacement& displacement = activeObject(doc).displacement;
    Result<StrokeRecord> record = operation(displacement);
    if (!record) return record.error();
    if (record->changes.empty()) return EditReport{};
    auto edit = std::make_unique<DisplacementEdit>(displacement, std::move(record).value(), displacementListener(doc));
    return performDisplacementEdit(doc, name, std::move(edit), frame);
}

}  // namespace

Result<EditReport> invertSculptMask(Document& doc, uint64_t frame) {
    return recordMaskOperation(doc, "Invert mask", &invertMask, frame);
}

Result<EditReport> clearSculptMask(Document& doc, uint64_t frame) {
    return recordMaskOperation(doc, "Clear mask", &clearMask, frame);
}

glm::vec3 mirrorCentreOf(const Document& doc) {
    if (doc.sculptSamples) return doc.sculptSamples->centre();
    const Bounds& bounds = cageExtent(doc).bounds;
    return 0.5f * (bounds.min + bounds.max);
}

const SculptSamples& sculptSamplesOf(Document& doc) {
    if (!doc.sculptSamples) doc.sculptSamples.emplace(SculptSamples::build(*doc.planned, activeObject(doc).displacement.layout));
    return *doc.sculptSamples;
}

std::vector<uint32_t> takeUnsyncedSamples(Document& doc) {
    std::vector<uint32_t> samples = std::exchange(doc.unsyncedSamples, {});
    if (doc.takenSamples.size() + samples.size() > displacementOf(doc).samples.size()) {
        doc.takenBefore += doc.takenSamples.size();
        doc.takenSamples.clear();
    }
    doc.takenSamples.insert(doc.takenSamples.end(), samples.begin(), samples.end());
    std::sort(samples.begin(), samples.end());
    samples.erase(std::unique(samples.begin(), samples.end()), samples.end());
    return samples;
}

}  // namespace qp::editor
