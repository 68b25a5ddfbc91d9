// PlannedCage applying topology edits: exactly the faces whose configuration may have changed
// are re-planned, every other face keeps its plan and control points, and the result always
// equals planning the edited cage from scratch.
#include <algorithm>
#include <cmath>
#include <bit>
#include <functional>
#include <random>

#include <gtest/gtest.h>

#include "mesh/obj_io.h"
#include "mesh/topology_edits.h"
#include "plans/planned_cage.h"
#include "test_cages.h"
#include "test_support.h"

namespace {

using qp::Cage;
using qp::EditReport;
using qp::PlanDatabase;
using qp::PlannedCage;
using qp::TopologyEdit;

PlannedCage plan(const Cage& cage, PlanDatabase& db) {
    auto planned = PlannedCage::create(cage, db, {}, "test cage");
    EXPECT_TRUE(planned.ok()) << (planned.ok() ? "" : planned.error().message);
    return std::move(planned).value();
}

struct SubfaceState {
    uint32_t plan, rotation;
    std::vector<glm::vec3> points;
};

std::vector<SubfaceState> snapshot(const PlannedCage& planned, uint32_t face) {
    std::vector<SubfaceState> out;
    for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s) {
        std::vector<glm::vec3> scratch;
        auto points = planned.controlPointsFor(s, qp::kMaxPlanDepth, scratch);
        out.push_back({planned.subfacePlan(s), planned.subfaceRotation(s), {points.begin(), points.end()}});
    }
    return out;
}

// Applies the edit and checks: the report's list is the expected count, every face that was
// not re-planned kept its plan and rotation, and its control points unless the report lists
// them as updated (a vertex of its 1-ring moved), and the whole equals a rebuild.
EditReport applyAndCheck(PlannedCage& planned, qp::Result<TopologyEdit> edit, uint32_t expectedReplanned) {
    EXPECT_TRUE(edit.ok()) << (edit.ok() ? "" : edit.error().message);
    if (!edit.ok()) return {};
    std::vector<uint32_t> oldFaceOf = edit->oldFaceOf;
    std::vector<std::vector<SubfaceState>> before;
    for (uint32_t f = 0; f < planned.cage().faceCount(); ++f) before.push_back(snapshot(planned, f));
    auto report = planned.applyTopologyEdit(std::move(edit).value());
    EXPECT_TRUE(report.ok()) << (report.ok() ? "" : report.error().message);
    if (!report.ok()) return {};
    EXPECT_EQ(report->replannedFaces, expectedReplanned);
    EXPECT_EQ(report->replannedFaceList.size(), report->replannedFaces);
    EXPECT_TRUE(report->topologyChanged);
    for (uint32_t f = 0; f < planned.cage().faceCount(); ++f) {
        if (std::binary_search(report->replannedFaceList.begin(), report->replannedFaceList.end(), f)) continue;
        EXPECT_NE(oldFaceOf[f], qp::kNewElement) << "new face " << f << " was not planned";
        if (oldFaceOf[f] == qp::kNewElement) continue;
        std::vector<SubfaceState> now = snapshot(planned, f), was = before[oldFaceOf[f]];
        EXPECT_EQ(now.size(), was.size());
        if (now.size() != was.size()) continue;
        for (uint32_t k = 0; k < now.size(); ++k) {
            EXPECT_EQ(now[k].plan, was[k].plan) << "face " << f;
            EXPECT_EQ(now[k].rotation, was[k].rotation) << "face " << f;
            const auto& updated = report->updatedSubfaceList;
            if (!std::binary_search(updated.begin(), updated.end(), planned.firstSubface(f) + k)) {
                EXPECT_EQ(now[k].points, was[k].points) << "face " << f;
            }
        }
    }
    std::vector<std::string> differences = planned.differencesFromRebuild();
    EXPECT_TRUE(differences.empty()) << differences[0];
    return *report;
}

}  // namespace

// Grid(5): 6 x 6 vertices (v = 6 y + x), faces f = 5 y + x; face 12 is the centre quad
// 14, 15, 21, 20, whose corners touch the 3 x 3 block of faces around it.
TEST(EditReplanning, ExtrudeReplansTheRegionItsNeighboursAndTheSideQuads) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    const uint32_t centre = 12;
    auto edit = qp::extrudeFaces(planned.cage(), planned.topology(), {&centre, 1}, 0.7f);
    EditReport r = applyAndCheck(planned, std::move(edit), 8 + 1 + 4);
    EXPECT_EQ(planned.cage().faceCount(), 29u);
    EXPECT_GT(r.newPlans, 0u);
}

