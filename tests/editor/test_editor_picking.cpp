// The editor's pick cache (editor/app/pick_cache.h) after edits: the limit picker follows tag,
// hole and topology edits without being built again, and hits what a fresh one hits.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "document.h"
#include "pick_cache.h"
#include "test_cages.h"

using namespace qp;
using namespace qp::editor;

namespace {

std::unique_ptr<Document> cubeDocument(uint32_t n) {
    Result<std::unique_ptr<Document>> doc = createDocument(sceneOfCage(test::makeSubdividedCube(n), "cage"), "", PlanOptions{});
    EXPECT_TRUE(doc.ok()) << doc.error().message;
    return doc ? std::move(doc).value() : nullptr;
}

// `count` rays from all around the cage toward its centre, spread by fixed angles.
std::vector<Ray> raysFromAround(const Cage& cage, int count) {
    const Bounds bounds = computeBounds(cage);
    const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        const glm::vec3 direction = glm::normalize(glm::vec3(std::cos(0.7f * i), std::sin(1.3f * i), std::cos(0.3f * i + 1.0f)));
        rays.push_back({centre + 3.0f * bounds.diagonal() * direction, -direction});
    }
    return rays;
}

// The same sub-face and point from both pickers along every ray; returns the rays that hit.
int expectSameHits(const LimitPicker& updated, const LimitPicker& fresh, const PlannedCage& planned, std::span<const Ray> rays) {
    int hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const LimitPicker::Hit x = updated.intersect(planned, rays[i]), y = fresh.intersect(planned, rays[i]);
        EXPECT_EQ(x.subface, y.subface) << "ray " << i;
        EXPECT_EQ(x.position, y.position) << "ray " << i;
        hits += x.subface != kNoHit;
    }
    return hits;
}

}  // namespace

TEST(Document, PickingFollowsTagEditsWithoutARebuild) {
    std::unique_ptr<Document> doc = cubeDocument(2);
    ASSERT_TRUE(doc);
    PickCache cache;
    (void)limitPicker(cache, *doc, 1);
    EXPECT_EQ(cache.limitBuilds, 1u);
    const Cage& cage = doc->planned->cage();
    const uint32_t a = cage.faceBegin(0)[0], b = cage.faceBegin(0)[1];
    ASSERT_TRUE(applyEdit(*doc, SetEdgeSharpness{{{a, b, 5.0f}}}, 1).ok());
    ASSERT_TRUE(applyEdit(*doc, SetHoles{{1}, true}, 2).ok());
    const EditReport change = takeUnsyncedPlanChange(*doc);
    EXPECT_FALSE(change.topologyChanged);
    EXPECT_FALSE(change.replannedFaceList.empty());
    EXPECT_TRUE(takeUnsyncedPlanChange(*doc).replannedFaceList.empty()) << "taken once";
    const LimitPicker& updated = limitPicker(cache, *doc, 1);
    EXPECT_EQ(cache.limitBuilds, 1u) << "a tag edit rebuilt the picker";
    const LimitPicker fresh(*doc->planned);
    EXPECT_GT(expectSameHits(updated, fresh, *doc->planned, raysFromAround(cage, 64)), 32);
}

// A hole changes no plan (holes are planned as if they were not), only whether the sub-faces
// have a surface: the limit picker must stop hitting it all the same.
TEST(Document, PickingFollowsAHoleAlone) {
    std::unique_ptr<Document> doc = cubeDocument(2);
    ASSERT_TRUE(doc);
    PickCache cache;
    (void)limitPicker(cache, *doc, 1);
    ASSERT_TRUE(applyEdit(*doc, SetHoles{{5}, true}, 1).ok());
    const LimitPicker& updated = limitPicker(cache, *doc, 1);
    EXPECT_EQ(cache.limitBuilds, 1u);
    const LimitPicker fresh(*doc->planned);
    const Bounds bounds = computeBounds(doc->planned->cage());
    const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
    const std::vector<Ray> rays = raysFromAround(doc->planned->cage(), 256);
    int throughHole = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const LimitPicker::Hit x = updated.intersect(*doc->planned, rays[i]), y = fresh.intersect(*doc->planned, rays[i]);
        EXPECT_EQ(x.subface, y.subface) << "ray " << i;
        const bool onHoleFace = x.subface >= doc->planned->firstSubface(5) && x.subface < doc->planned->firstSubface(6);
        EXPECT_FALSE(x.subface != kNoHit && onHoleFace) << "ray " << i << " hit the hole";
        throughHole += y.subface != kNoHit && glm::dot(y.position - centre, -rays[i].direction) < 0.0f;  // the far side
    }
    EXPECT_GT(throughHole, 0) << "no ray went through the hole";
}

