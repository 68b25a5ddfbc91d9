// The plan engine against OpenSubdiv, and its own invariants.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <thread>

#include <unistd.h>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "extraordinary_corners.h"
#include "mesh/generated_cage.h"
#include "mesh/topology.h"
#include "plans/face_config.h"
#include "plans/limit_check.h"
#include "plans/plan_builder.h"
#include "plans/plan_evaluator.h"
#include "plans/planned_cage.h"
#include "test_cages.h"

namespace {

using qp::Cage;
using qp::PlanDatabase;
using qp::PlannedCage;
using qp::PlanOptions;

PlannedCage plan(const Cage& cage, PlanDatabase& db, PlanOptions options = {}) {
    auto planned = PlannedCage::create(cage, db, options, "test cage");
    EXPECT_TRUE(planned.ok()) << (planned.ok() ? "" : planned.error().message);
    return std::move(planned).value();
}

qp::LimitCheck check(const Cage& cage, PlanOptions options = {}, uint32_t samples = 9) {
    PlanDatabase db;
    PlannedCage planned = plan(cage, db, options);
    auto reference = qp::LimitReference::create(cage, options.maxDepth, "test cage");
    EXPECT_TRUE(reference.ok());
    return qp::compareWithReference(planned, *reference, samples);
}

void expectMatchesOpenSubdiv(const Cage& cage, PlanOptions options = {}) {
    qp::LimitCheck c = check(cage, options);
    EXPECT_GT(c.samples, 0u);
    EXPECT_LE(c.maxPositionError, qp::kPositionTolerance) << "worst sub-face " << c.worstPositionSubface;
    EXPECT_LE(c.maxDerivativeError, qp::derivativeTolerance(options.maxDepth)) << "worst sub-face " << c.worstDerivativeSubface;
}

}  // namespace

TEST(PlanEngine, RegularGridIsOnePlanOfOneRegularNodeInTheInterior) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(6), db);
    // Interior faces of a regular grid share one plan: a single regular node, 16 stencils.
    uint32_t interior = planned.firstSubface(2 * 6 + 2);
    const qp::Plan& p = db.plan(planned.subfacePlan(interior));
    ASSERT_EQ(p.nodes.size(), 1u);
    EXPECT_EQ(p.nodes[0].kind, qp::NodeKind::Regular);
    EXPECT_EQ(p.stencilCount(), 16u);
    EXPECT_EQ(p.ringSize, 16u);
    EXPECT_EQ(planned.subfacePlan(planned.firstSubface(3 * 6 + 3)), planned.subfacePlan(interior));
    expectMatchesOpenSubdiv(qp::test::makeGrid(6));
}

TEST(PlanEngine, CubeSharesOnePlanAcrossRotations) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeCube(), db);
    EXPECT_EQ(db.size(), 1u);  // six faces, all the same configuration up to rotation
    std::set<uint32_t> rotations;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) rotations.insert(planned.subfaceRotation(s));
    expectMatchesOpenSubdiv(qp::test::makeCube());
}

TEST(PlanEngine, ExtraordinaryChainsCollapseIntoTerminalNodes) {
    PlanDatabase db;
    plan(qp::test::makeSubdividedCube(), db);
    qp::PlanDatabaseStats stats = db.stats();
    // Every extraordinary vertex is isolated (one per corner face), so each chain collapses
    // into one terminal node that holds the Gregory patch at its bottom.
    EXPECT_GT(stats.nodesByKind[uint32_t(qp::NodeKind::Terminal)], 0u);
    EXPECT_EQ(stats.nodesByKind[uint32_t(qp::NodeKind::Extraordinary)], 0u);
    expectMatchesOpenSubdiv(qp::test::makeSubdividedCube());
}