TEST(EditReplanning, DeleteReplansTheNeighbours) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    const uint32_t centre = 12;
    applyAndCheck(planned, qp::deleteFaces(planned.cage(), planned.topology(), {&centre, 1}, true), 8);
    // A corner face takes its corner vertex with it: every later vertex is renumbered, but
    // only the faces at the deleted face's other corners 1, 6, 7 are re-planned.
    const uint32_t corner = 0;
    applyAndCheck(planned, qp::deleteFaces(planned.cage(), planned.topology(), {&corner, 1}, true), 3);
    EXPECT_EQ(planned.cage().vertexCount(), 35u);
}

TEST(EditReplanning, SplitReplansBothHalvesAndTheNeighbours) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    applyAndCheck(planned, qp::splitFace(planned.cage(), planned.topology(), 12, 14, 21), 8 + 2);
}

TEST(EditReplanning, EdgeLoopReplansTheCutColumnAndTheNextColumn) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(3), db);
    // Column 0 (faces 0, 3, 6) is cut: its 6 halves plus column 1, whose corners it shares.
    applyAndCheck(planned, qp::insertEdgeLoop(planned.cage(), planned.topology(), 0, 1, 0.5f), 6 + 3);
}

TEST(EditReplanning, MergeReplansEveryFaceAtTheChangedFacesCorners) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    // Vertex 14 (2,2) merges into 15 (3,2). The faces that change are the 4 at vertex 14
    // (x in 1..2, y in 1..2); their corners (x in 1..3, y in 1..3) touch the 16 faces x in
    // 0..3, y in 0..3. Faces at 15 only keep their vertex list (15 moves to the centroid):
    // they get new control points, not new plans.
    uint32_t pair[2] = {14, 15};
    EditReport r = applyAndCheck(planned, qp::mergeVertices(planned.cage(), planned.topology(), pair), 16);
    EXPECT_GT(r.updatedSubfaces, r.replannedFaces);
}

TEST(EditReplanning, MakeFaceReplansTheNewFaceAndItsNeighbours) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    ASSERT_TRUE(planned.removeFace(12).ok());
    uint32_t quad[4] = {14, 15, 21, 20};
    applyAndCheck(planned, qp::makeFace(planned.cage(), planned.topology(), quad), 8 + 1);
}

TEST(EditReplanning, TagAndOptionEditsReplanTheirFaces) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(5), db);
    qp::EdgeCrease two[2] = {{14, 15, 2.0f}, {15, 16, 1.0f}};  // faces at 14, 15, 16: 4 + 4 + 4 - 2 - 2
    auto edges = planned.setEdgeSharpness(two);
    ASSERT_TRUE(edges.ok());
    EXPECT_EQ(edges->replannedFaces, 8u);
    EXPECT_FALSE(edges->topologyChanged);
    qp::VertexCorner corner{0, 3.0f};
    auto corners = planned.setVertexSharpness({&corner, 1});
    ASSERT_TRUE(corners.ok());
    EXPECT_EQ(corners->replannedFaces, 1u);
    auto method = planned.setCreaseMethod(qp::CreaseMethod::Chaikin);
    ASSERT_TRUE(method.ok());
    EXPECT_EQ(method->replannedFaces, 25u);
    EXPECT_EQ(planned.cage().options.creaseMethod, qp::CreaseMethod::Chaikin);
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
    qp::EdgeCrease bad[2] = {{14, 15, 1.0f}, {14, 21 + 1, 1.0f}};  // the second is a diagonal
    EXPECT_FALSE(planned.setEdgeSharpness(bad).ok());
    EXPECT_EQ(planned.cage().edgeSharpness(14, 15), 2.0f);  // nothing applied
}

TEST(EditReplanning, BadEditsChangeNothing) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(3), db);
    Cage before = planned.cage();
    TopologyEdit reordered;
    reordered.cage = before;
    reordered.oldFaceOf = {1, 0, 2, 3, 4, 5, 6, 7, 8};
    reordered.oldVertexOf.resize(before.vertexCount());
    for (uint32_t v = 0; v < before.vertexCount(); ++v) reordered.oldVertexOf[v] = v;
    EXPECT_FALSE(planned.applyTopologyEdit(reordered).ok());
    TopologyEdit invalid = reordered;
    invalid.oldFaceOf = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    invalid.cage.setEdgeSharpness(0, 5, 1.0f);  // not an edge
    EXPECT_FALSE(planned.applyTopologyEdit(invalid).ok());
    EXPECT_TRUE(qp::sameTopologyAndTags(planned.cage(), before));
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
}

