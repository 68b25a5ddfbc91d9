#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "mesh/cage.h"
#include "mesh/file_io.h"
#include "mesh/obj_io.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;

// A fresh empty directory per test, removed afterwards.
class ObjTempDir : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("quadplan_obj_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

bool samePositions(const qp::Cage& a, const qp::Cage& b) {
    return a.positions == b.positions && a.uvs == b.uvs;
}

bool anyContains(const std::vector<std::string>& lines, const std::string& part) {
    for (const std::string& line : lines)
        if (line.find(part) != std::string::npos) return true;
    return false;
}

const char* kQuad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

// A shared shape with a face that visits a vertex twice, non-consecutively.
const char* kFoldedShape = "catmark_nonman_edges.obj";

}  // namespace

// --- Shared shapes ------------------------------------------------------------------------------

TEST(ObjShapes, EveryShapeLoadsAndRoundTrips) {
    QP_REQUIRE_SHARED_SHAPES();
    std::vector<fs::path> shapes = qp::test::sharedShapes();
    ASSERT_GE(shapes.size(), 100u);
    for (const fs::path& path : shapes) {
        SCOPED_TRACE(path.filename().string());
        qp::Result<qp::Cage> first = qp::loadObj(path.string());
        ASSERT_TRUE(first.ok()) << first.error().message;
        std::string text = qp::formatObj(*first);
        std::vector<std::string> warnings;
        qp::Result<qp::Cage> second = qp::parseObj(text, "round trip", &warnings);
        ASSERT_TRUE(second.ok()) << second.error().message;
        EXPECT_TRUE(qp::sameTopologyAndTags(*first, *second));
        EXPECT_TRUE(samePositions(*first, *second));
        EXPECT_TRUE(warnings.empty()) << "our own output should load cleanly: " << warnings.front();
        EXPECT_EQ(qp::formatObj(*second), text) << "formatting is not stable";
    }
}

// `f  95/107  96/108  95/109  97/110` visits vertex 95 twice: non-manifold, and kept as is,
// as OpenSubdiv keeps it.
TEST(ObjShapes, FaceVisitingAVertexTwiceIsKept) {
    QP_REQUIRE_SHARED_SHAPES();
    std::string path = (qp::test::sharedShapesDir() / kFoldedShape).string();
    qp::Result<qp::Cage> cage = qp::loadObj(path);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    bool found = false;
    for (uint32_t f = 0; f < cage->faceCount(); ++f) {
        const uint32_t* fv = cage->faceBegin(f);
        if (cage->faceSize(f) == 4 && fv[0] == 94 && fv[1] == 95 && fv[2] == 94 && fv[3] == 96) found = true;
    }
    EXPECT_TRUE(found);
}

// `f 4 3 5 5`: OpenSubdiv's way of writing a triangle among quads.
TEST(ObjShapes, ConsecutiveRepeatsCollapse) {
    QP_REQUIRE_SHARED_SHAPES();
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage =
        qp::loadObj((qp::test::sharedShapesDir() / "catmark_nonman_quadpole8.obj").string(), &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    ASSERT_EQ(cage->faceSize(1), 3u);  // line 19
    EXPECT_EQ(std::vector<uint32_t>(cage->faceBegin(1), cage->faceBegin(1) + 3), (std::vector<uint32_t>{3, 2, 4}));
    EXPECT_TRUE(anyContains(warnings, ":19: face repeats a vertex consecutively")) << ::testing::PrintToString(warnings);
}

TEST(ObjShapes, CubeCreases1) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::Result<qp::Cage> cage = qp::loadObj((qp::test::sharedShapesDir() / "catmark_cube_creases1.obj").string());
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_EQ(cage->vertexCount(), 8u);
    EXPECT_EQ(cage->faceCount(), 6u);
    ASSERT_EQ(cage->creases.size(), 12u);
    EXPECT_FLOAT_EQ(cage->edgeSharpness(0, 1), 5.0f);
    EXPECT_FLOAT_EQ(cage->edgeSharpness(6, 4), 5.0f);
    EXPECT_FLOAT_EQ(cage->edgeSharpness(5, 3), 0.1f);  // `t crease 2/1/0 3 5 0.1`
    EXPECT_EQ(cage->options.boundary, qp::BoundaryInterpolation::EdgesOnly);  // `interpolateboundary 2`
    // `f 1/1/1 2/2/2 4/4/3 3/3/4`: UVs kept, normals dropped.
    ASSERT_EQ(cage->uvs.size(), 14u);
    EXPECT_EQ(cage->faceUVIndices[2], 3u);
    EXPECT_FLOAT_EQ(cage->positions[1].x, 1.414214f);
}