TEST(PlanEngine, SemiSharpCreasesUseCreaseNodesAndStayExact) {
    Cage cage = qp::test::makeGrid(6);
    for (uint32_t x = 0; x < 6; ++x) cage.setEdgeSharpness(3 * 7 + x, 3 * 7 + x + 1, 2.3f);
    PlanDatabase db;
    plan(cage, db);
    EXPECT_GT(db.stats().nodesByKind[uint32_t(qp::NodeKind::Crease)], 0u);
    expectMatchesOpenSubdiv(cage);

    // Without crease nodes the crease is isolated by subdivision: more nodes and stencils.
    PlanDatabase withoutDb;
    plan(cage, withoutDb, PlanOptions{6, false});
    EXPECT_EQ(withoutDb.stats().nodesByKind[uint32_t(qp::NodeKind::Crease)], 0u);
    EXPECT_GT(withoutDb.stats().stencils, db.stats().stencils);
    expectMatchesOpenSubdiv(cage, PlanOptions{6, false});
}

TEST(PlanEngine, BoundariesCornersAndInfiniteCreases) {
    Cage cage = qp::test::makeSubdividedCube();
    cage.setVertexSharpness(0, 2.5f);
    cage.setEdgeSharpness(cage.faceBegin(4)[0], cage.faceBegin(4)[1], qp::kInfiniteSharpness);
    cage.setHole(7, true);
    expectMatchesOpenSubdiv(cage);
    expectMatchesOpenSubdiv(qp::test::makeGrid(3));  // corners of a grid: valence-2 boundary
}

TEST(PlanEngine, NonQuadFacesSplitIntoSubfaces) {
    Cage cage = qp::test::makeMixedGrid();
    PlanDatabase db;
    PlannedCage planned = plan(cage, db);
    uint32_t triangle = cage.faceCount() - 2, pentagon = cage.faceCount() - 1;
    EXPECT_EQ(planned.firstSubface(pentagon) - planned.firstSubface(triangle), 3u);
    EXPECT_EQ(planned.subfaceCount(), cage.faceCount() - 2 + 3 + 5);
    expectMatchesOpenSubdiv(cage);
    for (uint32_t depth : {1u, 2u, 3u, 8u}) expectMatchesOpenSubdiv(cage, PlanOptions{depth, true});
}

TEST(LimitReference, DerivativesAreInTheSubfaceFrame) {
    Cage cage = qp::test::makeMixedGrid();
    auto reference = qp::LimitReference::create(cage, 6, "mixed grid");
    ASSERT_TRUE(reference.ok());
    const double h = 1e-4;
    for (uint32_t s = 0; s < reference->subfaceCount(); ++s) {
        qp::ReferenceSample at = reference->evaluate(s, 0.3, 0.6);
        glm::dvec3 du = (reference->evaluate(s, 0.3 + h, 0.6).position - reference->evaluate(s, 0.3 - h, 0.6).position) / (2 * h);
        glm::dvec3 dv = (reference->evaluate(s, 0.3, 0.6 + h).position - reference->evaluate(s, 0.3, 0.6 - h).position) / (2 * h);
        EXPECT_LT(glm::length(at.du - du), 1e-5) << "sub-face " << s;
        EXPECT_LT(glm::length(at.dv - dv), 1e-5) << "sub-face " << s;
    }
}

