// Cage animation (core/animation/cage_animation.h, core/animation/animation_playback.h, the scene file's keys):
// interpolation, keys set and replaced, topology edits carried to every frame, scene round trips
// and sequences, every refusal naming the frame, and playback that re-plans nothing and equals a
// cage planned from scratch at each frame.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "animation/animation_edits.h"
#include "animation/animation_playback.h"
#include "animation/cage_animation.h"
#include "mesh/obj_io.h"
#include "mesh/topology_edits.h"
#include "plans/plan_database.h"
#include "scene/scene.h"
#include "test_cages.h"

using namespace qp;
namespace fs = std::filesystem;

namespace {

// Keys every vertex of `cage` at `frames`, the cage twisted about y by 10 degrees per frame.
ObjectAnimation twist(const Cage& cage, std::initializer_list<int32_t> frames, Interpolation interpolation) {
    ObjectAnimation a;
    a.interpolation = interpolation;
    std::vector<uint32_t> all(cage.positions.size());
    for (uint32_t v = 0; v < all.size(); ++v) all[v] = v;
    for (int32_t f : frames) {
        std::vector<glm::vec3> p = cage.positions;
        for (glm::vec3& q : p) {
            const float angle = glm::radians(10.0f * float(f)) * (q.y + 1.0f);
            q = glm::vec3(q.x * std::cos(angle) - q.z * std::sin(angle), q.y, q.x * std::sin(angle) + q.z * std::cos(angle));
        }
        setVertexKeys(a, uint32_t(all.size()), f, all, p);
    }
    return a;
}

float maxDistance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
    float d = 0.0f;
    for (size_t i = 0; i < a.size(); ++i) d = std::max(d, glm::length(a[i] - b[i]));
    return d;
}

}  // namespace

TEST(CageAnimation, TracksHitTheirKeysInterpolateBetweenAndHoldOutside) {
    ObjectAnimation a;
    const std::vector<glm::vec3> rest{{0, 0, 0}, {5, 5, 5}};
    const uint32_t v0 = 0;
    setVertexKeys(a, 2, 10, std::span(&v0, 1), std::vector<glm::vec3>{{1, 0, 0}});
    setVertexKeys(a, 2, 20, std::span(&v0, 1), std::vector<glm::vec3>{{3, 0, 0}});
    setVertexKeys(a, 2, 30, std::span(&v0, 1), std::vector<glm::vec3>{{3, 4, 0}});
    ASSERT_TRUE(validateAnimation(a, 2, "test"));
    std::vector<glm::vec3> out(2);
    auto at = [&](double f) {
        evaluatePositions(a.vertexKeys, a.interpolation, rest, f, out);
        return out[0];
    };
    EXPECT_EQ(at(10), glm::vec3(1, 0, 0));
    EXPECT_EQ(at(20), glm::vec3(3, 0, 0));
    EXPECT_EQ(at(15), glm::vec3(2, 0, 0));
    EXPECT_EQ(at(0), glm::vec3(1, 0, 0));    // holds the first key before it
    EXPECT_EQ(at(99), glm::vec3(3, 4, 0));   // and the last after it
    EXPECT_EQ(out[1], rest[1]);              // an unkeyed vertex stays at rest
    // Catmull-Rom passes through the keys too, and is smooth: its tangent at key 20 is the
    // central difference (3 - 1, 4 - 0) / 20 per frame, so just after 20 y has begun to rise.
    a.interpolation = Interpolation::CatmullRom;
    EXPECT_EQ(at(20), glm::vec3(3, 0, 0));
    EXPECT_GT(at(21).y, 0.0f);
    EXPECT_NEAR(at(20.01).y - at(19.99).y, 0.02 * 0.2, 1e-4);
    // Replacing a key at an equal frame keeps one key there.
    setVertexKeys(a, 2, 20, std::span(&v0, 1), std::vector<glm::vec3>{{7, 0, 0}});
    EXPECT_EQ(a.vertexKeys.keyCount(0), 3u);
    EXPECT_EQ(at(20), glm::vec3(7, 0, 0));
    removeVertexKeysAt(a, 20);
    EXPECT_EQ(a.vertexKeys.keyCount(0), 2u);
}