TEST(ObjShapes, HoleTest1) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::Result<qp::Cage> cage = qp::loadObj((qp::test::sharedShapesDir() / "catmark_hole_test1.obj").string());
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    ASSERT_EQ(cage->holes.size(), 1u);
    EXPECT_TRUE(cage->isHole(1));
}

TEST(ObjShapes, HoleTest2HasFourHoles) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::Result<qp::Cage> cage = qp::loadObj((qp::test::sharedShapesDir() / "catmark_hole_test2.obj").string());
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_EQ(cage->holes, (std::vector<uint32_t>{5, 6, 9, 10}));  // `t hole 4/0/0 5 6 9 10`
}

TEST(ObjShapes, ChaikinCreaseMethod) {
    QP_REQUIRE_SHARED_SHAPES();
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> chaikin =
        qp::loadObj((qp::test::sharedShapesDir() / "catmark_chaikin1.obj").string(), &warnings);
    ASSERT_TRUE(chaikin.ok()) << chaikin.error().message;
    EXPECT_EQ(chaikin->options.creaseMethod, qp::CreaseMethod::Chaikin);

    // catmark_chaikin0 says `creasemethod normal`; 28 creases, 5.0 then 1..5 ramps.
    qp::Result<qp::Cage> normal = qp::loadObj((qp::test::sharedShapesDir() / "catmark_chaikin0.obj").string());
    ASSERT_TRUE(normal.ok()) << normal.error().message;
    EXPECT_EQ(normal->options.creaseMethod, qp::CreaseMethod::Normal);
    EXPECT_EQ(normal->creases.size(), 28u);
    EXPECT_FLOAT_EQ(normal->edgeSharpness(4, 6), 3.0f);
    EXPECT_EQ(normal->uvs.size(), 24u);
    EXPECT_EQ(normal->faceUVIndices.size(), normal->faceVertices.size());
}

TEST(ObjShapes, SmoothTrianglesAndFVarOptions) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::Result<qp::Cage> smooth = qp::loadObj((qp::test::sharedShapesDir() / "catmark_smoothtris1.obj").string());
    ASSERT_TRUE(smooth.ok()) << smooth.error().message;
    bool anySmooth = false;
    for (const fs::path& path : qp::test::sharedShapes("catmark_smoothtris")) {
        qp::Result<qp::Cage> c = qp::loadObj(path.string());
        ASSERT_TRUE(c.ok()) << c.error().message;
        anySmooth = anySmooth || c->options.triangleSubdivision == qp::TriangleSubdivision::Smooth;
    }
    EXPECT_TRUE(anySmooth) << "one smoothtris shape says `t smoothtriangles 0/0/1 smooth`";

    bool anyCornersOnly = false;
    for (const fs::path& path : qp::test::sharedShapes("catmark_cubes_")) {
        qp::Result<qp::Cage> c = qp::loadObj(path.string());
        ASSERT_TRUE(c.ok()) << c.error().message;
        anyCornersOnly = anyCornersOnly || c->options.fvarInterpolation == qp::FVarInterpolation::CornersOnly;
    }
    EXPECT_TRUE(anyCornersOnly) << "catmark_cubes_* say `facevaryinginterpolateboundary 1/0/0 1`";
}

TEST(ObjShapes, BareVerticesAreKept) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::Result<qp::Cage> cage =
        qp::loadObj((qp::test::sharedShapesDir() / "catmark_nonman_bareverts.obj").string());
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_EQ(cage->vertexCount(), 25u);
    EXPECT_EQ(cage->faceCount(), 8u);
    EXPECT_EQ(cage->uvs.size(), 31u);
}

TEST(ObjShapes, HierarchicalEditsWarn) {
    QP_REQUIRE_SHARED_SHAPES();
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage =
        qp::loadObj((qp::test::sharedShapesDir() / "catmark_square_hedit0.obj").string(), &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_TRUE(anyContains(warnings, "unknown tag")) << ::testing::PrintToString(warnings);
}

TEST(ObjShapes, CarParses) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::Result<qp::Cage> cage = qp::loadObj((qp::test::sharedShapesDir() / "catmark_car.obj").string());
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_EQ(cage->faceCount(), 1575u);
}

// --- Broken files ---------------------------------------------------------------------------------

struct BrokenCase {
    const char* file;
    int line;  // 0: the message names no line
    const char* keyword;
};

