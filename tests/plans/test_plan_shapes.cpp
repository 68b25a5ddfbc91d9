// The plan engine over OpenSubdiv's regression cages (../shared/shapes), checking in process
// what the per-shape `check-limit` ctest (default depth 6, crease nodes on) does not: other
// depths, plans without crease nodes, and the plan database's save -> load -> re-plan cycle.
// See docs/plan-engine.md for the method and the measured numbers.
//
// The big cages (catmark_pole360, catmark_nonman_quadpole360, catmark_car, catmark_pawn,
// catmark_lefthanded, catmark_righthanded) are left out to keep this under ~20 s; the
// per-shape ctest covers them at the default depth.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "mesh/obj_io.h"
#include "plans/limit_check.h"
#include "plans/planned_cage.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using qp::Cage;
using qp::PlanDatabase;
using qp::PlannedCage;
using qp::PlanOptions;

const std::vector<std::string> kBigCages = {"catmark_pole360", "catmark_nonman_quadpole360", "catmark_car",
                                            "catmark_pawn",    "catmark_lefthanded",         "catmark_righthanded"};

struct Shape {
    std::string name;
    Cage cage;
};

// Every catmark_ cage except the big ones, loaded once for all tests.
const std::vector<Shape>& smallShapes() {
    static const std::vector<Shape> shapes = [] {
        std::vector<Shape> loaded;
        for (const fs::path& path : qp::test::sharedShapes("catmark_")) {
            std::string name = path.stem().string();
            if (std::find(kBigCages.begin(), kBigCages.end(), name) != kBigCages.end()) continue;
            std::vector<std::string> warnings;  // normals and repaired faces; not what is tested here
            auto cage = qp::loadObj(path.string(), &warnings);
            EXPECT_TRUE(cage.ok()) << name << ": " << (cage.ok() ? "" : cage.error().message);
            if (cage.ok()) loaded.push_back({name, std::move(cage).value()});
        }
        return loaded;
    }();
    return shapes;
}

const Shape* findShape(const std::string& name) {
    for (const Shape& s : smallShapes())
        if (s.name == name) return &s;
    return nullptr;
}

// Plans the cage and compares with Far at the same depth; failures name the cage and the errors.
void expectMatchesOpenSubdiv(const Shape& shape, const PlanOptions& options) {
    SCOPED_TRACE(shape.name + " depth " + std::to_string(options.maxDepth) +
                 (options.useCreaseNodes ? "" : " without crease nodes"));
    PlanDatabase db;
    auto planned = PlannedCage::create(shape.cage, db, options, shape.name);
    ASSERT_TRUE(planned.ok()) << planned.error().message;
    auto reference = qp::LimitReference::create(shape.cage, options.maxDepth, shape.name);
    ASSERT_TRUE(reference.ok()) << reference.error().message;
    qp::LimitCheck check = qp::compareWithReference(*planned, *reference, 9);
    EXPECT_GT(check.subfaces, 0u);
    EXPECT_LE(check.maxPositionError, qp::kPositionTolerance) << "worst sub-face " << check.worstPositionSubface;
    EXPECT_LE(check.maxDerivativeError, qp::derivativeTolerance(options.maxDepth)) << "worst sub-face " << check.worstDerivativeSubface;
}

bool hasSemiSharpTags(const Cage& cage) {
    for (const qp::EdgeCrease& c : cage.creases)
        if (c.sharpness > 0.0f && c.sharpness < qp::kInfiniteSharpness) return true;
    for (const qp::VertexCorner& c : cage.corners)
        if (c.sharpness > 0.0f && c.sharpness < qp::kInfiniteSharpness) return true;
    return false;
}

TEST(PlanShapes, ShallowAndDeepPlansMatchOpenSubdiv) {
    QP_REQUIRE_SHARED_SHAPES();
    // EVs, n-gons, Gregory end caps, semi-sharp and infinitely sharp creases, boundaries.
    // Derivative errors grow about 2x per level (float control points, 2^depth scale inside
    // deep nodes), which derivativeTolerance(depth) allows for (docs/plan-engine.md).
    const std::vector<std::string> names = {"catmark_cube",          "catmark_pyramid_creases1", "catmark_nonquads",
                                            "catmark_gregory_test2", "catmark_single_crease",    "catmark_cubes_semisharp",
                                            "catmark_pole8",         "catmark_dart_edgeonly",    "catmark_val2_interior",
                                            "catmark_flap"};
    for (const std::string& name : names) {
        const Shape* shape = findShape(name);
        ASSERT_NE(shape, nullptr) << name << " is missing from ../shared/shapes";
        expectMatchesOpenSubdiv(*shape, PlanOptions{3, true});
        expectMatchesOpenSubdiv(*shape, PlanOptions{8, true});
    }
}

TEST(PlanShapes, PlansWithoutCreaseNodesMatchOpenSubdiv) {
    QP_REQUIRE_SHARED_SHAPES();
    uint32_t checked = 0;
    for (const Shape& shape : smallShapes()) {
        if (!hasSemiSharpTags(shape.cage)) continue;
        expectMatchesOpenSubdiv(shape, PlanOptions{6, false});
        ++checked;
    }
    EXPECT_GE(checked, 10u) << "expected the crease cages (cube_creases*, tent_creases*, ...) to be found";
}

TEST(PlanShapes, DatabaseSurvivesSaveLoadAndReplansWithoutMisses) {
    QP_REQUIRE_SHARED_SHAPES();
    const fs::path dir = fs::temp_directory_path() / ("qp-plan-shapes-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    for (const Shape& shape : smallShapes()) {
        for (bool creaseNodes : {true, false}) {
            SCOPED_TRACE(shape.name + (creaseNodes ? "" : " without crease nodes"));
            const PlanOptions options{6, creaseNodes};
            PlanDatabase built;
            auto first = PlannedCage::create(shape.cage, built, options, shape.name);
            ASSERT_TRUE(first.ok()) << first.error().message;
            const std::string path = (dir / (shape.name + (creaseNodes ? ".db" : ".nc.db"))).string();
            ASSERT_TRUE(built.save(path).ok());

            PlanDatabase loaded;
            qp::Status status = loaded.load(path);
            ASSERT_TRUE(status.ok()) << status.error().message;
            ASSERT_EQ(loaded.size(), built.size());
            auto second = PlannedCage::create(shape.cage, loaded, options, shape.name);
            ASSERT_TRUE(second.ok()) << second.error().message;
            qp::PlanDatabaseStats stats = loaded.stats();
            EXPECT_EQ(stats.misses, 0u) << "re-planning after load built new plans";
            EXPECT_EQ(loaded.size(), built.size());

            ASSERT_EQ(second->subfaceCount(), first->subfaceCount());
            for (uint32_t s = 0; s < first->subfaceCount(); ++s) {
                ASSERT_EQ(first->hasSurface(s), second->hasSurface(s)) << "sub-face " << s;
                if (!first->hasSurface(s)) continue;
                EXPECT_EQ(loaded.plan(second->subfacePlan(s)), built.plan(first->subfacePlan(s))) << "sub-face " << s;
                EXPECT_EQ(second->subfaceRotation(s), first->subfaceRotation(s)) << "sub-face " << s;
                qp::LimitSample a = first->evaluate(s, 0.3f, 0.7f), b = second->evaluate(s, 0.3f, 0.7f);
                EXPECT_EQ(a.position, b.position) << "sub-face " << s;
            }
        }
    }
    std::error_code ignored;
    fs::remove_all(dir, ignored);
}

}  // namespace