// At an extraordinary corner the parameterisation is singular and the derivatives are
// differences of control points 2^-depth of a face apart, times 2^depth. Far from the origin,
// float in absolute coordinates cannot hold them (depth 10 flipped the normal on
// catmark_pawn); relative to a corner of the face it can. The normal at every valence-3 corner
// of a cube translated far from the origin stays in the exact limit tangent plane at every
// depth.
TEST(PlanEngine, ExtraordinaryCornerNormalsKeepTheirPrecisionAtDepth) {
    const Cage cage = qp::test::makeFarOffCube();
    const glm::vec2 cornerUV[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (uint32_t depth : {6u, 8u, 10u}) {
        SCOPED_TRACE("depth " + std::to_string(depth));
        PlanDatabase db;
        PlanOptions options;
        options.maxDepth = depth;
        PlannedCage planned = plan(cage, db, options);
        uint32_t corners = 0;
        const double worst = qp::test::worstValence3CornerDegrees(cage, [&](uint32_t f, uint32_t k) {
            const qp::LimitSample s = planned.evaluate(planned.firstSubface(f), cornerUV[k].x, cornerUV[k].y);
            return glm::dvec3(glm::cross(s.du, s.dv));
        }, corners);
        EXPECT_EQ(corners, 24u);  // 8 cube corners, 3 faces each
        EXPECT_LT(worst, 0.1) << "degrees from the exact limit tangent plane";
    }
}

// Each sub-face stores the prefix of its control points that factors up to
// 2^kStoredControlPointLevel read; evaluate computes the rest, bit for bit what storing them
// all gave, and computes them again after an edit.
TEST(PlanEngine, StoredControlPointsAreThePrefixAndEvaluateComputesTheRest) {
    Cage cage = qp::test::makeCube();  // valence-3 corners: plans deeper than the stored level
    PlanDatabase db;
    PlannedCage planned = plan(cage, db);
    const float at[][2] = {{1e-3f, 1e-3f}, {0.37f, 0.01f}, {0.999f, 0.999f}, {0.5f, 0.25f}};
    uint32_t partial = 0;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
        const qp::Plan& p = db.plan(planned.subfacePlan(s));
        const auto stored = planned.storedControlPoints(s);
        std::vector<glm::vec3> scratch;
        const auto all = planned.controlPointsFor(s, qp::kMaxPlanDepth, scratch);
        ASSERT_EQ(stored.size(), p.stencilCountByLevel[PlannedCage::kStoredControlPointLevel]);
        ASSERT_EQ(all.size(), p.stencilCount());
        EXPECT_TRUE(std::equal(stored.begin(), stored.end(), all.begin())) << "sub-face " << s;
        EXPECT_EQ(planned.controlPointsFor(s, PlannedCage::kStoredControlPointLevel, scratch).data(), stored.data());
        partial += stored.size() < all.size();
        for (const auto& uv : at) {
            const qp::LimitSample computed = planned.evaluate(s, uv[0], uv[1]);
            const qp::LimitSample from = planned.evaluate(s, all, uv[0], uv[1]);
            EXPECT_EQ(computed.position, from.position) << "sub-face " << s;
            EXPECT_EQ(computed.du, from.du) << "sub-face " << s;
            EXPECT_EQ(computed.dv, from.dv) << "sub-face " << s;
        }
    }
    EXPECT_GT(partial, 0u) << "no sub-face keeps fewer control points than it has: nothing computed";

    // The same point before and after moving a vertex of its sub-face's 1-ring.
    const uint32_t s = 0, vertex = planned.subfaceRing(s)[1];
    const qp::LimitSample before = planned.evaluate(s, 1e-3f, 1e-3f);
    const glm::vec3 moved = planned.cage().positions[vertex] + glm::vec3(0.1f, 0.2f, -0.1f);
    ASSERT_TRUE(planned.moveVertices({&vertex, 1}, {&moved, 1}).ok());
    PlanDatabase freshDb;
    const PlannedCage fresh = plan(planned.cage(), freshDb);
    const qp::LimitSample after = planned.evaluate(s, 1e-3f, 1e-3f), expected = fresh.evaluate(s, 1e-3f, 1e-3f);
    EXPECT_NE(before.position, after.position);
    EXPECT_EQ(after.position, expected.position);
    EXPECT_EQ(after.du, expected.du);
}