TEST(CageAnimation, TransformKeysInterpolateEachComponent) {
    ObjectAnimation a;
    setTransformKey(a, 0, ObjectTransform{{0, 0, 0}, {0, 0, 0}, {1, 1, 1}});
    setTransformKey(a, 10, ObjectTransform{{10, 0, 0}, {0, 90, 0}, {2, 2, 2}});
    const ObjectTransform mid = evaluateTransform(a, 5, ObjectTransform{});
    EXPECT_EQ(mid.translation, glm::vec3(5, 0, 0));
    EXPECT_EQ(mid.rotationDegrees, glm::vec3(0, 45, 0));
    EXPECT_EQ(mid.scale, glm::vec3(1.5f));
    const ObjectTransform fallback{{1, 2, 3}, {}, {1, 1, 1}};
    EXPECT_EQ(evaluateTransform(ObjectAnimation{}, 5, fallback), fallback);
}

TEST(CageAnimation, RefusalsNameTheVertexAndTheFrame) {
    ObjectAnimation a;
    a.vertexKeys.offsets = {0, 2, 2};
    a.vertexKeys.frames = {5, 5};
    a.vertexKeys.positions = {{0, 0, 0}, {1, 0, 0}};
    Status s = validateAnimation(a, 2, "obj");
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("vertex 0: the key at frame 5 is not after the key at frame 5"), std::string::npos)
        << s.error().message;
    a.vertexKeys.frames = {5, 6};
    a.vertexKeys.positions[1].y = NAN;
    s = validateAnimation(a, 2, "obj");
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("non-finite position at frame 6"), std::string::npos) << s.error().message;
    a.vertexKeys.positions[1].y = 0;
    EXPECT_FALSE(validateAnimation(a, 3, "obj"));  // keys for 2 vertices, cage of 3
    a.transformKeys = {{3, {}}, {2, {}}};
    s = validateAnimation(a, 2, "obj");
    ASSERT_FALSE(s);
    EXPECT_NE(s.error().message.find("transform key at frame 2 is not after the key at frame 3"), std::string::npos);
}

// An edge loop and an extrude at frame 3 of a twisting cube: the edited cage is exactly what the
// frame showed, and at every other frame the new vertices move with the old ones (a loop vertex
// stays on the segment between its edge's ends, for linear interpolation).
TEST(CageAnimation, TopologyEditsApplyToEveryFrame) {
    const Cage cube = test::makeSubdividedCube(2);
    for (Interpolation interpolation : {Interpolation::Linear, Interpolation::CatmullRom}) {
        ObjectAnimation a = twist(cube, {0, 2, 4, 6}, interpolation);
        std::vector<glm::vec3> rest = cube.positions;
        Cage shown = cube;
        shown.positions = positionsAtFrame(a, rest, 3);
        const Topology topology = buildTopology(shown);
        Result<TopologyEdit> loop = insertEdgeLoop(shown, topology, topology.edgeVertices[0], topology.edgeVertices[1], 0.25f);
        ASSERT_TRUE(loop) << loop.error().message;
        ObjectAnimation edited = a;
        std::vector<glm::vec3> editedRest = rest;
        applyTopologyEditToAnimation(edited, editedRest, shown, *loop, 3);
        ASSERT_TRUE(validateAnimation(edited, loop->cage.vertexCount(), "edited"));
        EXPECT_LT(maxDistance(positionsAtFrame(edited, editedRest, 3), loop->cage.positions), 1e-6f);
        for (double f : {0.0, 1.0, 2.0, 5.5, 6.0}) {
            const std::vector<glm::vec3> before = positionsAtFrame(a, rest, f);
            const std::vector<glm::vec3> after = positionsAtFrame(edited, editedRest, f);
            for (uint32_t v = 0; v < loop->cage.vertexCount(); ++v) {
                const uint32_t old = loop->oldVertexOf[v];
                if (old != kNewElement) {
                    EXPECT_EQ(after[v], before[old]) << "kept vertex " << v << " frame " << f;
                } else if (interpolation == Interpolation::Linear) {
                    // On its edge: the distances to the two ends add up to the edge's length.
                    float best = INFINITY;
                    for (uint32_t i = 0; i < loop->cage.vertexCount(); ++i)
                        for (uint32_t j = i + 1; j < loop->cage.vertexCount(); ++j) {
                            if (loop->oldVertexOf[i] == kNewElement || loop->oldVertexOf[j] == kNewElement) continue;
                            best = std::min(best, glm::length(after[v] - after[i]) + glm::length(after[v] - after[j]) -
                                                      glm::length(after[i] - after[j]));
                        }
                    EXPECT_LT(best, 0.03f) << "loop vertex " << v << " frame " << f;
                }
            }
        }
        // Extrude one face by 0.3 at frame 3: each new vertex has one kept neighbour (along its
        // side quad) and keeps its offset from it at every frame.
        const uint32_t face = 0;
        Result<TopologyEdit> extrude = extrudeFaces(shown, topology, std::span(&face, 1), 0.3f);
        ASSERT_TRUE(extrude) << extrude.error().message;
        edited = a;
        editedRest = rest;
        applyTopologyEditToAnimation(edited, editedRest, shown, *extrude, 3);
        EXPECT_LT(maxDistance(positionsAtFrame(edited, editedRest, 3), extrude->cage.positions), 1e-6f);
        const Cage& e = extrude->cage;
        uint32_t checked = 0;
        for (uint32_t f = 0; f < e.faceCount(); ++f)
            for (uint32_t i = e.faceOffsets[f]; i < e.faceOffsets[f + 1]; ++i) {
                const uint32_t next = i + 1 == e.faceOffsets[f + 1] ? e.faceOffsets[f] : i + 1;
                const uint32_t v = e.faceVertices[i], n = e.faceVertices[next];
                if (extrude->oldVertexOf[v] != kNewElement || extrude->oldVertexOf[n] == kNewElement) continue;
                for (double frame : {0.0, 6.0}) {
                    const std::vector<glm::vec3> p = positionsAtFrame(edited, editedRest, frame);
                    EXPECT_LT(glm::length((p[v] - p[n]) - (e.positions[v] - e.positions[n])), 1e-5f)
                        << "new vertex " << v << " frame " << frame;
                }
                ++checked;
            }
        EXPECT_GE(checked, 4u);
    }
}