class ObjBroken : public ::testing::TestWithParam<BrokenCase> {};

TEST_P(ObjBroken, ErrorNamesFileLineAndCause) {
    const BrokenCase& c = GetParam();
    std::string path = qp::test::dataPath(std::string("broken/") + c.file);
    qp::Result<qp::Cage> cage = qp::loadObj(path);
    ASSERT_FALSE(cage.ok()) << c.file << " should not load";
    const std::string& message = cage.error().message;
    std::string where = c.line ? path + ":" + std::to_string(c.line) + ": " : path + ": ";
    EXPECT_EQ(message.rfind(where, 0), 0u) << message;
    EXPECT_NE(message.find(c.keyword), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Obj, ObjBroken,
    ::testing::Values(BrokenCase{"truncated_vertex.obj", 3, "truncated 'v' line"},
                      BrokenCase{"non_numeric.obj", 3, "coordinate y 'zero' is not a number"},
                      BrokenCase{"garbage.obj", 2, "not an OBJ"},
                      BrokenCase{"face_out_of_range.obj", 5, "out of range"},
                      BrokenCase{"face_index_zero.obj", 5, "index 0"},
                      BrokenCase{"nan_coordinate.obj", 5, "finite"},
                      BrokenCase{"inf_coordinate.obj", 6, "finite"},
                      BrokenCase{"two_vertex_face.obj", 6, "at least 3"},
                      BrokenCase{"crease_not_edge.obj", 7, "not joined by an edge"},
                      BrokenCase{"negative_sharpness.obj", 6, "negative"},
                      BrokenCase{"nan_sharpness.obj", 6, "not a finite number"},
                      BrokenCase{"tag_count_mismatch.obj", 6, "count mismatch"},
                      BrokenCase{"empty.obj", 0, "no faces"}),
    [](const ::testing::TestParamInfo<BrokenCase>& info) {
        std::string name = info.param.file;
        return name.substr(0, name.find('.'));
    });

TEST(ObjParse, UnknownTagLoadsWithWarning) {
    std::string path = qp::test::dataPath("broken/unknown_tag.obj");
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::loadObj(path, &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].rfind(path + ":6: ", 0), 0u) << warnings[0];
    EXPECT_NE(warnings[0].find("vertexedit"), std::string::npos) << warnings[0];
    EXPECT_EQ(cage->options.boundary, qp::BoundaryInterpolation::EdgesOnly);
}

TEST(ObjParse, HugeSharpnessIsClampedWithWarning) {
    std::string path = qp::test::dataPath("broken/huge_sharpness.obj");
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::loadObj(path, &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_EQ(cage->edgeSharpness(0, 1), qp::kInfiniteSharpness);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(path + ":6: "), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("clamped to 10"), std::string::npos) << warnings[0];
}

