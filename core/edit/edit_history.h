// EditHistory: undo and redo of named edits on a PlannedCage, through the same incremental
// path as the edits themselves (undoing a move re-plans nothing; undoing a crease re-plans only
// the faces at that edge; undoing a topology edit re-plans what the edit re-planned).
//
// Usage: perform every edit through the history instead of calling PlannedCage directly:
//     EditHistory history;
//     history.moveVertices(planned, "Move", selected, newPositions, /*mergeWithPrevious=*/dragging);
//     history.applyTopologyEdit(planned, "Extrude", extrudeFaces(...).value());
//     history.undo(planned);  history.redo(planned);  history.jumpTo(planned, 3);
// A new edit after an undo drops the entries that could have been redone.
//
// Memory: entries store differences, not cages: a move its vertices with positions before and
// after; a tag edit the tags before and after; a topology edit a TopologyDelta (only the faces,
// vertices and tags that differ). When the total passes the budget the oldest entries go.
//
// Extension point: future edits (displacement strokes, ...) implement CustomEdit and go
// through perform(); the history treats them like any other entry.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "edit/cage_delta.h"
#include "plans/planned_cage.h"

namespace qp {

// An edit the history knows only through this interface. redo() must bring the PlannedCage
// from the state before the edit to the state after it, undo() back; both are called only in
// those states (the history keeps the order).
class CustomEdit {
public:
    virtual ~CustomEdit() = default;
    virtual Result<EditReport> redo(PlannedCage& planned) = 0;
    virtual Result<EditReport> undo(PlannedCage& planned) = 0;
    virtual size_t bytes() const = 0;  // memory held, for the history's budget
};

// What a history panel shows for one entry.
struct HistoryEntryInfo {
    std::string name;
    EditReport report;  // of the last time the entry was done, undone or redone
    size_t bytes = 0;
};

class EditHistory {
public:
    explicit EditHistory(size_t memoryBudgetBytes = size_t(256) << 20);

    // Each performs its edit on `planned` and, when it succeeds, records it as the newest
    // entry called `name`. On failure nothing is recorded and the PlannedCage is unchanged.

    // With mergeWithPrevious, a move of exactly the same vertices as the newest entry (also a
    // move, not undone since) extends that entry instead of adding one: a drag is one entry.
    Result<EditReport> moveVertices(PlannedCage& planned, std::string name, std::span<const uint32_t> vertices,
                                    std::span<const glm::vec3> positions, bool mergeWithPrevious = false);
    Result<EditReport> setEdgeSharpness(PlannedCage& planned, std::string name, std::span<const EdgeCrease> edges);
    Result<EditReport> setVertexSharpness(PlannedCage& planned, std::string name, std::span<const VertexCorner> corners);
    Result<EditReport> setHoles(PlannedCage& planned, std::string name, std::span<const uint32_t> faces, bool hole);
    Result<EditReport> setCreaseMethod(PlannedCage& planned, std::string name, CreaseMethod method);
    // `edit` must have been made from planned.cage() (by an operation of topology_edits.h).
    Result<EditReport> applyTopologyEdit(PlannedCage& planned, std::string name, TopologyEdit edit);
    Result<EditReport> perform(PlannedCage& planned, std::string name, std::unique_ptr<CustomEdit> edit);

    bool canUndo() const { return position_ > 0; }
    bool canRedo() const { return position_ < entries_.size(); }
    Result<EditReport> undo(PlannedCage& planned);
    Result<EditReport> redo(PlannedCage& planned);
    // Undoes or redoes until `position` entries are applied (0: the state before the oldest
    // entry still kept). The report accumulates every step (accumulateReport).
    Result<EditReport> jumpTo(PlannedCage& planned, size_t position);

    size_t size() const { return entries_.size(); }
    size_t position() const { return position_; }  // entries [0, position) are applied
    HistoryEntryInfo entry(size_t index) const;
    // Whether doing, undoing or redoing entry `index` leaves every position where it was (tag,
    // hole and crease-method entries), so consumers need not look for moved vertices.
    bool keepsPositions(size_t index) const;
    size_t bytes() const;
    // The memory budget; lowering it drops the oldest applied entries at once (never the newest).
    size_t budget() const { return budget_; }
    // New entries carry this tag (0 until set): a history shared by several planned cages (the
    // objects of a scene) tags each entry with the cage it was made on, so undo and redo can pass
    // that cage. A move merges only into an entry of the same tag.
    void setTag(uint32_t tag) { tag_ = tag; }
    uint32_t tag(size_t index) const { return entries_.at(index).tag; }
    void setBudget(size_t memoryBudgetBytes);
    void clear();
    // Forgets the entries a redo would apply (an interactive tool that previewed its edit and
    // was cancelled undoes it, then leaves no trace of it).
    void dropRedo();

private:
    struct Move {
        std::vector<uint32_t> vertices;
        std::vector<glm::vec3> before, after;
        bool mergeable = false;
    };
    struct EdgeTags {
        std::vector<EdgeCrease> before, after;
    };
    struct VertexTags {
        std::vector<VertexCorner> before, after;
    };
    struct Holes {
        std::vector<uint32_t> faces;
        std::vector<uint8_t> before;
        bool after = false;
    };
    struct Method {
        CreaseMethod before, after;
    };
    // Topology deltas sit behind a pointer so small entries stay small.
    using Payload = std::variant<Move, EdgeTags, VertexTags, Holes, Method, std::unique_ptr<TopologyDelta>,
                                 std::unique_ptr<CustomEdit>>;
    struct Entry {
        std::string name;
        EditReport report;
        Payload payload;
        uint32_t tag = 0;
    };

    Result<EditReport> run(PlannedCage& planned, Entry& entry, bool forward);
    void record(std::string name, EditReport report, Payload payload);
    static size_t entryBytes(const Entry& entry);
    void trimToBudget();

    std::vector<Entry> entries_;
    size_t position_ = 0;
    size_t budget_;
    uint32_t tag_ = 0;
};

}  // namespace qp