class AnimatedScene : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("quadplan_animation_" + std::to_string(getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) {
        std::ofstream((dir / name).string()) << text;
        return (dir / name).string();
    }
};

TEST_F(AnimatedScene, KeysAndTimelineRoundTripThroughTheSceneFile) {
    Scene scene = sceneOfCage(test::makeSubdividedCube(2), "cube");
    scene.objects[0].animation = twist(scene.objects[0].cage, {1, 5, 9}, Interpolation::CatmullRom);
    setTransformKey(scene.objects[0].animation, 1, ObjectTransform{});
    setTransformKey(scene.objects[0].animation, 9, ObjectTransform{{1, 2, 3}, {0, 45, 0}, {1, 1, 2}});
    scene.timeline = Timeline{30.0, 1, 9};
    const std::string path = (dir / "animated.json").string();
    ASSERT_TRUE(saveScene(scene, path, CageStorage::Inline));
    std::vector<std::string> warnings;
    Result<Scene> loaded = loadScene(path, &warnings);
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(loaded->objects[0].animation, scene.objects[0].animation);
    EXPECT_EQ(loaded->timeline, scene.timeline);
    EXPECT_TRUE(isAnimated(*loaded));
    EXPECT_EQ(timelineOf(*loaded).lastFrame, 9);
    loaded->timeline.reset();
    EXPECT_EQ(timelineOf(*loaded).firstFrame, 1);  // from the keys
}

TEST_F(AnimatedScene, BadKeysAreRefusedNamingTheKey) {
    const std::string cage = R"("cage": {"positions": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]], "faces": [[0,1,2,3]]})";
    auto scene = [&](const std::string& animation) {
        return R"({"format": "quadplan-scene", "version": 2, "objects": [{"name": "q", )" + cage +
               R"(, "animation": )" + animation + "}]}";
    };
    struct Case {
        const char* animation;
        const char* message;
    } cases[] = {
        {R"({"keys": [{"frame": 5, "vertices": [0], "positions": [[0,0,1]]}, {"frame": 3, "vertices": [0], "positions": [[0,0,2]]}]})",
         "objects[0].animation.keys[1].frame: frame 3 is not after the previous key's frame 5"},
        {R"({"keys": [{"frame": 5, "vertices": [0], "positions": [[0,0,1]]}, {"frame": 5, "vertices": [1], "positions": [[0,0,2]]}]})",
         "keys[1].frame: frame 5 is not after the previous key's frame 5"},
        {R"({"keys": [{"frame": 1, "vertices": [7], "positions": [[0,0,1]]}]})", "vertex index 7 out of range"},
        {R"({"keys": [{"frame": 1, "vertices": [0, 0], "positions": [[0,0,1], [0,0,2]]}]})", "vertex 0 is keyed twice at frame 1"},
        {R"({"keys": [{"frame": 1, "vertices": [0], "positions": [[0,0,1e300]]}]})", "is too large"},
        {R"({"keys": [{"frame": 1, "vertices": [0, 1], "positions": [[0,0,1]]}]})", "1 positions for 2 vertices"},
        {R"({"transform_keys": [{"frame": 2}, {"frame": 1}]})", "frame 1 is not after the previous key's frame 2"},
        {R"({"interpolation": "cubic"})", "unknown value \"cubic\""},
        {R"({"sequence": "missing_*.obj"})", "no file matches the sequence"},
    };
    for (const Case& c : cases) {
        Result<Scene> s = parseScene(scene(c.animation), "bad.json", dir.string());
        ASSERT_FALSE(s) << c.animation;
        EXPECT_NE(s.error().message.find(c.message), std::string::npos) << s.error().message;
    }
}

