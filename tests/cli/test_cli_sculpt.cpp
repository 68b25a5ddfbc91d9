// `quadplan sculpt`: headless strokes reproduce the library's result bit for bit, stroke files
// and --path agree, and bad input is refused with a message.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <sys/wait.h>
#include <unistd.h>

#include "cli_run.h"
#include "displacement/brush.h"
#include "displacement/sculpt_samples.h"
#include "plans/planned_cage.h"
#include "scene/scene.h"

#define STBI_ONLY_PNG
#include <stb/stb_image.h>

namespace fs = std::filesystem;

namespace {

using qp::test::CommandRun;

CommandRun runQuadplan(const std::string& args) { return qp::test::runQuadplan(args, true); }

std::string temp(const std::string& name) {
    return (fs::temp_directory_path() / ("quadplan-sculpt-" + std::to_string(::getpid()) + "-" + name)).string();
}

const std::string kScene = std::string(QUADPLAN_SCENES_DIR) + "/creased_box.json";

}  // namespace

TEST(CliSculpt, PathStrokeMatchesTheLibraryBitForBit) {
    const std::string out = temp("path.json");
    CommandRun run = runQuadplan("sculpt " + kScene + " --brush raise --radius 0.6 --strength 0.05 --falloff sphere "
                                 "--mirror x --resolution 16 --path \"0.2,1.2,0.3;0.9,1.1,-0.4\" --out " + out);
    ASSERT_EQ(run.status, 0) << run.out;
    EXPECT_NE(run.out.find("sculpt: 1 stroke"), std::string::npos) << run.out;
    qp::Result<qp::Scene> written = qp::loadScene(out);
    ASSERT_TRUE(written) << written.error().message;

    // The same stroke through the library.
    qp::Result<qp::Scene> scene = qp::loadScene(kScene);
    ASSERT_TRUE(scene);
    qp::PlanDatabase database;
    qp::Result<qp::PlannedCage> planned = qp::PlannedCage::create(scene->objects[0].cage, database, qp::PlanOptions{});
    ASSERT_TRUE(planned);
    qp::Displacement d = qp::makeDisplacement(scene->objects[0].cage, planned->topology(), 16);
    qp::SculptSamples samples = qp::SculptSamples::build(*planned, d.layout);
    qp::StrokeOptions options{{qp::BrushKind::Raise, 0.6f, 0.05f, qp::Falloff::Sphere}, qp::MirrorAxis::X};
    std::vector<glm::vec3> path = {{0.2f, 1.2f, 0.3f}, {0.9f, 1.1f, -0.4f}};
    qp::StrokeRecord record = qp::applyStroke(d, samples, options, path);
    ASSERT_GT(record.changes.size(), 20u);
    ASSERT_EQ(written->objects[0].displacement.layout, d.layout);
    for (size_t i = 0; i < d.samples.size(); ++i)
        ASSERT_EQ(std::bit_cast<uint32_t>(written->objects[0].displacement.samples[i]), std::bit_cast<uint32_t>(d.samples[i])) << i;
    fs::remove(out);
}

TEST(CliSculpt, StrokeFileContinuesASculptedScene) {
    const std::string first = temp("first.json"), second = temp("second.json"), viaPath = temp("via-path.json");
    ASSERT_EQ(runQuadplan("sculpt " + kScene + " --radius 0.5 --strength 0.1 --path \"0,1.2,0\" --out " + first).status, 0);
    const std::string strokes = temp("strokes.json");
    std::ofstream(strokes) << R"({"strokes": [
        {"brush": "smooth", "radius": 0.8, "strength": 0.5, "path": [[0, 1.2, 0], [0.3, 1.2, 0.3]]}]})";
    CommandRun run = runQuadplan("sculpt " + first + " --strokes " + strokes + " --out " + second);
    ASSERT_EQ(run.status, 0) << run.out;
    run = runQuadplan("sculpt " + first + " --brush smooth --radius 0.8 --strength 0.5 --path \"0,1.2,0;0.3,1.2,0.3\" --out " +
                      viaPath);
    ASSERT_EQ(run.status, 0) << run.out;
    qp::Result<qp::Scene> a = qp::loadScene(second), b = qp::loadScene(viaPath), before = qp::loadScene(first);
    ASSERT_TRUE(a && b && before);
    EXPECT_EQ(a->objects[0].displacement, b->objects[0].displacement);
    EXPECT_NE(a->objects[0].displacement, before->objects[0].displacement);  // the smooth stroke changed something
    for (const std::string& f : {first, second, viaPath, strokes}) fs::remove(f);
}