TEST(PlanEngine, StencilPrefixServesEveryFactorOfItsLevel) {
    Cage cage = qp::test::makeMixedGrid();
    cage.setEdgeSharpness(0, 1, 1.5f);
    PlanDatabase db;
    PlannedCage planned = plan(cage, db);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
        const qp::Plan& p = db.plan(planned.subfacePlan(s));
        std::vector<glm::vec3> scratch;
        auto all = planned.controlPointsFor(s, qp::kMaxPlanDepth, scratch);
        for (uint32_t level = 0; level <= p.maxDepth; ++level) {
            // Control points beyond the prefix are poisoned: any use shows up as NaN.
            std::vector<glm::vec3> prefix(all.begin(), all.end());
            for (uint32_t i = p.stencilCountByLevel[level]; i < prefix.size(); ++i) prefix[i] = glm::vec3(nan);
            uint32_t lowest = level == 0 ? 1 : (1u << (level - 1)) + 1;
            for (uint32_t f = lowest; f <= (1u << level); ++f)
                for (uint32_t j = 0; j <= f; ++j)
                    for (uint32_t i = 0; i <= f; ++i) {
                        float u = float(i) / float(f), v = float(j) / float(f);
                        qp::LimitSample full = qp::evaluatePlan(p, all.data(), u, v);
                        qp::LimitSample partial = qp::evaluatePlan(p, prefix.data(), u, v);
                        ASSERT_EQ(full.position, partial.position)
                            << "sub-face " << s << " level " << level << " factor " << f << " at " << u << "," << v;
                    }
        }
    }
}

TEST(PlanEngine, MovingVerticesReplansNothing) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeSubdividedCube(), db);
    uint32_t plansBefore = db.size();
    glm::vec3 before = planned.evaluate(0, 0.5f, 0.5f).position;
    uint32_t v = planned.cage().faceBegin(0)[0];
    glm::vec3 moved = planned.cage().positions[v] + glm::vec3(0.3f, 0.2f, 0.1f);
    auto report = planned.moveVertices({&v, 1}, {&moved, 1});
    ASSERT_TRUE(report.ok());
    EXPECT_EQ(report->replannedFaces, 0u);
    EXPECT_EQ(report->newPlans, 0u);
    EXPECT_GT(report->updatedSubfaces, 0u);
    EXPECT_LT(report->updatedSubfaces, planned.subfaceCount());
    EXPECT_EQ(db.size(), plansBefore);
    EXPECT_NE(planned.evaluate(0, 0.5f, 0.5f).position, before);
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
}

TEST(PlanEngine, SharpnessEditReplansOnlyTheFacesAtTheEdge) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(8), db);
    auto report = planned.setEdgeSharpness(40, 41, 1.7f);
    ASSERT_TRUE(report.ok());
    EXPECT_EQ(report->replannedFaces, 6u);  // four faces at each end, two of them shared
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
}

TEST(PlanEngine, RandomEditSequencesEqualRebuild) {
    std::mt19937 rng(1234);
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeMixedGrid(), db);
    for (int step = 0; step < 60; ++step) {
        const Cage& cage = planned.cage();
        const qp::Topology& t = planned.topology();
        uint32_t kind = rng() % 6;
        qp::Result<qp::EditReport> report = qp::Error{"unset"};
        if (kind == 0) {
            uint32_t v = rng() % cage.vertexCount();
            glm::vec3 p = cage.positions[v] + glm::vec3(0.1f, -0.05f, 0.2f);
            report = planned.moveVertices({&v, 1}, {&p, 1});
        } else if (kind == 1) {
            uint32_t e = rng() % t.edgeCount();
            report = planned.setEdgeSharpness(t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1], float(rng() % 40) / 10.0f);
        } else if (kind == 2) {
            report = planned.setVertexSharpness(rng() % cage.vertexCount(), float(rng() % 30) / 10.0f);
        } else if (kind == 3) {
            uint32_t f = rng() % cage.faceCount();
            report = planned.setHole(f, !cage.isHole(f));
        } else if (kind == 4 && cage.faceCount() > 4) {
            uint32_t f = rng() % cage.faceCount();
            std::vector<uint32_t> vertices(cage.faceBegin(f), cage.faceBegin(f) + cage.faceSize(f));
            report = planned.removeFace(f);
            ASSERT_TRUE(report.ok()) << report.error().message;
            report = planned.addFace(vertices);  // put it back (now last)
        } else {
            continue;
        }
        ASSERT_TRUE(report.ok()) << report.error().message;
        std::vector<std::string> differences = planned.differencesFromRebuild();
        ASSERT_TRUE(differences.empty()) << "after step " << step << " (edit kind " << kind << "): " << differences[0];
    }
}

