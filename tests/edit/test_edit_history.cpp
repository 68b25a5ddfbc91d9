// Undo/redo (core/edit/edit_history.h) and the topology deltas it stores (core/edit/cage_delta.h).
#include <random>

#include <gtest/gtest.h>

#include "edit/edit_history.h"
#include "mesh/generated_cage.h"
#include "test_cages.h"

namespace {

using qp::Cage;
using qp::EditHistory;
using qp::EditReport;
using qp::PlanDatabase;
using qp::PlannedCage;

PlannedCage plan(const Cage& cage, PlanDatabase& db) {
    auto planned = PlannedCage::create(cage, db, {}, "test cage");
    EXPECT_TRUE(planned.ok()) << (planned.ok() ? "" : planned.error().message);
    return std::move(planned).value();
}

bool sameCage(const Cage& a, const Cage& b) { return qp::sameTopologyAndTags(a, b) && a.positions == b.positions && a.uvs == b.uvs; }

size_t cageBytes(const Cage& c) {
    return c.positions.size() * sizeof(glm::vec3) + (c.faceOffsets.size() + c.faceVertices.size()) * sizeof(uint32_t);
}

}  // namespace

TEST(EditHistory, UndoingAMoveReplansNothingAndDragsMergeIntoOneEntry) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    const Cage original = planned.cage();
    EditHistory history;
    std::vector<uint32_t> selection{14, 15};
    for (int frame = 1; frame <= 5; ++frame) {
        std::vector<glm::vec3> moved{original.positions[14] + glm::vec3(0, 0, 0.1f * frame),
                                     original.positions[15] + glm::vec3(0, 0, 0.1f * frame)};
        ASSERT_TRUE(history.moveVertices(planned, "Move", selection, moved, frame > 1).ok());
    }
    EXPECT_EQ(history.size(), 1u);
    EXPECT_NEAR(planned.cage().positions[14].z - original.positions[14].z, 0.5f, 1e-6f);
    auto undo = history.undo(planned);
    ASSERT_TRUE(undo.ok());
    EXPECT_EQ(undo->replannedFaces, 0u);
    EXPECT_GT(undo->updatedSubfaces, 0u);
    EXPECT_TRUE(sameCage(planned.cage(), original));
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
    auto redo = history.redo(planned);
    ASSERT_TRUE(redo.ok());
    EXPECT_EQ(redo->replannedFaces, 0u);
    EXPECT_NEAR(planned.cage().positions[14].z - original.positions[14].z, 0.5f, 1e-6f);
    // A drag that starts after an undo/redo is a new entry, and so is a different selection.
    std::vector<glm::vec3> again{planned.cage().positions[14], planned.cage().positions[15]};
    ASSERT_TRUE(history.moveVertices(planned, "Move", selection, again, true).ok());
    EXPECT_EQ(history.size(), 2u);
    ASSERT_TRUE(history.moveVertices(planned, "Move", std::vector<uint32_t>{14}, std::vector<glm::vec3>{again[0]}, true).ok());
    EXPECT_EQ(history.size(), 3u);
}

TEST(EditHistory, UndoingACreaseReplansOnlyTheFacesAtThatEdge) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    EditHistory history;
    qp::EdgeCrease crease{14, 15, 2.5f};
    auto set = history.setEdgeSharpness(planned, "Crease", {&crease, 1});
    ASSERT_TRUE(set.ok());
    EXPECT_EQ(set->replannedFaces, 6u);
    auto undo = history.undo(planned);
    ASSERT_TRUE(undo.ok());
    EXPECT_EQ(undo->replannedFaces, 6u);
    EXPECT_EQ(planned.cage().edgeSharpness(14, 15), 0.0f);
    ASSERT_TRUE(history.redo(planned).ok());
    EXPECT_EQ(planned.cage().edgeSharpness(14, 15), 2.5f);
    EXPECT_EQ(history.entry(0).name, "Crease");
    EXPECT_EQ(history.entry(0).report.replannedFaces, 6u);
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
}