// After topology edits the renderer tells the pick cache about (noteTopologyChange), the limit
// picker keeps its kept sub-faces' samples and re-samples the new ones, the re-planned ones and
// those whose ring moved before the edit (a move it had not seen, a hole it had not sampled):
// no rebuild, and the same hits as a picker built afresh. Without the note it is built again.
TEST(Document, PickingFollowsTopologyEditsWithoutARebuild) {
    std::unique_ptr<Document> created = cubeDocument(6);
    ASSERT_TRUE(created);
    Document& doc = *created;
    PickCache cache;
    (void)limitPicker(cache, doc, 1);
    ASSERT_EQ(cache.limitBuilds, 1u);
    const Cage& cage = doc.planned->cage();
    auto centroid = [&](uint32_t f) {
        glm::vec3 sum(0.0f);
        for (uint32_t i = 0; i < cage.faceSize(f); ++i) sum += cage.positions[cage.faceBegin(f)[i]];
        return sum / float(cage.faceSize(f));
    };
    // Unseen by the limit picker before the topology edits, on one side of the cube: a hole
    // (taken as re-planned by the cage raycaster's sync, not sampled: a stale picker still hits
    // it) and a move; the topology edits are on the far corner.
    const glm::vec3 holeAt = centroid(0), movedAt = centroid(14);
    ASSERT_TRUE(applyEdit(doc, SetHoles{{0}, true}, 1).ok());
    (void)cageRaycaster(cache, doc, 1);
    ASSERT_FALSE(cache.replanned.empty());
    const uint32_t v = cage.faceBegin(14)[0];
    ASSERT_TRUE(applyEdit(doc, MoveVertices{{v}, {cage.positions[v] * 1.3f}}, 2).ok());
    noteTopologyChange(cache, doc, takeUnsyncedPlanChange(doc));
    // Two topology edits, each told of in its own frame, then a pick.
    const uint32_t last = cage.faceCount() - 1;
    ASSERT_TRUE(applyEdit(doc, ExtrudeFaces{{last}, 0.4f}, 3).ok());
    noteTopologyChange(cache, doc, takeUnsyncedPlanChange(doc));
    ASSERT_TRUE(applyEdit(doc, DeleteFaces{{last - 2}}, 4).ok());
    noteTopologyChange(cache, doc, takeUnsyncedPlanChange(doc));
    const LimitPicker& carried = limitPicker(cache, doc, 1);
    EXPECT_EQ(cache.limitBuilds, 1u) << "the picker was built again after topology edits it was told of";

    // Rays at the hole, at the moved vertex's faces and from all around: the hits of a picker
    // built afresh.
    const LimitPicker fresh(*doc.planned);
    const Bounds bounds = computeBounds(cage);
    const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
    std::vector<Ray> rays;
    for (const glm::vec3& target : {holeAt, movedAt})
        for (int i = 0; i < 16; ++i) {
            const glm::vec3 jitter = 0.03f * bounds.diagonal() * glm::vec3(std::cos(1.7f * i), std::sin(2.3f * i), std::cos(0.9f * i));
            const glm::vec3 from = centre + 2.0f * (target - centre) + jitter;
            rays.push_back({from, glm::normalize(target - from)});
        }
    const std::vector<Ray> around = raysFromAround(cage, 64);
    rays.insert(rays.end(), around.begin(), around.end());
    EXPECT_GT(expectSameHits(carried, fresh, *doc.planned, rays), 64);

    // An edit the cache was not told of: built again.
    ASSERT_TRUE(applyEdit(doc, ExtrudeFaces{{2}, 0.2f}, 5).ok());
    (void)limitPicker(cache, doc, 1);
    EXPECT_EQ(cache.limitBuilds, 2u);
}