namespace {

// An oracle for "faces whose configuration may have changed", written independently of
// PlannedCage's dirty-vertex rule: a face of the edited cage is listed when it is new or has a
// new vertex list, its hole flag changed, or any input of its configuration differs: per corner,
// the corner sharpness, the creased edges at it, and the faces around it with their vertex lists
// (vertices named by their index before the edit; created vertices by fresh names).
std::vector<uint32_t> facesWithChangedInputs(const Cage& before, const TopologyEdit& edit) {
    const Cage& after = edit.cage;
    const qp::Topology tb = qp::buildTopology(before), ta = qp::buildTopology(after);
    using Inputs = std::vector<std::vector<uint64_t>>;
    auto inputs = [](const Cage& cage, const qp::Topology& t, uint32_t f, const std::function<uint64_t(uint32_t)>& name) {
        Inputs out;
        for (uint32_t i = 0; i < cage.faceSize(f); ++i) {
            const uint32_t c = cage.faceBegin(f)[i];
            std::vector<uint64_t> corner{name(c), std::bit_cast<uint32_t>(cage.vertexSharpness(c))};
            std::vector<std::vector<uint64_t>> creases, faces;
            for (uint32_t k = t.vertexEdgeOffsets[c]; k < t.vertexEdgeOffsets[c + 1]; ++k) {
                const uint32_t e = t.vertexEdges[k], a = t.edgeVertices[2 * e], b = t.edgeVertices[2 * e + 1];
                if (float s = cage.edgeSharpness(a, b); s > 0.0f) creases.push_back({name(a + b - c), std::bit_cast<uint32_t>(s)});
            }
            for (uint32_t k = t.vertexFaceOffsets[c]; k < t.vertexFaceOffsets[c + 1]; ++k) {
                const uint32_t g = t.vertexFaces[k];
                std::vector<uint64_t> cycle;
                for (uint32_t j = 0; j < cage.faceSize(g); ++j) cycle.push_back(name(cage.faceBegin(g)[j]));
                faces.push_back(cycle);
            }
            std::sort(creases.begin(), creases.end());
            std::sort(faces.begin(), faces.end());
            for (auto& x : creases) corner.insert(corner.end(), x.begin(), x.end());
            corner.push_back(UINT64_MAX);
            for (auto& x : faces) {
                corner.insert(corner.end(), x.begin(), x.end());
                corner.push_back(UINT64_MAX - 1);
            }
            out.push_back(corner);
        }
        return out;
    };
    auto oldName = [](uint32_t v) { return uint64_t(v); };
    auto newName = [&](uint32_t v) {
        return edit.oldVertexOf[v] == qp::kNewElement ? (uint64_t(1) << 40) + v : uint64_t(edit.oldVertexOf[v]);
    };
    std::vector<uint32_t> listed;
    for (uint32_t f = 0; f < after.faceCount(); ++f) {
        const uint32_t g = edit.oldFaceOf[f];
        const bool changed = g == qp::kNewElement || std::binary_search(edit.changedFaces.begin(), edit.changedFaces.end(), f) ||
                             before.isHole(g) != after.isHole(f) || before.options != after.options ||
                             inputs(before, tb, g, oldName) != inputs(after, ta, f, newName);
        if (changed) listed.push_back(f);
    }
    return listed;
}

// One random edit of any kind on the planned cage; returns false when the edit was refused (the
// cage must then be unchanged). Kinds: 0 move, 1 edge sharpness, 2 vertex sharpness, 3 hole,
// 4 crease method, 5 extrude, 6 delete, 7 split, 8 edge loop, 9 merge, 10 delete + make face.
bool randomEdit(PlannedCage& planned, std::mt19937& rng, uint32_t kind, std::string& failure) {
    const Cage& cage = planned.cage();
    const qp::Topology& t = planned.topology();
    auto randomFace = [&] { return uint32_t(rng() % cage.faceCount()); };
    auto randomEdge = [&] { return uint32_t(rng() % t.edgeCount()); };
    qp::Result<EditReport> report = qp::Error{"unset"};
    qp::Result<TopologyEdit> edit = qp::Error{"unset"};
    bool topological = false;
    switch (kind) {
    case 0: {
        uint32_t v = rng() % cage.vertexCount();
        glm::vec3 p = cage.positions[v] + glm::vec3(0.1f, -0.05f, 0.2f);
        report = planned.moveVertices({&v, 1}, {&p, 1});
        break;
    }
    case 1: {
        uint32_t e = randomEdge();
        report = planned.setEdgeSharpness(t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1], float(rng() % 40) / 10.0f);
        break;
    }
    case 2: report = planned.setVertexSharpness(rng() % cage.vertexCount(), float(rng() % 30) / 10.0f); break;
    case 3: {
        uint32_t f = randomFace();
        report = planned.setHole(f, !cage.isHole(f));
        break;
    }
    case 4:
        report = planned.setCreaseMethod(cage.options.creaseMethod == qp::CreaseMethod::Normal ? qp::CreaseMethod::Chaikin
                                                                                               : qp::CreaseMethod::Normal);
        break;
    case 5: {
        std::vector<uint32_t> faces{randomFace()};
        if (rng() % 2) {  // grow the region by a neighbour across an edge
            uint32_t e = t.faceEdges[cage.faceOffsets[faces[0]]];
            for (uint32_t k = t.edgeFaceOffsets[e]; k < t.edgeFaceOffsets[e + 1]; ++k) faces.push_back(t.edgeFaces[k]);
        }
        edit = qp::extrudeFaces(cage, t, faces, float(rng() % 3) * 0.2f);
        topological = true;
        break;
    }
    case 6: {
        uint32_t f = randomFace();
        edit = qp::deleteFaces(cage, t, {&f, 1}, rng() % 2);
        topological = true;
        break;
    }
    case 7: {
        uint32_t f = randomFace(), n = cage.faceSize(f);
        if (n < 4) {
            failure = "a triangle cannot be split";
            return false;
        }
        uint32_t i = rng() % n, j = (i + 2 + rng() % (n - 3)) % n;
        edit = qp::splitFace(cage, t, f, cage.faceBegin(f)[i], cage.faceBegin(f)[j]);
        topological = true;
        break;
    }
    case 8: {
        uint32_t e = randomEdge();
        edit = qp::insertEdgeLoop(cage, t, t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1], 0.2f + 0.6f * float(rng() % 4) / 3.0f);
        topological = true;
        break;
    }
    case 9: {
        uint32_t e = randomEdge();
        uint32_t pair[2] = {t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1]};
        edit = qp::mergeVertices(cage, t, pair, rng() % 2 ? qp::MergeTarget::Centroid : qp::MergeTarget::Last);
        topological = true;
        break;
    }
    default: {
        uint32_t f = randomFace();
        std::vector<uint32_t> vertices(cage.faceBegin(f), cage.faceBegin(f) + cage.faceSize(f));
        auto removed = planned.removeFace(f);
        if (!removed.ok()) return false;
        edit = qp::makeFace(planned.cage(), planned.topology(), vertices);
        topological = true;
        break;
    }
    }
    if (topological) {
        if (!edit.ok()) {
            failure = edit.error().message;
            return false;
        }
        const Cage before = planned.cage();
        std::vector<uint32_t> expected = facesWithChangedInputs(before, *edit);
        report = planned.applyTopologyEdit(std::move(edit).value());
        if (report.ok()) {
            EXPECT_EQ(report->replannedFaceList, expected) << "topology edit kind " << kind;
        }
    }
    if (!report.ok()) failure = report.error().message;
    return report.ok();
}

}  // namespace