TEST(ObjParse, RepeatedClampsGiveOneWarningWithCount) {
    std::string text = std::string(kQuad) + "f 1 2 3 4\nt crease 4/1/0 0 1 1 2 50\nt corner 1/1/0 3 11\n";
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::parseObj(text, "mem", &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("mem:6:"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("(3 lines)"), std::string::npos) << warnings[0];
}

TEST(ObjParse, NormalsGiveOneWarning) {
    std::string text = std::string(kQuad) + "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1//1 2//2 3//3 4//1\n";
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::parseObj(text, "mem", &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("3 normals"), std::string::npos) << warnings[0];
    EXPECT_TRUE(cage->uvs.empty());
}

TEST(ObjParse, FaceFormsAndRelativeIndices) {
    std::string text = std::string(kQuad) +
                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                       "vn 0 0 1\n"
                       "f 1/1/1 2/2/1 3/3/1\n"
                       "f -4/-4 -2/-2 -1/-1\n";
    qp::Result<qp::Cage> cage = qp::parseObj(text, "mem");
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_EQ(cage->faceVertices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(cage->faceUVIndices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(ObjParse, IgnoresGroupsCommentsCrLfAndW) {
    std::string text =
        "\xEF\xBB\xBF# comment\r\nmtllib a.mtl\r\no obj\r\ng grp\r\ns 1\r\nusemtl m\r\n\r\n"
        "v 0 0 0 1 \r\nv\t1 0 0\r\nv 1 1 0 # trailing comment\r\nv +0 1 0\r\n"
        "f 1 2 3 4  \r\n";
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::parseObj(text, "mem", &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_EQ(cage->vertexCount(), 4u);
    EXPECT_EQ(cage->faceCount(), 1u);
}

TEST(ObjParse, TagsInAnyOrderAreNormalized) {
    std::string text = std::string(kQuad) +
                       "t crease 4/2/0 3 2 1 0 2.5 1.5\n"  // before the face; one sharpness per edge
                       "f 1 2 3 4\n"
                       "t crease 2/1/0 0 1 3\n"  // a later tag overrides an earlier one
                       "t corner 2/1/0 2 0 4\n"
                       "t hole 1/0/0 0\n"
                       "t creasemethod 0/0/1 chaikin\n"
                       "t interpolateboundary 1/0/0 0\n"
                       "t facevaryingpropagatecorners 1/0/0 1\n";
    qp::Result<qp::Cage> cage = qp::parseObj(text, "mem");
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    ASSERT_EQ(cage->creases.size(), 2u);
    EXPECT_EQ(cage->edgeSharpness(2, 3), 2.5f);
    EXPECT_EQ(cage->edgeSharpness(0, 1), 3.0f);
    EXPECT_EQ(cage->vertexSharpness(0), 4.0f);
    EXPECT_EQ(cage->vertexSharpness(2), 4.0f);
    EXPECT_TRUE(cage->isHole(0));
    EXPECT_EQ(cage->options.creaseMethod, qp::CreaseMethod::Chaikin);
    EXPECT_EQ(cage->options.boundary, qp::BoundaryInterpolation::None);
    EXPECT_TRUE(cage->options.fvarPropagateCorners);
}

// OpenSubdiv numbers interpolateboundary 1 = edges and corners, 2 = edges only, and reads an
// untagged file as edges only.
TEST(ObjParse, BoundaryTagUsesOpenSubdivNumbering) {
    std::string base = std::string(kQuad) + "f 1 2 3 4\n";
    auto boundaryOf = [&](const std::string& tag) {
        qp::Result<qp::Cage> cage = qp::parseObj(base + tag, "mem");
        EXPECT_TRUE(cage.ok()) << cage.error().message;
        return cage.ok() ? cage->options.boundary : qp::BoundaryInterpolation::None;
    };
    EXPECT_EQ(boundaryOf(""), qp::BoundaryInterpolation::EdgesOnly);
    EXPECT_EQ(boundaryOf("t interpolateboundary 1/0/0 1\n"), qp::BoundaryInterpolation::EdgesAndCorners);
    EXPECT_EQ(boundaryOf("t interpolateboundary 1/0/0 2\n"), qp::BoundaryInterpolation::EdgesOnly);

    qp::Cage cage = *qp::parseObj(base, "mem");
    cage.options.boundary = qp::BoundaryInterpolation::EdgesAndCorners;
    EXPECT_NE(qp::formatObj(cage).find("t interpolateboundary 1/0/0 1\n"), std::string::npos);
}

TEST(ObjParse, MoreBadInputNamesLineAndField) {
    struct Case {
        std::string text;
        const char* expected;
    };
    std::string face = std::string(kQuad) + "f 1 2 3 4\n";
    const Case cases[] = {
        {std::string(kQuad) + "f 1 2 3 x\n", "mem:5: vertex index 'x' is not an integer"},
        {std::string(kQuad) + "f 1 2 -9\n", "mem:5: relative vertex index -9 is out of range"},
        {std::string(kQuad) + "f 1/1 2/1 3/1\n", "mem:5: face refers to texture coordinate 1"},
        {std::string(kQuad) + "vt 0 0\nf 1/1 2 3\n", "mem:6: face gives texture coordinates for some corners"},
        {std::string(kQuad) + "vt 0\nf 1 2 3\n", "mem:5: truncated 'vt' line"},
        {std::string(kQuad) + "v 1e50 0 0\nf 1 2 3\n", "mem:5: coordinate x '1e50' is not a number"},
        {face + "t\n", "mem:6: tag line 't' has no tag name"},
        {face + "t crease\n", "mem:6: tag 'crease': missing the nInts/nFloats/nStrings counts"},
        {face + "t crease 2/1 0 1 1\n", "mem:6: tag 'crease': counts '2/1' are not of the form"},
        {face + "t crease 3/1/0 0 1 2 1\n", "mem:6: tag 'crease' needs pairs"},
        {face + "t crease 4/3/0 0 1 1 2 1 1 1\n", "mem:6: tag 'crease' needs 1 sharpness or one per edge"},
        {face + "t crease 2/1/0 0 0 1\n", "mem:6: tag 'crease': edge 0-0 joins a vertex to itself"},
        {face + "t crease 2/1/0 0 -1 1\n", "mem:6: tag 'crease': index -1 is out of range"},
        {face + "t crease 2/1/0 0 a 1\n", "mem:6: tag 'crease': integer 2 'a' is not an integer"},
        {face + "t corner 1/1/0 7 1\n", "mem:6: tag 'corner': vertex 7 (0-based) is out of range"},
        {face + "t corner 1/1/0 1 inf\n", "mem:6: tag 'corner': sharpness 'inf' is not a finite number"},
        {face + "t hole 1/0/0 1\n", "mem:6: tag 'hole': face 1 (0-based) is out of range"},
        {face + "t interpolateboundary 1/0/0 3\n", "mem:6: tag 'interpolateboundary': value 3 is out of range"},
        {face + "t interpolateboundary 0/0/1 edges\n", "mem:6: tag 'interpolateboundary' expects 1/0/0"},
        {face + "t facevaryinginterpolateboundary 1/0/0 6\n", "mem:6: tag 'facevaryinginterpolateboundary': value 6"},
        {face + "t creasemethod 0/0/1 sharp\n", "mem:6: tag 'creasemethod': unknown value 'sharp'"},
        {face + "\x01\x02\n", "mem:6: binary data"},
        {face + "%%%\n", "mem:6: unrecognized line starting with '%%%'"},
        {"# only comments\nv 0 0 0\n", "mem: no faces"},
    };
    for (const Case& c : cases) {
        qp::Result<qp::Cage> cage = qp::parseObj(c.text, "mem");
        ASSERT_FALSE(cage.ok()) << c.text;
        EXPECT_EQ(cage.error().message.rfind(c.expected, 0), 0u) << cage.error().message;
    }
}

TEST(ObjParse, DegenerateFacesAreDroppedAndHolesRenumbered) {
    std::string text = std::string(kQuad) +
                       "f 1 1 1\n"       // file face 0: one vertex, dropped
                       "f 2 2 3 3 2\n"   // file face 1: an edge, dropped
                       "f 1 2 3 4 1\n"   // file face 2: quad with a repeated closing vertex
                       "t hole 2/0/0 0 2\n";
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::parseObj(text, "mem", &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    ASSERT_EQ(cage->faceCount(), 1u);
    EXPECT_EQ(cage->faceSize(0), 4u);
    EXPECT_EQ(cage->holes, (std::vector<uint32_t>{0}));
    EXPECT_TRUE(anyContains(warnings, "mem:5: face has fewer than 3 distinct vertices; dropped (2 lines)"))
        << ::testing::PrintToString(warnings);
    EXPECT_TRUE(anyContains(warnings, "mem:7: face repeats a vertex consecutively"));
    EXPECT_TRUE(anyContains(warnings, "1 hole tags name dropped faces"));
}

TEST(ObjParse, UnsupportedStatementsWarnOnce) {
    std::string text = std::string(kQuad) + "f 1 2 3 4\nl 1 2\nl 2 3\n";
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::parseObj(text, "mem", &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], "mem:6: unsupported OBJ statement 'l' ignored (2 lines)");
}

TEST(ObjParse, FacesWithoutUVsAmongOthersDropUVsWithWarning) {
    std::string text = std::string(kQuad) + "vt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\nf 1 3 4\n";
    std::vector<std::string> warnings;
    qp::Result<qp::Cage> cage = qp::parseObj(text, "mem", &warnings);
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_TRUE(cage->uvs.empty());
    EXPECT_TRUE(cage->faceUVIndices.empty());
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("mem:9: face has no texture coordinates"), std::string::npos) << warnings[0];
}

TEST(ObjParse, GarbageNeverCrashes) {
    // Every prefix of a valid file, and the file with each byte replaced, either loads or fails cleanly.
    std::string text = std::string(kQuad) + "vt 0 0\nf 1/1 2/1 3/1 4/1\nt crease 2/1/0 0 1 2\nt hole 1/0/0 0\n";
    for (size_t n = 0; n <= text.size(); ++n) (void)qp::parseObj(text.substr(0, n), "mem");
    for (size_t i = 0; i < text.size(); ++i)
        for (char c : {'\0', '/', '-', '9', ' ', '\n', 'e', '\xff'}) {
            std::string broken = text;
            broken[i] = c;
            qp::Result<qp::Cage> cage = qp::parseObj(broken, "mem");
            if (!cage.ok()) {
                EXPECT_EQ(cage.error().message.rfind("mem", 0), 0u) << cage.error().message;
            }
        }
}

// --- Writing --------------------------------------------------------------------------------------

TEST(ObjFormat, UVsAndAllOptionsRoundTrip) {
    qp::Cage cage = *qp::parseObj(std::string(kQuad) + "vt 0 0\nvt 0.1 0.2\nvt 1 1\nf 1/1 2/2 3/3 4/2\n", "mem");
    cage.positions[2] = {0.1f, 1e-7f, -3.4028235e38f};
    cage.setEdgeSharpness(0, 1, 0.1f);
    cage.setEdgeSharpness(3, 0, 10.0f);
    cage.setVertexSharpness(2, 1.0f / 3.0f);
    cage.setHole(0, true);
    cage.options = {qp::BoundaryInterpolation::None, qp::CreaseMethod::Chaikin, qp::TriangleSubdivision::Smooth,
                    qp::FVarInterpolation::CornersPlus1, true};
    std::string text = qp::formatObj(cage);
    qp::Result<qp::Cage> back = qp::parseObj(text, "mem");
    ASSERT_TRUE(back.ok()) << back.error().message << "\n" << text;
    EXPECT_TRUE(qp::sameTopologyAndTags(cage, *back)) << text;
    EXPECT_TRUE(samePositions(cage, *back)) << text;
    EXPECT_EQ(back->vertexSharpness(2), 1.0f / 3.0f);

    // Tags come in the order crease, corner, hole, options.
    size_t crease = text.find("t crease"), corner = text.find("t corner"), hole = text.find("t hole"),
           options = text.find("t interpolateboundary");
    EXPECT_LT(crease, corner);
    EXPECT_LT(corner, hole);
    EXPECT_LT(hole, options);
}

TEST(ObjFormat, DefaultOptionsWriteOnlyInterpolateBoundary) {
    qp::Cage cage = *qp::parseObj(std::string(kQuad) + "f 1 2 3 4\nt interpolateboundary 1/0/0 1\n", "mem");
    std::string text = qp::formatObj(cage);
    EXPECT_NE(text.find("t interpolateboundary 1/0/0 1\n"), std::string::npos) << text;
    EXPECT_EQ(text.find("t creasemethod"), std::string::npos) << text;
    EXPECT_EQ(text.find("t smoothtriangles"), std::string::npos) << text;
    EXPECT_EQ(text.find("t facevarying"), std::string::npos) << text;
    EXPECT_EQ(text.find("vt "), std::string::npos) << text;
    EXPECT_NE(text.find("f 1 2 3 4\n"), std::string::npos) << text;
}

// --- Files ----------------------------------------------------------------------------------------

TEST_F(ObjTempDir, LoadMissingPathOrDirectoryNamesPath) {
    std::string missing = (dir_ / "missing.obj").string();
    qp::Result<qp::Cage> a = qp::loadObj(missing);
    ASSERT_FALSE(a.ok());
    EXPECT_NE(a.error().message.find(missing), std::string::npos) << a.error().message;

    qp::Result<qp::Cage> b = qp::loadObj(dir_.string());
    ASSERT_FALSE(b.ok());
    EXPECT_NE(b.error().message.find(dir_.string()), std::string::npos) << b.error().message;
}

TEST_F(ObjTempDir, SaveIntoMissingDirectoryFailsAndLeavesNothing) {
    qp::Cage cage = *qp::parseObj(std::string(kQuad) + "f 1 2 3 4\n", "mem");
    std::string path = (dir_ / "nope" / "cage.obj").string();
    qp::Status s = qp::saveObj(cage, path);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find(path), std::string::npos) << s.error().message;
    EXPECT_FALSE(fs::exists(dir_ / "nope"));
    EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(ObjTempDir, SaveReplacesExistingFileWhole) {
    fs::path path = dir_ / "cage.obj";
    {
        std::ofstream old(path);
        old << std::string(100000, '#') << "\n";  // longer than the new contents
    }
    qp::Cage cage = *qp::parseObj(std::string(kQuad) + "f 1 2 3 4\nt crease 2/1/0 1 2 4\n", "mem");
    ASSERT_TRUE(qp::saveObj(cage, path.string()).ok());
    EXPECT_EQ(slurp(path), qp::formatObj(cage));
    qp::Result<qp::Cage> back = qp::loadObj(path.string());
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_TRUE(qp::sameTopologyAndTags(cage, *back));
    // Only the file itself: no temporary left behind.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}