TEST(PlanEngine, EditsRejectBadInputWithoutChangingTheCage) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeGrid(3), db);
    EXPECT_FALSE(planned.setEdgeSharpness(0, 5, 1.0f).ok());  // a diagonal, not an edge
    EXPECT_FALSE(planned.setEdgeSharpness(0, 1, std::nanf("")).ok());
    EXPECT_FALSE(planned.setVertexSharpness(999, 1.0f).ok());
    uint32_t v = 0;
    glm::vec3 bad(std::nanf(""), 0, 0);
    EXPECT_FALSE(planned.moveVertices({&v, 1}, {&bad, 1}).ok());
    uint32_t degenerate[3] = {0, 1, 1};
    EXPECT_FALSE(planned.addFace(degenerate).ok());
    EXPECT_TRUE(planned.cage().creases.empty());
    EXPECT_EQ(planned.cage().faceCount(), 9u);
    EXPECT_TRUE(planned.differencesFromRebuild().empty());
}

TEST(PlanDatabase, PersistsAndRejectsDamagedFiles) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeMixedGrid(), db);
    auto path = std::filesystem::temp_directory_path() / ("qp-plans-" + std::to_string(::getpid()) + ".db");
    ASSERT_TRUE(db.save(path.string()).ok());

    PlanDatabase loaded;
    ASSERT_TRUE(loaded.load(path.string()).ok());
    ASSERT_EQ(loaded.size(), db.size());
    for (uint32_t i = 0; i < db.size(); ++i) EXPECT_TRUE(loaded.plan(i) == db.plan(i));
    // A cage planned against the loaded database builds nothing new.
    PlannedCage again = plan(qp::test::makeMixedGrid(), loaded);
    EXPECT_EQ(loaded.stats().misses, 0u);
    EXPECT_GT(loaded.stats().hits, 0u);

    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    auto writeAndLoad = [&](const std::string& contents) {
        std::ofstream(path, std::ios::binary | std::ios::trunc) << contents;
        PlanDatabase broken;
        qp::Status status = broken.load(path.string());
        EXPECT_EQ(broken.size(), 0u);
        return status;
    };
    std::string flipped = bytes;
    flipped[bytes.size() / 2] ^= 0x5a;
    qp::Status damaged = writeAndLoad(flipped);
    ASSERT_FALSE(damaged.ok());
    EXPECT_NE(damaged.error().message.find("checksum"), std::string::npos);
    EXPECT_FALSE(writeAndLoad(bytes.substr(0, bytes.size() / 3)).ok());
    EXPECT_FALSE(writeAndLoad("not a database at all").ok());
    EXPECT_FALSE(writeAndLoad("").ok());
    std::filesystem::remove(path);
    EXPECT_FALSE(PlanDatabase().load(path.string()).ok());  // missing file
}