TEST(EditReplanning, RandomSequencesOfEveryEditKindEqualRebuild) {
    for (uint32_t seed : {1u, 2u, 3u}) {
        std::mt19937 rng(seed);
        PlanDatabase db;
        Cage start = seed == 1 ? qp::test::makeMixedGrid() : qp::test::makeSubdividedCube(3);
        start.setEdgeSharpness(start.faceBegin(0)[0], start.faceBegin(0)[1], 2.0f);
        start.setVertexSharpness(start.faceBegin(1)[2], 1.5f);
        start.setHole(start.faceCount() - 1, true);
        PlannedCage planned = plan(start, db);
        uint32_t applied = 0, refused = 0;
        for (int step = 0; step < 70; ++step) {
            uint32_t kind = rng() % 11;
            Cage before = planned.cage();
            std::string failure;
            bool ok = randomEdit(planned, rng, kind, failure);
            if (!ok && kind != 10) {
                // A refused edit changes nothing (delete+make face may stop after the delete).
                EXPECT_TRUE(qp::sameTopologyAndTags(planned.cage(), before)) << "kind " << kind << ": " << failure;
                EXPECT_EQ(planned.cage().positions, before.positions);
            }
            ok ? ++applied : ++refused;
            ASSERT_TRUE(qp::validateCage(planned.cage(), "after edit").ok());
            std::vector<std::string> differences = planned.differencesFromRebuild();
            ASSERT_TRUE(differences.empty()) << "seed " << seed << " step " << step << " (kind " << kind
                                             << "): " << differences[0];
            if (planned.cage().faceCount() > 400) break;
        }
        EXPECT_GT(applied, 40u) << "seed " << seed << ": too few edits succeeded to test anything";
    }
}