TEST(EditHistory, UndoingATopologyEditReplansWhatTheEditReplanned) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    const Cage original = planned.cage();
    EditHistory history;
    const uint32_t centre = 12;
    auto extrude = qp::extrudeFaces(planned.cage(), planned.topology(), {&centre, 1}, 0.5f);
    ASSERT_TRUE(extrude.ok());
    auto done = history.applyTopologyEdit(planned, "Extrude", std::move(extrude).value());
    ASSERT_TRUE(done.ok());
    const Cage extruded = planned.cage();
    EXPECT_EQ(done->replannedFaces, 13u);
    auto undo = history.undo(planned);
    ASSERT_TRUE(undo.ok()) << undo.error().message;
    EXPECT_EQ(undo->replannedFaces, 9u);  // face 12 and its 8 neighbours; the side quads are gone
    EXPECT_TRUE(sameCage(planned.cage(), original));
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
    auto redo = history.redo(planned);
    ASSERT_TRUE(redo.ok());
    EXPECT_EQ(redo->replannedFaces, 13u);
    EXPECT_TRUE(sameCage(planned.cage(), extruded));
}

TEST(EditHistory, RandomEditsUndoToTheStartAndRedoToTheEndThroughEveryState) {
    std::mt19937 rng(11);
    PlanDatabase db;
    Cage start = qp::test::makeSubdividedCube(3);
    for (uint32_t v = 0; v < start.vertexCount(); ++v) start.uvs.push_back({start.positions[v].x, start.positions[v].y});
    start.faceUVIndices = start.faceVertices;
    start.setEdgeSharpness(start.faceBegin(0)[0], start.faceBegin(0)[1], 2.0f);
    start.setHole(3, true);
    PlannedCage planned = plan(start, db);
    EditHistory history;
    std::vector<Cage> states{planned.cage()};
    for (int step = 0; step < 60; ++step) {
        const Cage& cage = planned.cage();
        const qp::Topology& t = planned.topology();
        const uint32_t e = rng() % t.edgeCount(), f = rng() % cage.faceCount(), v = rng() % cage.vertexCount();
        const uint32_t a = t.edgeVertices[2 * e], b = t.edgeVertices[2 * e + 1];
        qp::Result<EditReport> r = qp::Error{"refused"};
        auto topo = [&](const char* name, qp::Result<qp::TopologyEdit> edit) -> qp::Result<EditReport> {
            if (!edit) return edit.error();
            return history.applyTopologyEdit(planned, name, std::move(edit).value());
        };
        switch (rng() % 10) {
        case 0: {
            glm::vec3 p = cage.positions[v] + glm::vec3(0.05f, 0.1f, -0.1f);
            r = history.moveVertices(planned, "Move", std::vector<uint32_t>{v}, std::vector<glm::vec3>{p});
            break;
        }
        case 1: {
            qp::EdgeCrease c{a, b, float(rng() % 30) / 10.0f};
            r = history.setEdgeSharpness(planned, "Crease", {&c, 1});
            break;
        }
        case 2: {
            qp::VertexCorner c{v, float(rng() % 30) / 10.0f};
            r = history.setVertexSharpness(planned, "Corner", {&c, 1});
            break;
        }
        case 3: r = history.setHoles(planned, "Hole", std::vector<uint32_t>{f}, !cage.isHole(f)); break;
        case 4:
            r = history.setCreaseMethod(planned, "Crease method",
                                        cage.options.creaseMethod == qp::CreaseMethod::Normal ? qp::CreaseMethod::Chaikin
                                                                                              : qp::CreaseMethod::Normal);
            break;
        case 5: r = topo("Extrude", qp::extrudeFaces(cage, t, std::vector<uint32_t>{f}, 0.3f)); break;
        case 6: r = topo("Delete", qp::deleteFaces(cage, t, std::vector<uint32_t>{f}, rng() % 2)); break;
        case 7: r = topo("Loop cut", qp::insertEdgeLoop(cage, t, a, b, 0.3f)); break;
        case 8: r = topo("Merge", qp::mergeVertices(cage, t, std::vector<uint32_t>{a, b})); break;
        default: {
            const uint32_t n = cage.faceSize(f);
            if (n >= 4) r = topo("Split", qp::splitFace(cage, t, f, cage.faceBegin(f)[0], cage.faceBegin(f)[2]));
            break;
        }
        }
        if (r.ok()) states.push_back(planned.cage());
        ASSERT_EQ(history.size(), states.size() - 1);
    }
    ASSERT_GT(history.size(), 30u);

    auto toStart = history.jumpTo(planned, 0);
    ASSERT_TRUE(toStart.ok()) << toStart.error().message;
    EXPECT_TRUE(sameCage(planned.cage(), states.front()));
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
    for (size_t i = 1; i < states.size(); ++i) {
        auto redo = history.redo(planned);
        ASSERT_TRUE(redo.ok()) << redo.error().message;
        ASSERT_TRUE(sameCage(planned.cage(), states[i])) << "after redoing entry " << i - 1 << " (" << history.entry(i - 1).name << ")";
    }
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
    EXPECT_FALSE(history.redo(planned).ok());
    const size_t middle = states.size() / 2;
    ASSERT_TRUE(history.jumpTo(planned, middle).ok());
    EXPECT_TRUE(sameCage(planned.cage(), states[middle]));
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
    // A new edit drops the entries after the current one.
    uint32_t v = 0;
    glm::vec3 p = planned.cage().positions[0] + glm::vec3(1.0f);
    ASSERT_TRUE(history.moveVertices(planned, "Move", {&v, 1}, {&p, 1}).ok());
    EXPECT_EQ(history.size(), middle + 1);
    EXPECT_FALSE(history.canRedo());
}

