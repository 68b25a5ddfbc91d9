#include "edit/edit_history.h"

#include <algorithm>

namespace qp {

namespace {

template <class... Ts>
struct Overloaded : Ts... {
    using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

template <class T>
size_t vectorBytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}

}  // namespace

EditHistory::EditHistory(size_t memoryBudgetBytes) : budget_(memoryBudgetBytes) {}

size_t EditHistory::entryBytes(const Entry& entry) {
    return std::visit(Overloaded{
                          [](const Move& m) { return vectorBytes(m.vertices) + vectorBytes(m.before) + vectorBytes(m.after); },
                          [](const EdgeTags& t) { return vectorBytes(t.before) + vectorBytes(t.after); },
                          [](const VertexTags& t) { return vectorBytes(t.before) + vectorBytes(t.after); },
                          [](const Holes& h) { return vectorBytes(h.faces) + vectorBytes(h.before); },
                          [](const Method&) { return size_t(0); },
                          [](const std::unique_ptr<TopologyDelta>& d) { return d->bytes(); },
                          [](const std::unique_ptr<CustomEdit>& c) { return c->bytes(); },
                      },
                      entry.payload) +
           sizeof(Entry) + entry.name.capacity() + vectorBytes(entry.report.replannedFaceList) +
           vectorBytes(entry.report.updatedSubfaceList);
}

namespace {

// What an entry keeps of its edit's report: the renumbering maps serve only the caller that
// applies the edit, and would cost O(cage) per topology entry.
EditReport kept(EditReport report) {
    report.previousFaceOf = {};
    report.previousSubfaceOf = {};
    return report;
}

}  // namespace

void EditHistory::record(std::string name, EditReport report, Payload payload) {
    entries_.erase(entries_.begin() + std::ptrdiff_t(position_), entries_.end());
    entries_.push_back({std::move(name), kept(std::move(report)), std::move(payload), tag_});
    position_ = entries_.size();
    trimToBudget();
}

void EditHistory::setBudget(size_t memoryBudgetBytes) {
    budget_ = memoryBudgetBytes;
    trimToBudget();
}

// Keeps the newest entry whatever its size; drops the oldest while over budget, but only
// applied ones (dropping an undone entry would let a redo skip it).
void EditHistory::trimToBudget() {
    size_t total = bytes();
    while (entries_.size() > 1 && position_ > 0 && total > budget_) {
        total -= entryBytes(entries_.front());
        entries_.erase(entries_.begin());
        --position_;
    }
}

size_t EditHistory::bytes() const {
    size_t total = 0;
    for (const Entry& e : entries_) total += entryBytes(e);
    return total;
}

HistoryEntryInfo EditHistory::entry(size_t index) const {
    const Entry& e = entries_.at(index);
    return {e.name, e.report, entryBytes(e)};
}

bool EditHistory::keepsPositions(size_t index) const {
    const Payload& p = entries_.at(index).payload;
    return std::holds_alternative<EdgeTags>(p) || std::holds_alternative<VertexTags>(p) || std::holds_alternative<Holes>(p) ||
           std::holds_alternative<Method>(p);
}

void EditHistory::clear() {
    entries_.clear();
    position_ = 0;
}

void EditHistory::dropRedo() { entries_.erase(entries_.begin() + std::ptrdiff_t(position_), entries_.end()); }

Result<EditReport> EditHistory::moveVertices(PlannedCage& planned, std::string name, std::span<const uint32_t> vertices,
                                             std::span<const glm::vec3> positions, bool mergeWithPrevious) {
    std::vector<glm::vec3> before;
    for (uint32_t v : vertices) before.push_back(v < planned.cage().vertexCount() ? planned.cage().positions[v] : glm::vec3(0.0f));
    auto report = planned.moveVertices(vertices, positions);
    if (!report) return report;
    if (mergeWithPrevious && position_ == entries_.size() && !entries_.empty()) {
        Move* last = std::get_if<Move>(&entries_.back().payload);
        if (last && last->mergeable && entries_.back().tag == tag_ && std::equal(last->vertices.begin(), last->vertices.end(), vertices.begin(), vertices.end())) {
            last->after.assign(positions.begin(), positions.end());
            entries_.back().report = kept(*report);
            return report;
        }
    }
    record(std::move(name), *report,
           Move{{vertices.begin(), vertices.end()}, std::move(before), {positions.begin(), positions.end()}, true});
    return report;
}

Result<EditReport> EditHistory::setEdgeSharpness(PlannedCage& planned, std::string name, std::span<const EdgeCrease> edges) {
    EdgeTags tags;
    for (const EdgeCrease& e : edges) tags.before.push_back({e.v0, e.v1, planned.cage().edgeSharpness(e.v0, e.v1)});
    auto report = planned.setEdgeSharpness(edges);
    if (!report) return report;
    for (const EdgeCrease& e : edges) tags.after.push_back({e.v0, e.v1, planned.cage().edgeSharpness(e.v0, e.v1)});
    record(std::move(name), *report, std::move(tags));
    return report;
}

Result<EditReport> EditHistory::setVertexSharpness(PlannedCage& planned, std::string name,
                                                   std::span<const VertexCorner> corners) {
    VertexTags tags;
    for (const VertexCorner& c : corners)
        tags.before.push_back({c.vertex, c.vertex < planned.cage().vertexCount() ? planned.cage().vertexSharpness(c.vertex) : 0.0f});
    auto report = planned.setVertexSharpness(corners);
    if (!report) return report;
    for (const VertexCorner& c : corners) tags.after.push_back({c.vertex, planned.cage().vertexSharpness(c.vertex)});
    record(std::move(name), *report, std::move(tags));
    return report;
}

Result<EditReport> EditHistory::setHoles(PlannedCage& planned, std::string name, std::span<const uint32_t> faces, bool hole) {
    for (uint32_t f : faces)
        if (f >= planned.cage().faceCount()) return Error{"face " + std::to_string(f + 1) + " does not exist"};
    Holes holes{{faces.begin(), faces.end()}, {}, hole};
    for (uint32_t f : faces) holes.before.push_back(planned.cage().isHole(f));
    EditReport total;
    for (uint32_t f : faces) {
        auto report = planned.setHole(f, hole);
        if (!report) return report;  // cannot happen: faces were checked
        accumulateReport(total, *report);
    }
    record(std::move(name), total, std::move(holes));
    return total;
}

Result<EditReport> EditHistory::setCreaseMethod(PlannedCage& planned, std::string name, CreaseMethod method) {
    Method change{planned.cage().options.creaseMethod, method};
    auto report = planned.setCreaseMethod(method);
    if (!report) return report;
    record(std::move(name), *report, change);
    return report;
}

Result<EditReport> EditHistory::applyTopologyEdit(PlannedCage& planned, std::string name, TopologyEdit edit) {
    if (Status s = finishTopologyEdit(planned.cage(), edit, name); !s) return s.error();
    auto delta = std::make_unique<TopologyDelta>(makeTopologyDelta(planned.cage(), edit));
    auto report = planned.applyFinishedTopologyEdit(std::move(edit));
    if (!report) return report;
    record(std::move(name), *report, std::move(delta));
    return report;
}

Result<EditReport> EditHistory::perform(PlannedCage& planned, std::string name, std::unique_ptr<CustomEdit> edit) {
    auto report = edit->redo(planned);
    if (!report) return report;
    record(std::move(name), *report, std::move(edit));
    return report;
}

Result<EditReport> EditHistory::run(PlannedCage& planned, Entry& entry, bool forward) {
    return std::visit(
        Overloaded{
            [&](Move& m) { return planned.moveVertices(m.vertices, forward ? m.after : m.before); },
            [&](EdgeTags& t) { return planned.setEdgeSharpness(forward ? t.after : t.before); },
            [&](VertexTags& t) { return planned.setVertexSharpness(forward ? t.after : t.before); },
            [&](Holes& h) -> Result<EditReport> {
                EditReport total;
                for (size_t i = 0; i < h.faces.size(); ++i) {
                    auto report = planned.setHole(h.faces[i], forward ? h.after : bool(h.before[i]));
                    if (!report) return report;
                    accumulateReport(total, *report);
                }
                return total;
            },
            [&](Method& m) { return planned.setCreaseMethod(forward ? m.after : m.before); },
            [&](std::unique_ptr<TopologyDelta>& d) -> Result<EditReport> {
                auto edit = applyTopologyDelta(planned.cage(), *d, forward ? DeltaDirection::Forward : DeltaDirection::Backward);
                if (!edit) return edit.error();
                return planned.applyFinishedTopologyEdit(std::move(edit).value());  // applyTopologyDelta finished it
            },
            [&](std::unique_ptr<CustomEdit>& c) { return forward ? c->redo(planned) : c->undo(planned); },
        },
        entry.payload);
}

Result<EditReport> EditHistory::undo(PlannedCage& planned) {
    if (!canUndo()) return Error{"there is nothing to undo"};
    Entry& entry = entries_[position_ - 1];
    auto report = run(planned, entry, false);
    if (!report) return Error{"cannot undo \"" + entry.name + "\": " + report.error().message};
    entry.report = kept(*report);
    if (Move* m = std::get_if<Move>(&entry.payload)) m->mergeable = false;  // a new drag starts a new entry
    --position_;
    return report;
}

Result<EditReport> EditHistory::redo(PlannedCage& planned) {
    if (!canRedo()) return Error{"there is nothing to redo"};
    Entry& entry = entries_[position_];
    auto report = run(planned, entry, true);
    if (!report) return Error{"cannot redo \"" + entry.name + "\": " + report.error().message};
    entry.report = kept(*report);
    ++position_;
    return report;
}

Result<EditReport> EditHistory::jumpTo(PlannedCage& planned, size_t position) {
    if (position > entries_.size())
        return Error{"history position " + std::to_string(position) + " is past the newest entry (" +
                     std::to_string(entries_.size()) + ")"};
    EditReport total;
    while (position_ != position) {
        auto step = position_ > position ? undo(planned) : redo(planned);
        if (!step) return step;
        accumulateReport(total, *step);
    }
    return total;
}

}  // namespace qp