// OpenSubdiv's regression cages (non-manifold ones included): every operation either succeeds
// with a cage equal to its rebuild or refuses with a message, changing nothing.
TEST(EditReplanning, SharedShapesSurviveEveryOperationOrRefuseCleanly) {
    QP_REQUIRE_SHARED_SHAPES();
    std::mt19937 rng(7);
    uint32_t shapes = 0, applied = 0;
    for (const auto& path : qp::test::sharedShapes("catmark_")) {
        auto cage = qp::loadObj(path.string());
        ASSERT_TRUE(cage.ok()) << path;
        if (cage->faceCount() > 90) continue;  // keeps the test to a few seconds
        PlanDatabase db;
        auto created = PlannedCage::create(*cage, db, {}, path.filename().string());
        ASSERT_TRUE(created.ok()) << created.error().message;
        PlannedCage planned = std::move(created).value();
        ++shapes;
        for (uint32_t kind = 5; kind <= 10; ++kind) {
            Cage before = planned.cage();
            std::string failure;
            bool ok = randomEdit(planned, rng, kind, failure);
            if (ok) ++applied;
            if (!ok && kind != 10) {
                EXPECT_FALSE(failure.empty()) << path.filename() << " kind " << kind;
                EXPECT_TRUE(qp::sameTopologyAndTags(planned.cage(), before)) << path.filename() << " kind " << kind;
            }
            std::vector<std::string> differences = planned.differencesFromRebuild();
            ASSERT_TRUE(differences.empty()) << path.filename() << " kind " << kind << ": " << differences[0];
        }
    }
    EXPECT_GT(shapes, 50u);
    EXPECT_GT(applied, shapes * 3);
}

TEST(EditReplanning, MovingEveryVertexUpdatesEverySubfaceAndReplansNothing) {
    // An animation frame: every vertex moves. The whole-cage shortcut must give what a rebuild
    // gives; a list as long as the cage that repeats a vertex is not "every vertex".
    PlanDatabase database;
    auto planned = PlannedCage::create(qp::test::makeMixedGrid(), database, qp::PlanOptions{}, "mixed");
    ASSERT_TRUE(planned) << planned.error().message;
    std::vector<uint32_t> all(planned->cage().vertexCount());
    std::vector<glm::vec3> twisted(all.size());
    for (uint32_t v = 0; v < all.size(); ++v) {
        all[v] = v;
        const glm::vec3 p = planned->cage().positions[v];
        const float a = 0.2f * p.y;
        twisted[v] = {std::cos(a) * p.x - std::sin(a) * p.z, p.y, std::sin(a) * p.x + std::cos(a) * p.z};
    }
    std::reverse(all.begin(), all.end()), std::reverse(twisted.begin(), twisted.end());  // any order
    auto moved = planned->moveVertices(all, twisted);
    ASSERT_TRUE(moved) << moved.error().message;
    EXPECT_EQ(moved->updatedSubfaces, planned->subfaceCount());
    EXPECT_EQ(moved->replannedFaces, 0u);
    EXPECT_TRUE(planned->differencesFromRebuild().empty());
    const std::vector<uint32_t> one(all.size(), 0);
    const std::vector<glm::vec3> same(all.size(), planned->cage().positions[0]);
    auto repeated = planned->moveVertices(one, same);
    ASSERT_TRUE(repeated) << repeated.error().message;
    EXPECT_LT(repeated->updatedSubfaces, planned->subfaceCount()) << "vertex 0 repeated was taken for every vertex";
    EXPECT_TRUE(planned->differencesFromRebuild().empty());
}