// A scene naming an OBJ sequence loads every frame as keys, saves the pattern again while the
// keys are unchanged, and refuses a frame with other faces naming it (nothing loaded).
TEST_F(AnimatedScene, SequencesLoadWholeOrNotAtAll) {
    const Cage cube = test::makeSubdividedCube(2);
    ASSERT_TRUE(saveObj(cube, (dir / "rest.obj").string()));
    for (uint32_t k = 1; k <= 4; ++k) {
        Cage frame = cube;
        for (glm::vec3& p : frame.positions) p.x *= 1.0f + float(k) / 10.0f;
        char name[32];
        std::snprintf(name, sizeof name, "walk_%04u.obj", k);
        ASSERT_TRUE(saveObj(frame, (dir / name).string()));
    }
    const std::string text = R"({"format": "quadplan-scene", "version": 2, "objects": [{"name": "c", "cage": {"path": "rest.obj"},
        "animation": {"sequence": "walk_*.obj"}}]})";
    Result<Scene> scene = parseScene(text, "seq.json", dir.string());
    ASSERT_TRUE(scene) << scene.error().message;
    const ObjectAnimation& a = scene->objects[0].animation;
    EXPECT_EQ(a.sequencePattern, (dir / "walk_*.obj").string());  // kept absolute
    EXPECT_EQ(a.vertexKeys.keyCount(0), 4u);
    const std::vector<glm::vec3> at3 = positionsAtFrame(a, scene->objects[0].cage.positions, 3);
    for (size_t v = 0; v < at3.size(); ++v) EXPECT_NEAR(at3[v].x, cube.positions[v].x * 1.3f, 1e-5f);
    // Saved beside the frames it names them as written; saved in another folder it names them
    // from there, and loads from there.
    ASSERT_TRUE(saveScene(*scene, (dir / "again.json").string(), CageStorage::Inline));
    std::ifstream again((dir / "again.json").string());
    EXPECT_NE(std::string(std::istreambuf_iterator<char>(again), {}).find("\"sequence\": \"walk_*.obj\""), std::string::npos);
    fs::create_directories(dir / "elsewhere");
    ASSERT_TRUE(saveScene(*scene, (dir / "elsewhere" / "moved.json").string(), CageStorage::Inline));
    std::ifstream moved((dir / "elsewhere" / "moved.json").string());
    EXPECT_NE(std::string(std::istreambuf_iterator<char>(moved), {}).find("\"sequence\": \"../walk_*.obj\""), std::string::npos);
    Result<Scene> reloaded = loadScene((dir / "elsewhere" / "moved.json").string());
    ASSERT_TRUE(reloaded) << reloaded.error().message;
    EXPECT_EQ(reloaded->objects[0].animation.vertexKeys, a.vertexKeys);

    Cage other = test::makeSubdividedCube(3);
    ASSERT_TRUE(saveObj(other, (dir / "walk_0003.obj").string()));
    Result<Scene> bad = parseScene(text, "seq.json", dir.string());
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("walk_0003.obj"), std::string::npos) << bad.error().message;
    fs::remove(dir / "walk_0003.obj");
    bad = parseScene(text, "seq.json", dir.string());
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("3"), std::string::npos) << bad.error().message;
}

