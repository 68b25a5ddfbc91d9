// The editor document's sculpting mask (document.h): mask strokes touch the mask only, invert
// and clear are one history entry each, and the displaced-surface picker of the pick cache
// follows dabs by re-displacing only the sub-faces they reached.
#include <gtest/gtest.h>

#include <algorithm>

#include "document.h"
#include "pick_cache.h"
#include "test_cages.h"

using namespace qp;
using namespace qp::editor;

namespace {

std::unique_ptr<Document> cubeDocument() {
    Scene scene = sceneOfCage(test::makeSubdividedCube(2), "cage");
    Result<std::unique_ptr<Document>> doc = createDocument(scene, "", PlanOptions{});
    EXPECT_TRUE(doc.ok()) << doc.error().message;
    return doc ? std::move(doc).value() : nullptr;
}

uint32_t maskedCount(const Document& doc) {
    const std::vector<float>& mask = doc.scene.objects[0].displacement.mask;
    return uint32_t(std::count_if(mask.begin(), mask.end(), [](float m) { return m > 0.0f; }));
}

}  // namespace

TEST(DocumentMask, MaskStrokesInvertAndClearAreOneEntryEachAndLeaveDAlone) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    EXPECT_FALSE(invertSculptMask(*doc, 1).ok()) << "no displacement to hold a mask";
    EXPECT_EQ(doc->history.size(), 0u);

    const glm::vec3 centre = doc->planned->evaluate(0, 0.5f, 0.5f).position;
    ASSERT_TRUE(beginStroke(*doc, 8, 1).ok());
    StrokeOptions mask;
    mask.brush = Brush{BrushKind::Mask, 0.3f, 1.0f, Falloff::Constant};
    const uint64_t samples = doc->sampleRevision, masks = doc->maskRevision;
    EXPECT_GT(strokeTo(*doc, mask, centre), 0u);
    EXPECT_EQ(doc->sampleRevision, samples) << "a mask dab told the renderer D changed";
    EXPECT_GT(doc->maskRevision, masks);
    ASSERT_TRUE(endStroke(*doc, "Mask stroke", 2).ok());
    ASSERT_EQ(doc->history.size(), 1u);
    const uint32_t painted = maskedCount(*doc);
    EXPECT_GT(painted, 0u);
    const std::vector<float> zeros(doc->scene.objects[0].displacement.samples.size(), 0.0f);
    EXPECT_EQ(doc->scene.objects[0].displacement.samples, zeros);

    const uint32_t total = uint32_t(zeros.size());
    Result<EditReport> inverted = invertSculptMask(*doc, 3);
    ASSERT_TRUE(inverted.ok()) << inverted.error().message;
    ASSERT_EQ(doc->history.size(), 2u);
    EXPECT_EQ(doc->history.entry(1).name, "Invert mask");
    EXPECT_EQ(maskedCount(*doc), total - painted);
    ASSERT_TRUE(clearSculptMask(*doc, 4).ok());
    ASSERT_EQ(doc->history.size(), 3u);
    EXPECT_EQ(maskedCount(*doc), 0u);
    ASSERT_TRUE(clearSculptMask(*doc, 5).ok());
    EXPECT_EQ(doc->history.size(), 3u) << "clearing an empty mask made an entry";
    ASSERT_TRUE(undoEdit(*doc, 6).ok());
    EXPECT_EQ(maskedCount(*doc), total - painted);
    ASSERT_TRUE(undoEdit(*doc, 7).ok());
    EXPECT_EQ(maskedCount(*doc), painted);
}

TEST(DocumentMask, TheDisplacedPickerFollowsDabsAsARebuildWould) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    PickCache cache;
    const glm::vec3 centre = doc->planned->evaluate(0, 0.4f, 0.5f).position;
    const glm::vec3 normal = glm::normalize(centre);
    // The picker answers as one built from the document now would.
    auto expectRebuilt = [&](const char* when) {
        const DisplacedPicker& updated = displacedPicker(cache, *doc, 1);
        const DisplacedPicker rebuilt(*doc->planned, displacementOf(*doc));
        for (float offset : {-0.3f, -0.1f, 0.0f, 0.15f, 0.3f}) {
            const Ray ray{centre + 5.0f * normal + glm::vec3(offset, 0.1f, 0.0f), -normal};
            const DisplacedPicker::Hit a = updated.intersect(*doc->planned, displacementOf(*doc), ray);
            const DisplacedPicker::Hit b = rebuilt.intersect(*doc->planned, displacementOf(*doc), ray);
            ASSERT_NE(a.subface, kNoHit) << when;
            EXPECT_EQ(a.subface, b.subface) << when;
            EXPECT_EQ(a.distance, b.distance) << when;
        }
    };
    StrokeOptions raise;
    raise.brush = Brush{BrushKind::Raise, 0.3f, 1.0f, Falloff::Smooth};
    // A first stroke makes the displacement (a new layout: the picker is built for it), the
    // second changes it in place.
    ASSERT_TRUE(beginStroke(*doc, 8, 1).ok());
    strokeDab(*doc, raise, centre - glm::vec3(0.1f));
    ASSERT_TRUE(endStroke(*doc, "First stroke", 1).ok());
    ASSERT_TRUE(beginStroke(*doc, 8, 1).ok());
    displacedPicker(cache, *doc, 1);  // built before the dabs
    const uint32_t builds = cache.displacedBuilds;
    for (int k = 0; k < 4; ++k) {
        strokeDab(*doc, raise, centre + glm::vec3(0.05f * float(k)));
        // The renderer takes the samples before the picker sees them (odd dabs) or after.
        if (k % 2 == 1) takeUnsyncedSamples(*doc);
        const DisplacedPicker& picker = displacedPicker(cache, *doc, 1);
        EXPECT_GT(picker.lastUpdated().size(), 0u);
        EXPECT_LT(picker.lastUpdated().size(), doc->planned->subfaceCount() / 2) << "a dab re-sampled most of the cube";
        if (k % 2 == 0) takeUnsyncedSamples(*doc);
    }
    ASSERT_TRUE(endStroke(*doc, "Raise stroke", 2).ok());
    expectRebuilt("after the stroke");
    const DisplacedPicker::Hit top = displacedPicker(cache, *doc, 1).intersect(*doc->planned, displacementOf(*doc),
                                                                                Ray{centre + 5.0f * normal, -normal});
    EXPECT_GT(glm::length(top.position - top.limit), 0.01f) << "the pick is not on the raised surface";
    // Undo and redo list the stroke's samples as dabs do.
    ASSERT_TRUE(undoEdit(*doc, 3).ok());
    takeUnsyncedSamples(*doc);
    expectRebuilt("after undo");
    ASSERT_TRUE(redoEdit(*doc, 4).ok());
    expectRebuilt("after redo");
    EXPECT_EQ(cache.displacedBuilds, builds) << "dabs, undo or redo rebuilt the picker";
}

