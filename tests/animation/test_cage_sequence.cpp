// OBJ sequences (core/animation/cage_sequence.h): frames found and ordered by number, each checked against
// the cage's topology, every refusal naming the frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <glm/geometric.hpp>

#include "animation/cage_sequence.h"
#include "mesh/obj_io.h"
#include "test_cages.h"

using namespace qp;
namespace fs = std::filesystem;

namespace {

class CageSequence : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("quadplan_sequence_" + std::to_string(getpid()));
    Cage cube = test::makeSubdividedCube(2);
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }

    // Frame k: the cube stretched along x by 1 + k / 10.
    Cage frame(uint32_t k) const {
        Cage c = cube;
        for (glm::vec3& p : c.positions) p.x *= 1.0f + float(k) / 10.0f;
        return c;
    }
    void write(uint32_t number, const Cage& cage, const char* format = "frame_%04u.obj") {
        char name[64];
        std::snprintf(name, sizeof name, format, number);
        ASSERT_TRUE(saveObj(cage, (dir / name).string()));
    }
};

}  // namespace

TEST_F(CageSequence, FramesComeInNumberOrderWithTheirPositions) {
    for (uint32_t k : {3u, 1u, 10u, 2u, 4u, 5u, 6u, 7u, 8u, 9u}) write(k, frame(k));
    write(1, cube, "other_%04u.obj");  // another pattern in the same folder is not a frame
    Result<std::vector<SequenceFile>> files = sequenceFiles((dir / "frame_*.obj").string());
    ASSERT_TRUE(files) << files.error().message;
    ASSERT_EQ(files->size(), 10u);
    for (uint32_t i = 0; i < 10; ++i) {
        EXPECT_EQ((*files)[i].number, i + 1);
        Result<std::vector<glm::vec3>> positions = loadSequenceFrame((*files)[i].path, cube);
        ASSERT_TRUE(positions) << positions.error().message;
        const Cage expected = frame(i + 1);
        ASSERT_EQ(positions->size(), expected.positions.size());
        for (size_t v = 0; v < expected.positions.size(); ++v)
            EXPECT_LT(glm::length((*positions)[v] - expected.positions[v]), 1e-6f) << "frame " << i + 1 << " vertex " << v;
    }
}

TEST_F(CageSequence, RefusesGapsOtherTopologiesAndBadPatterns) {
    write(1, frame(1));
    write(3, frame(3));
    Result<std::vector<SequenceFile>> gap = sequenceFiles((dir / "frame_*.obj").string());
    ASSERT_FALSE(gap);
    EXPECT_NE(gap.error().message.find("missing frame 2"), std::string::npos) << gap.error().message;
    EXPECT_FALSE(sequenceFiles((dir / "frame_0001.obj").string())) << "a pattern without '*'";
    EXPECT_FALSE(sequenceFiles((dir / "none_*.obj").string())) << "a pattern nothing matches";

    // A face of another winding, a vertex too many, a NaN: each names its frame.
    Cage turned = cube;
    std::reverse(turned.faceVertices.begin() + turned.faceOffsets[5], turned.faceVertices.begin() + turned.faceOffsets[6]);
    write(7, turned, "bad_%04u.obj");
    Result<std::vector<glm::vec3>> other = loadSequenceFrame((dir / "bad_0007.obj").string(), cube);
    ASSERT_FALSE(other);
    EXPECT_NE(other.error().message.find("bad_0007.obj: face 5 differs"), std::string::npos) << other.error().message;
    Cage more = cube;
    more.positions.push_back({9, 9, 9});
    write(8, more, "bad_%04u.obj");
    Result<std::vector<glm::vec3>> extra = loadSequenceFrame((dir / "bad_0008.obj").string(), cube);
    ASSERT_FALSE(extra);
    EXPECT_NE(extra.error().message.find("bad_0008.obj: the frame has 27 vertices, the cage 26"), std::string::npos)
        << extra.error().message;
    write(9, cube, "bad_%04u.obj");
    {
        std::string text = formatObj(cube);
        text.replace(text.find("\nv "), 3, "\nv nan ");  // the first vertex line
        std::ofstream((dir / "bad_0009.obj").string()) << text;
    }
    Result<std::vector<glm::vec3>> nan = loadSequenceFrame((dir / "bad_0009.obj").string(), cube);
    ASSERT_FALSE(nan);
    EXPECT_NE(nan.error().message.find("bad_0009.obj"), std::string::npos) << nan.error().message;
}

// Only regular files are frames: a folder (or a device) named like one is not read, so the
// sequence is missing that frame.
TEST_F(CageSequence, OnlyRegularFilesAreFrames) {
    write(1, frame(1));
    write(3, frame(3));
    fs::create_directories(dir / "frame_0002.obj");
    Result<std::vector<SequenceFile>> files = sequenceFiles((dir / "frame_*.obj").string());
    ASSERT_FALSE(files);
    EXPECT_NE(files.error().message.find("missing frame 2"), std::string::npos) << files.error().message;
}