// Playback: every frame is a move, nothing is re-planned, and the planned cage at each frame
// evaluates as the cage planned from scratch at that frame.
TEST(AnimationPlayback, EveryFrameReplansNothingAndEqualsACagePlannedFromScratch) {
    const Cage cube = test::makeSubdividedCube(3);
    const ObjectAnimation a = twist(cube, {1, 3, 5, 8}, Interpolation::CatmullRom);
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(cube, database, {});
    ASSERT_TRUE(planned) << planned.error().message;
    const size_t plansBefore = database.size();
    for (double frame : {1.0, 2.0, 3.5, 8.0, 4.0, 1.0}) {
        Result<EditReport> report = showFrame(*planned, a, cube.positions, frame);
        ASSERT_TRUE(report) << report.error().message;
        EXPECT_EQ(report->replannedFaces, 0u);
        EXPECT_EQ(report->newPlans, 0u);
        Cage fresh = cube;
        fresh.positions = positionsAtFrame(a, cube.positions, frame);
        PlanDatabase freshDatabase;
        Result<PlannedCage> scratch = PlannedCage::create(fresh, freshDatabase, {});
        ASSERT_TRUE(scratch);
        ASSERT_EQ(planned->subfaceCount(), scratch->subfaceCount());
        for (uint32_t s = 0; s < planned->subfaceCount(); ++s)
            for (float u : {0.0f, 0.37f, 1.0f}) {
                const LimitSample x = planned->evaluate(s, u, 0.61f), y = scratch->evaluate(s, u, 0.61f);
                EXPECT_LT(glm::length(x.position - y.position), 1e-5f) << "frame " << frame << " sub-face " << s;
            }
    }
    EXPECT_EQ(database.size(), plansBefore);
}

// The history entries of core/animation/animation_edits.h: a move at a frame keys it, a topology edit
// carries the keys, and undo and redo give back keys, rest and positions at the frame shown.
TEST(AnimationEdits, KeyedMovesAndTopologyEditsUndoAndRedoWithTheirKeys) {
    const Cage cube = test::makeSubdividedCube(2);
    ObjectAnimation animation = twist(cube, {0, 4}, Interpolation::Linear);
    std::vector<glm::vec3> rest = cube.positions;
    double frame = 2.0;
    AnimationAccess access = [&] { return AnimatedCageState{&animation, &rest, frame}; };
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(cube, database, {});
    ASSERT_TRUE(planned);
    ASSERT_TRUE(showFrame(*planned, animation, rest, frame));
    EditHistory history;

    const ObjectAnimation original = animation;
    const uint32_t vertex = 5;
    const glm::vec3 target = planned->cage().positions[vertex] + glm::vec3(0, 0.5f, 0);
    ASSERT_TRUE(history.perform(*planned, "key", makeKeyedMove(access(), access, 2, std::span(&vertex, 1), std::span(&target, 1))));
    EXPECT_EQ(planned->cage().positions[vertex], target);
    EXPECT_EQ(animation.vertexKeys.keyCount(vertex), 3u);
    frame = 4.0;  // the entry is undone at another frame: positions follow the keys there
    ASSERT_TRUE(history.undo(*planned));
    EXPECT_EQ(animation, original);
    EXPECT_EQ(planned->cage().positions, positionsAtFrame(original, rest, 4.0));
    ASSERT_TRUE(history.redo(*planned));
    EXPECT_EQ(animation.vertexKeys.keyCount(vertex), 3u);
    const ObjectAnimation keyed = animation;

    const Topology topology = buildTopology(planned->cage());
    const uint32_t face = 3;
    Result<TopologyEdit> extrude = extrudeFaces(planned->cage(), topology, std::span(&face, 1), 0.2f);
    ASSERT_TRUE(extrude);
    const std::vector<glm::vec3> restBefore = rest;
    Result<EditReport> report =
        history.perform(*planned, "extrude", makeAnimatedTopologyEdit(*planned, access(), access, *extrude));
    ASSERT_TRUE(report) << report.error().message;
    EXPECT_EQ(planned->cage().vertexCount(), extrude->cage.vertexCount());
    EXPECT_EQ(rest.size(), extrude->cage.vertexCount());
    EXPECT_LT(maxDistance(planned->cage().positions, extrude->cage.positions), 1e-6f);
    EXPECT_TRUE(planned->differencesFromRebuild().empty());
    frame = 0.0;
    ASSERT_TRUE(history.undo(*planned));
    EXPECT_EQ(animation, keyed);
    EXPECT_EQ(rest, restBefore);
    EXPECT_EQ(planned->cage().positions, positionsAtFrame(keyed, rest, 0.0));
    ASSERT_TRUE(history.redo(*planned));
    EXPECT_EQ(rest.size(), extrude->cage.vertexCount());
    EXPECT_EQ(planned->cage().positions, positionsAtFrame(animation, rest, 0.0));
    EXPECT_TRUE(planned->differencesFromRebuild().empty());

    ASSERT_TRUE(history.perform(*planned, "unkey", makeKeyRemoval(access(), access, 4)));
    EXPECT_EQ(keyedFrames(animation), std::vector<int32_t>({0, 2}));  // the extrude was made at frame 4
}