TEST(DocumentSculpt, TopologyEditsKeepTheSculptAndUndoBringsItBack) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    const glm::vec3 centre = doc->planned->evaluate(0, 0.5f, 0.5f).position;
    ASSERT_TRUE(beginStroke(*doc, 8, 1).ok());
    StrokeOptions raise;
    raise.brush = Brush{BrushKind::Raise, 0.6f, 0.3f, Falloff::Smooth};
    EXPECT_GT(strokeTo(*doc, raise, centre), 0u);
    ASSERT_TRUE(endStroke(*doc, "Stroke", 2).ok());
    StrokeOptions mask;
    mask.brush = Brush{BrushKind::Mask, 0.3f, 1.0f, Falloff::Constant};
    ASSERT_TRUE(beginStroke(*doc, 8, 3).ok());
    EXPECT_GT(strokeTo(*doc, mask, centre), 0u);
    ASSERT_TRUE(endStroke(*doc, "Mask stroke", 4).ok());
    const Displacement sculpted = doc->scene.objects[0].displacement;
    const float top = *std::max_element(sculpted.samples.begin(), sculpted.samples.end());
    ASSERT_GT(top, 0.0f);
    const size_t entries = doc->history.size();

    // Extrude the sculpted face out: one entry; the displacement fits the new cage, its bump
    // went along with the face and its mask with it.
    const uint64_t revision = doc->displacementRevision;
    Result<EditReport> extruded = applyEdit(*doc, ExtrudeFaces{{0}, 0.4f}, 5);
    ASSERT_TRUE(extruded.ok()) << extruded.error().message;
    EXPECT_EQ(doc->history.size(), entries + 1);
    EXPECT_GT(doc->displacementRevision, revision) << "the renderer was not told of the new layout";
    const Displacement& carried = doc->scene.objects[0].displacement;
    EXPECT_EQ(carried.layout, buildDisplacementLayout(doc->planned->cage(), doc->planned->topology(), 8));
    // (The in-place extrude sharpens the face's rim, which tilts the surface at its centre a
    // little: the centre's normal meets the old surface a little off the old centre.)
    EXPECT_NEAR(evaluateDisplacement(carried, 0, 0.5f, 0.5f).value, evaluateDisplacement(sculpted, 0, 0.5f, 0.5f).value,
                0.05f * top);
    ASSERT_EQ(carried.mask.size(), carried.samples.size());
    EXPECT_GT(*std::max_element(carried.mask.begin(), carried.mask.end()), 0.5f);

    // Not while a stroke is in progress: its record belongs to the layout the edit replaces.
    ASSERT_TRUE(beginStroke(*doc, 8, 6).ok());
    Result<EditReport> during = applyEdit(*doc, DeleteFaces{{1}}, 6);
    ASSERT_FALSE(during.ok());
    EXPECT_NE(during.error().message.find("finish the stroke"), std::string::npos) << during.error().message;
    cancelStroke(*doc);

    // Delete a face next to it, then undo both: the sculpt comes back bit for bit.
    ASSERT_TRUE(applyEdit(*doc, DeleteFaces{{1}}, 6).ok());
    EXPECT_EQ(doc->scene.objects[0].displacement.layout,
              buildDisplacementLayout(doc->planned->cage(), doc->planned->topology(), 8));
    ASSERT_TRUE(undoEdit(*doc, 7).ok());
    ASSERT_TRUE(undoEdit(*doc, 8).ok());
    EXPECT_EQ(doc->scene.objects[0].displacement, sculpted);
    EXPECT_TRUE(doc->planned->differencesFromRebuild().empty());
    ASSERT_TRUE(redoEdit(*doc, 9).ok());
    EXPECT_EQ(doc->scene.objects[0].displacement.layout,
              buildDisplacementLayout(doc->planned->cage(), doc->planned->topology(), 8));
}