// Mask strokes and whole-mask steps in a stroke file run in order: a mask painted, inverted, a
// raise stroke over everything changes only what the inverted mask leaves free; --clear-mask
// alone clears it.
TEST(CliSculpt, MaskStepsRunInOrderAndHoldTheirSamples) {
    const std::string masked = temp("masked.json"), cleared = temp("cleared.json"), strokes = temp("mask-strokes.json");
    std::ofstream(strokes) << R"({"strokes": [
        {"brush": "mask", "radius": 0.5, "strength": 1, "falloff": "constant", "path": [[0, 1.2, 0]]},
        {"mask": "invert"},
        {"brush": "raise", "radius": 3, "strength": 0.05, "path": [[0, 1.2, 0]]}]})";
    CommandRun run = runQuadplan("sculpt " + kScene + " --strokes " + strokes + " --out " + masked);
    ASSERT_EQ(run.status, 0) << run.out;
    EXPECT_NE(run.out.find("sculpt: 2 strokes and 1 mask step"), std::string::npos) << run.out;
    qp::Result<qp::Scene> scene = qp::loadScene(masked);
    ASSERT_TRUE(scene) << scene.error().message;
    const qp::Displacement& d = scene->objects[0].displacement;
    ASSERT_EQ(d.mask.size(), d.samples.size());
    uint32_t free = 0, held = 0;
    for (size_t i = 0; i < d.samples.size(); ++i) {
        if (d.mask[i] == 1.0f) {
            EXPECT_EQ(d.samples[i], 0.0f) << "masked sample " << i << " changed";
            ++held;
        }
        if (d.mask[i] == 0.0f && d.samples[i] > 0.0f) ++free;
    }
    EXPECT_GT(held, 0u);
    EXPECT_GT(free, 0u);

    run = runQuadplan("sculpt " + masked + " --clear-mask --out " + cleared);
    ASSERT_EQ(run.status, 0) << run.out;
    qp::Result<qp::Scene> after = qp::loadScene(cleared);
    ASSERT_TRUE(after) << after.error().message;
    EXPECT_EQ(after->objects[0].displacement.samples, d.samples);
    EXPECT_FALSE(after->objects[0].displacement.hasMask() &&
                 *std::max_element(after->objects[0].displacement.mask.begin(), after->objects[0].displacement.mask.end()) > 0.0f);
    for (const std::string& f : {masked, cleared, strokes}) fs::remove(f);
}

TEST(CliSculpt, BadInputIsRefusedWithAMessage) {
    const std::string out = temp("bad.json");
    struct Case {
        std::string args, message;
    };
    const std::string strokes = temp("bad-strokes.json");
    std::ofstream(strokes) << R"({"strokes": [{"brush": "raise", "radius": -1, "strength": 0.1, "path": [[0, 0, 0]]}]})";
    const std::string badStep = temp("bad-step.json");
    std::ofstream(badStep) << R"({"strokes": [{"mask": "flip"}]})";
    const Case cases[] = {
        {"--radius 0.5 --strength 0.1 --path \"0,1\"", "--path: point 1 (\"0,1\") needs three numbers separated by commas"},
        {"--brush pinch --radius 0.5 --strength 0.1 --path \"0,1,0\"", "--brush: unknown brush \"pinch\""},
        {"--brush erase --radius 0.5 --strength 3 --path \"0,1,0\"", "its strength must be between 0 and 1, got 3"},
        {"--radius 0.5 --strength 0.1 --path \"0,1,0\" --resolution 12", "--resolution must be a power of two"},
        {"--radius 0.5 --strength 0.1", "nothing to sculpt"},
        {"--strokes " + strokes, "strokes[0]: brush radius must be a positive number, got -1"},
        {"--strokes " + badStep, "strokes[0].mask: unknown value \"flip\"; expected \"invert\" or \"clear\""},
    };
    for (const Case& c : cases) {
        CommandRun run = runQuadplan("sculpt " + kScene + " " + c.args + " --out " + out);
        EXPECT_EQ(run.status, 1) << c.args;
        EXPECT_NE(run.out.find(c.message), std::string::npos) << c.args << "\n" << run.out;
        EXPECT_FALSE(fs::exists(out)) << c.args;
    }
    fs::remove(strokes);
    fs::remove(badStep);
}

// The --png preview shows the displacement: a raised stroke changes the picture, only near it.
TEST(CliSculpt, PreviewShowsTheStroke) {
    const std::string flat = temp("flat.png"), raised = temp("raised.png"), out = temp("preview.json");
    const std::string common = "sculpt " + kScene + " --radius 0.6 --resolution 8 --path \"0.2,0.8,0.2\" --validate --out " + out;
    CommandRun a = runQuadplan(common + " --strength 0 --png " + flat);
    ASSERT_EQ(a.status, 0) << a.out;
    CommandRun b = runQuadplan(common + " --strength 0.1 --png " + raised);
    ASSERT_EQ(b.status, 0) << b.out;
    EXPECT_EQ(b.out.find("validation:"), std::string::npos) << b.out;
    int w = 0, h = 0, n = 0, w2 = 0, h2 = 0;
    unsigned char* p = stbi_load(flat.c_str(), &w, &h, &n, 4);
    unsigned char* q = stbi_load(raised.c_str(), &w2, &h2, &n, 4);
    ASSERT_TRUE(p && q);
    ASSERT_EQ(w, 768);
    ASSERT_EQ(w, w2);
    ASSERT_EQ(h, h2);
    size_t differing = 0, covered = 0;
    for (size_t i = 0; i < size_t(w) * h; ++i) {
        differing += std::abs(int(p[4 * i]) - int(q[4 * i])) > 8;
        covered += p[4 * i] > 40;  // the lit surface against the dark background
    }
    stbi_image_free(p);
    stbi_image_free(q);
    EXPECT_GT(covered, size_t(w) * h / 10);
    EXPECT_GT(differing, 300u);
    EXPECT_LT(differing, covered / 2);
    for (const std::string& f : {flat, raised, out}) fs::remove(f);
}