TEST(EditHistory, EntriesStoreDifferencesAndTheBudgetDropsTheOldest) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::makeBenchmarkCage(2000, 1), db);
    const size_t cage = cageBytes(planned.cage());
    EditHistory history;
    const uint32_t face = 100;
    auto extrude = qp::extrudeFaces(planned.cage(), planned.topology(), {&face, 1}, 0.1f);
    ASSERT_TRUE(history.applyTopologyEdit(planned, "Extrude", std::move(extrude).value()).ok());
    EXPECT_LT(history.entry(0).bytes, cage / 20) << "a one-face extrude should store a small delta";
    uint32_t v = 7;
    glm::vec3 p = planned.cage().positions[v] + glm::vec3(0.1f);
    ASSERT_TRUE(history.moveVertices(planned, "Move", {&v, 1}, {&p, 1}).ok());
    EXPECT_LT(history.entry(1).bytes, size_t(1024)) << "a one-vertex move should not depend on the cage size";

    EditHistory small(history.entry(0).bytes * 3);
    for (int i = 0; i < 10; ++i) {
        const uint32_t f = 200 + 10 * i;
        auto e = qp::extrudeFaces(planned.cage(), planned.topology(), {&f, 1}, 0.1f);
        ASSERT_TRUE(small.applyTopologyEdit(planned, "Extrude " + std::to_string(i), std::move(e).value()).ok());
    }
    EXPECT_LE(small.bytes(), history.entry(0).bytes * 3);
    EXPECT_LT(small.size(), 10u);
    EXPECT_EQ(small.position(), small.size());
    EXPECT_EQ(small.entry(small.size() - 1).name, "Extrude 9");
    ASSERT_TRUE(small.jumpTo(planned, 0).ok());
    EXPECT_FALSE(small.undo(planned).ok());
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
}