// Files with a valid checksum but unsafe contents (a forged or buggy writer): each must be
// refused, since a plan that loads is applied to 1-rings without further checks. Found by
// tests/fuzz/fuzz_plan_db (an empty key array reached memcpy with a null pointer).
TEST(PlanDatabase, RejectsChecksumValidFilesWithUnsafePlans) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeMixedGrid(), db);
    auto path = std::filesystem::temp_directory_path() / ("qp-forged-" + std::to_string(::getpid()) + ".db");
    ASSERT_TRUE(db.save(path.string()).ok());
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    std::filesystem::remove(path);
    bytes.resize(bytes.size() - sizeof(uint64_t));  // the body, without its checksum
    auto word = [&](size_t at) {
        uint32_t w;
        std::memcpy(&w, bytes.data() + at, 4);
        return w;
    };
    auto setWord = [](std::string& b, size_t at, uint32_t w) { std::memcpy(b.data() + at, &w, 4); };
    auto load = [](std::string body) {
        const uint64_t sum = qp::planDatabaseChecksum(body.data(), body.size());
        body.append(reinterpret_cast<const char*>(&sum), sizeof(sum));
        PlanDatabase forged;
        qp::Status status = forged.loadFromBytes(body, "forged.db");
        if (!status) {
            EXPECT_EQ(forged.size(), 0u);
        }
        return status;
    };
    // Layout of the first entry (plan_database.cpp): magic 8 B, version, count, then key count
    // and key words, ring size, depth, node count and 12-byte nodes, point count and points,
    // weight count and weights, 11 per-level counts.
    const size_t keyAt = 16, keyWords = word(keyAt);
    const size_t ringAt = keyAt + 4 + 4 * keyWords;
    const size_t nodesAt = ringAt + 8, pointsAt = nodesAt + 4 + 12 * word(nodesAt);
    const size_t weightsAt = pointsAt + 4 + 4 * word(pointsAt);
    ASSERT_TRUE(load(bytes).ok());  // the unmodified body loads

    // A key whose 1-ring is one vertex smaller than the plan's stencils are wide: a face with
    // that key would have its stencils read past its 1-ring.
    std::string wrongRing = bytes;
    setWord(wrongRing, keyAt + 4 + 4 * 4, word(keyAt + 4 + 4 * 4) - 1);
    EXPECT_FALSE(load(wrongRing).ok());

    std::string emptyKey = bytes.substr(0, keyAt);
    setWord(emptyKey, 12, 1);
    emptyKey += std::string(4, '\0');                 // key count 0
    emptyKey += bytes.substr(ringAt, weightsAt - ringAt);  // ring size .. points
    emptyKey += std::string(4, '\0');                 // no weights
    emptyKey += std::string(4 * (qp::kMaxPlanDepth + 1), '\0');
    EXPECT_FALSE(load(emptyKey).ok());

    std::string nanWeight = bytes;
    ASSERT_GT(word(weightsAt), 0u);
    setWord(nanWeight, weightsAt + 4, 0x7fc00000u);  // quiet NaN
    EXPECT_FALSE(load(nanWeight).ok());
}

TEST(PlanEvaluator, BatchEqualsOneByOne) {
    PlanDatabase db;
    PlannedCage planned = plan(qp::test::makeMixedGrid(), db);
    std::vector<qp::SampleRequest> requests;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s)
        for (uint32_t k = 0; k < 50; ++k) requests.push_back({s, float(k % 7) / 6.0f, float(k / 7) / 7.0f});
    std::vector<qp::LimitSample> out(requests.size());
    qp::evaluateBatch(planned, requests, out);
    for (size_t i = 0; i < requests.size(); ++i) {
        qp::LimitSample one = planned.evaluate(requests[i].subface, requests[i].u, requests[i].v);
        ASSERT_EQ(out[i].position, one.position);
        ASSERT_EQ(out[i].du, one.du);
        ASSERT_EQ(out[i].dv, one.dv);
    }
}

