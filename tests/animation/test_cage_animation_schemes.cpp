// Playing an animation through every scheme plugin: each frame is a vertex move that the scheme
// instance takes as such (updateMoved), and what it then evaluates equals an instance built from
// scratch on the cage loaded at that frame (issue 22: "every frame equals a cage loaded from
// scratch at that frame, positions of every scheme").
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "animation/animation_playback.h"
#include "mesh/topology.h"
#include "scheme_loader.h"
#include "test_cages.h"

using namespace qp;

namespace {

// Every vertex keyed at frames 1 and 9: a bend about z growing with x.
ObjectAnimation bend(const Cage& cage) {
    ObjectAnimation a;
    a.interpolation = Interpolation::CatmullRom;
    std::vector<uint32_t> all(cage.positions.size());
    for (uint32_t v = 0; v < all.size(); ++v) all[v] = v;
    setVertexKeys(a, uint32_t(all.size()), 1, all, cage.positions);
    std::vector<glm::vec3> bent = cage.positions;
    for (glm::vec3& p : bent) p += glm::vec3(0.0f, 0.4f * p.x * p.x, 0.2f * p.x);
    setVertexKeys(a, uint32_t(all.size()), 9, all, bent);
    setVertexKeys(a, uint32_t(all.size()), 17, all, cage.positions);
    return a;
}

std::vector<SampleRequest> samplesOf(const PlannedCage& planned) {
    std::vector<SampleRequest> requests;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s)
        for (float u : {0.0f, 0.3f, 1.0f})
            for (float v : {0.0f, 0.55f, 1.0f}) requests.push_back({s, u, v});
    return requests;
}

}  // namespace

TEST(AnimationSchemes, EveryFrameOfEverySchemeEqualsAnInstanceBuiltAtThatFrame) {
    const PluginCatalog catalog = loadPlugins(QUADPLAN_PLUGIN_DIR);
    ASSERT_GE(catalog.plugins.size(), 7u) << catalog.names();
    Cage cage = test::makeSubdividedCube(3);
    cage.creases.push_back({cage.faceBegin(0)[0], cage.faceBegin(0)[1], 2.5f});  // a semi-sharp crease in play
    const ObjectAnimation animation = bend(cage);
    const SchemeSettings settings;
    uint32_t tested = 0;
    for (const std::shared_ptr<SchemePlugin>& plugin : catalog.plugins) {
        SCOPED_TRACE(plugin->name);
        PlanDatabase database;
        Result<PlannedCage> planned = PlannedCage::create(cage, database, {});
        ASSERT_TRUE(planned);
        Result<SchemeInstance> instance = SchemeInstance::create(plugin);
        ASSERT_TRUE(instance) << instance.error().message;
        Result<SupportReport> support = instance->support(analyzeCage(cage, buildTopology(cage)), settings);
        ASSERT_TRUE(support);
        if (!support->usable()) continue;  // counted below: most schemes must take this cage
        ASSERT_TRUE(instance->build(*planned, settings)) << plugin->name;
        ASSERT_TRUE(instance->update());
        const std::vector<SampleRequest> requests = samplesOf(*planned);
        for (double frame : {5.0, 9.0, 12.5}) {
            const std::vector<glm::vec3> before = planned->cage().positions;
            Result<EditReport> shown = showFrame(*planned, animation, cage.positions, frame);
            ASSERT_TRUE(shown);
            EXPECT_EQ(shown->replannedFaces, 0u);
            std::vector<uint32_t> moved;
            for (uint32_t v = 0; v < before.size(); ++v)
                if (before[v] != planned->cage().positions[v]) moved.push_back(v);
            ASSERT_TRUE(instance->updateMoved(moved));
            std::vector<SurfacePoint> played(requests.size());
            ASSERT_TRUE(instance->evaluate(requests, played));

            Cage atFrame = cage;
            atFrame.positions = positionsAtFrame(animation, cage.positions, frame);
            PlanDatabase freshDatabase;
            Result<PlannedCage> fresh = PlannedCage::create(atFrame, freshDatabase, {});
            ASSERT_TRUE(fresh);
            Result<SchemeInstance> scratch = SchemeInstance::create(plugin);
            ASSERT_TRUE(scratch);
            ASSERT_TRUE(scratch->build(*fresh, settings));
            ASSERT_TRUE(scratch->update());
            std::vector<SurfacePoint> expected(requests.size());
            ASSERT_TRUE(scratch->evaluate(requests, expected));
            const float tolerance = 1e-6f * computeBounds(atFrame).diagonal();
            float worst = 0.0f;
            for (size_t i = 0; i < requests.size(); ++i)
                worst = std::max(worst, glm::length(played[i].position - expected[i].position));
            EXPECT_LE(worst, tolerance) << "frame " << frame;
        }
        ++tested;
    }
    EXPECT_GE(tested, 6u) << "schemes that refused the cage are not compared";
}