namespace {

// A stand-in for a future edit kind: offsets every vertex by a vector.
class ShiftEverything : public qp::CustomEdit {
public:
    explicit ShiftEverything(glm::vec3 offset) : offset_(offset) {}
    qp::Result<EditReport> redo(PlannedCage& planned) override { return shift(planned, offset_); }
    qp::Result<EditReport> undo(PlannedCage& planned) override { return shift(planned, -offset_); }
    size_t bytes() const override { return sizeof(*this); }

private:
    static qp::Result<EditReport> shift(PlannedCage& planned, glm::vec3 offset) {
        std::vector<uint32_t> all(planned.cage().vertexCount());
        std::vector<glm::vec3> positions(all.size());
        for (uint32_t v = 0; v < all.size(); ++v) {
            all[v] = v;
            positions[v] = planned.cage().positions[v] + offset;
        }
        return planned.moveVertices(all, positions);
    }
    glm::vec3 offset_;
};

}  // namespace

TEST(EditHistory, CustomEditsGoThroughTheSameUndoRedo) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeCube(), db);
    EditHistory history;
    ASSERT_TRUE(history.perform(planned, "Shift", std::make_unique<ShiftEverything>(glm::vec3(1, 0, 0))).ok());
    EXPECT_EQ(planned.cage().positions[0].x, 0.0f);
    ASSERT_TRUE(history.undo(planned).ok());
    EXPECT_EQ(planned.cage().positions[0].x, -1.0f);
    ASSERT_TRUE(history.redo(planned).ok());
    EXPECT_EQ(planned.cage().positions[0].x, 0.0f);
    EXPECT_EQ(history.entry(0).name, "Shift");
    EXPECT_FALSE(history.jumpTo(planned, 5).ok());
}

TEST(EditHistory, RefusedEditsAreNotRecorded) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(2), db);
    EditHistory history;
    qp::EdgeCrease diagonal{0, 4, 1.0f};
    EXPECT_FALSE(history.setEdgeSharpness(planned, "Crease", {&diagonal, 1}).ok());
    EXPECT_FALSE(history.setHoles(planned, "Hole", std::vector<uint32_t>{9}, true).ok());
    uint32_t v = 99;
    glm::vec3 p(0.0f);
    EXPECT_FALSE(history.moveVertices(planned, "Move", {&v, 1}, {&p, 1}).ok());
    EXPECT_EQ(history.size(), 0u);
    EXPECT_FALSE(history.undo(planned).ok());
}

// A history shared by two planned cages (the objects of a scene): entries carry the tag they were
// made under, undo goes to the cage the caller finds by it, and a drag never merges across tags.
TEST(EditHistory, TagsSayWhichCageAnEntryBelongsTo) {
    PlanDatabase db;
    PlannedCage a = plan(qp::test::makeGrid(3), db), b = plan(qp::test::makeGrid(3), db);
    const Cage original = a.cage();
    EditHistory history;
    const std::vector<uint32_t> vertex{5};
    const std::vector<glm::vec3> up{original.positions[5] + glm::vec3(0, 0, 0.2f)};
    history.setTag(1);
    ASSERT_TRUE(history.moveVertices(a, "Move", vertex, up, true).ok());
    history.setTag(2);
    ASSERT_TRUE(history.moveVertices(b, "Move", vertex, up, true).ok());  // same vertex, other cage: no merge
    ASSERT_TRUE(history.setEdgeSharpness(b, "Crease", std::vector<qp::EdgeCrease>{{0, 1, 2.0f}}).ok());
    ASSERT_EQ(history.size(), 3u);
    EXPECT_EQ(history.tag(0), 1u);
    EXPECT_EQ(history.tag(1), 2u);
    EXPECT_EQ(history.tag(2), 2u);
    auto cageOf = [&](uint32_t tag) -> PlannedCage& { return tag == 1 ? a : b; };
    while (history.canUndo()) ASSERT_TRUE(history.undo(cageOf(history.tag(history.position() - 1))).ok());
    EXPECT_TRUE(sameCage(a.cage(), original));
    EXPECT_TRUE(sameCage(b.cage(), original));
    EXPECT_TRUE(a.differencesFromRebuild().empty());
    EXPECT_TRUE(b.differencesFromRebuild().empty());
}