// A quad gathered again takes the corner of its smallest key from what its thread remembers of
// the quads it gathered before; the key, ring and rotation must be a full gathering's (a fresh
// thread remembers nothing). Rotated copies, two-fold symmetric creases, creases and corners,
// extraordinary vertices and a fin of three faces on one edge (non-manifold: never remembered).
// Gathering with a GatherIndex gives the same, on these, a torus with one face wound the wrong
// way and a grid of quads, triangles and n-gons (every sub-face).
TEST(PlanEngine, QuadsGatheredAgainKeepAFullGatheringsKey) {
    Cage creased = qp::test::makeGrid(6);
    for (uint32_t x = 0; x < 6; ++x) creased.setEdgeSharpness(3 * 7 + x, 3 * 7 + x + 1, 1.5f);
    creased.setEdgeSharpness(1, 8, 3.0f);
    Cage fin = qp::test::makeGrid(3);
    const uint32_t a = 5, b = 6;  // an interior edge of the grid's second row
    const uint32_t top = uint32_t(fin.positions.size());
    fin.positions.push_back(fin.positions[a] + glm::vec3(0, 0, 1));
    fin.positions.push_back(fin.positions[b] + glm::vec3(0, 0, 1));
    fin.faceVertices.insert(fin.faceVertices.end(), {a, b, top + 1, top});
    fin.faceOffsets.push_back(uint32_t(fin.faceVertices.size()));
    // A torus with one face wound the other way: the fans at its corners do not close, so the
    // index must not take their orbits as cycles.
    Cage flipped = qp::test::makeTorus(8, 6);
    std::reverse(flipped.faceVertices.begin() + flipped.faceOffsets[9], flipped.faceVertices.begin() + flipped.faceOffsets[10]);
    const std::vector<Cage> cages = {qp::makeBenchmarkCage(600, 3), creased, qp::test::makeCube(), fin, flipped,
                                     qp::test::makeMixedGrid()};
    for (size_t c = 0; c < cages.size(); ++c) {
        const Cage& cage = cages[c];
        const qp::Topology topology = qp::buildTopology(cage);
        const qp::GatherIndex index = qp::buildGatherIndex(cage, topology);
        const qp::GatherIndex creasesOnly = qp::buildGatherIndex(cage, topology, false);
        EXPECT_TRUE(creasesOnly.cyclic.empty() && creasesOnly.orbitFaces.empty());
        EXPECT_EQ(creasesOnly.withCreases, index.withCreases);
        uint32_t cyclic = 0;
        for (uint8_t is : index.cyclic) cyclic += is;
        EXPECT_GT(cyclic, 0u) << "cage " << c << ": the index rotates no orbit";
        for (int pass = 0; pass < 3; ++pass)
            for (uint32_t f = 0; f < cage.faceCount(); ++f)
                for (uint32_t k = 0; k < qp::subfaceCount(cage.faceSize(f)); ++k) {
                    qp::FaceConfig full;
                    std::thread([&] { full = qp::gatherFaceConfig(cage, topology, f, k, PlanOptions{}); }).join();
                    // The second pass gathers with the index: creases looked up only at the
                    // vertices it marks, orbits of cyclic vertices rotated instead of walked;
                    // the third with the crease marks alone.
                    const qp::GatherIndex* with = pass == 1 ? &index : pass == 2 ? &creasesOnly : nullptr;
                    const qp::FaceConfig again = qp::gatherFaceConfig(cage, topology, f, k, PlanOptions{}, with);
                    ASSERT_EQ(again.key, full.key) << "cage " << c << " face " << f << " sub-face " << k << " pass " << pass;
                    ASSERT_EQ(again.ring, full.ring) << "cage " << c << " face " << f << " sub-face " << k;
                    ASSERT_EQ(again.rotation, full.rotation) << "cage " << c << " face " << f;
                    ASSERT_EQ(again.hash, qp::hashKey(full.key)) << "cage " << c << " face " << f;
                }
    }
    // Where the flipped face meets its neighbours the fans are not cycles.
    const qp::Topology flippedTopology = qp::buildTopology(flipped);
    const qp::GatherIndex flippedIndex = qp::buildGatherIndex(flipped, flippedTopology);
    for (uint32_t j = flipped.faceOffsets[9]; j < flipped.faceOffsets[10]; ++j)
        EXPECT_EQ(flippedIndex.cyclic[flipped.faceVertices[j]], 0) << "vertex " << flipped.faceVertices[j];
}
