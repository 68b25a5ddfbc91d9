// Brushes on displacement samples: what each brush does, strokes across faces and EVs, mirror
// symmetry, undo records, and the samples cache (index, refresh).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "displacement/brush.h"
#include "displacement/displacement.h"
#include "displacement/displacement_edit.h"
#include "displacement/sculpt_samples.h"
#include "plans/planned_cage.h"
#include "sculpt_test_support.h"
#include "test_cages.h"

using namespace qp;
using test::Sculpt;

namespace {

uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }


// A cube of 2x2-split faces centred at the origin: symmetric across x = 0, valence-3 EVs at
// the corners.
Cage symmetricCube() { return test::makeSubdividedCube(2); }

float variance(const std::vector<float>& values) {
    double mean = 0.0, squares = 0.0;
    for (float v : values) mean += v;
    mean /= double(values.size());
    for (float v : values) squares += (v - mean) * (v - mean);
    return float(squares / double(values.size()));
}

}  // namespace

TEST(SculptSamples, QueryFindsExactlyTheSamplesInTheSphere) {
    Sculpt s(test::makeMixedGrid(), 8);
    std::mt19937 rng(4);
    std::vector<uint32_t> sited = s.sited();
    for (int k = 0; k < 20; ++k) {
        glm::vec3 centre = s.samples->position(sited[rng() % sited.size()]) + glm::vec3(0.05f, -0.03f, 0.02f);
        float radius = 0.1f + 0.2f * float(k % 5);
        std::vector<uint32_t> found;
        s.samples->query(centre, radius, found);
        std::sort(found.begin(), found.end());
        std::vector<uint32_t> brute;
        for (uint32_t i : sited)
            if (s.distance(i, centre) <= radius) brute.push_back(i);
        EXPECT_EQ(found, brute);
        EXPECT_FALSE(brute.empty());
    }
}

TEST(SculptSamples, EverySampleOfAClosedCageHasASiteOnTheSurface) {
    Sculpt s(symmetricCube(), 4);
    std::vector<SampleSite> sites = computeSampleSites(s.displacement.layout, *s.planned);
    const DisplacementLayout& layout = s.displacement.layout;
    for (uint32_t i = 0; i < layout.sampleCount; ++i) {
        EXPECT_NE(sites[i].subface, kNoSite) << i;
        if (sites[i].subface == kNoSite) continue;
        glm::vec3 p = s.planned->evaluate(sites[i].subface, sites[i].u, sites[i].v).position;
        EXPECT_EQ(p, s.samples->position(i));
        EXPECT_NEAR(glm::length(s.samples->normal(i)), 1.0f, 1e-5f);
    }
}

TEST(SculptSamples, RefreshAfterMovingAVertexMatchesARebuild) {
    Sculpt s(test::makeGrid(6), 4);
    const uint32_t vertex = 8;
    // A small move (the index keeps its cells and widens queries), then a large one (rebuilt).
    for (glm::vec3 step : {glm::vec3(0.01f, 0.0f, 0.02f), glm::vec3(0.5f, 0.8f, 1.5f)}) {
        glm::vec3 moved = s.planned->cage().positions[vertex] + step;
        ASSERT_TRUE(s.planned->moveVertices({&vertex, 1}, {&moved, 1}));
        std::vector<uint32_t> affected = subfacesAffectedByVertices(*s.planned, {&vertex, 1});
        EXPECT_LT(affected.size(), s.planned->subfaceCount());
        s.samples->refresh(*s.planned, affected);
        SculptSamples rebuilt = SculptSamples::build(*s.planned, s.displacement.layout);
        for (uint32_t i = 0; i < rebuilt.sampleCount(); ++i) {
            ASSERT_EQ(s.samples->position(i), rebuilt.position(i)) << i;
            ASSERT_EQ(s.samples->normal(i), rebuilt.normal(i)) << i;
        }
        // Queries around the moved vertex find what a brute-force search finds.
        for (float radius : {0.05f, 0.3f, 1.0f}) {
            glm::vec3 centre = s.planned->evaluate(affected[affected.size() / 2], 0.3f, 0.6f).position;
            std::vector<uint32_t> found, brute;
            s.samples->query(centre, radius, found);
            std::sort(found.begin(), found.end());
            for (uint32_t i : s.sited())
                if (s.distance(i, centre) <= radius) brute.push_back(i);
            EXPECT_EQ(found, brute) << "radius " << radius;
        }
    }
}

TEST(Brush, RaiseRaisesWithinTheRadiusOnly) {
    Sculpt s(symmetricCube(), 8);
    // Centred on a cube corner: a valence-3 extraordinary vertex shared by three faces.
    const glm::vec3 centre = s.samples->position(0);
    Brush brush{BrushKind::Raise, 0.6f, 0.25f, Falloff::Constant};
    Sculptor sculptor(s.displacement, *s.samples);
    sculptor.beginStroke();
    sculptor.dab(brush, MirrorAxis::None, centre);
    StrokeRecord record = sculptor.endStroke();
    std::vector<uint32_t> subfacesTouched;
    uint32_t inside = 0;
    for (uint32_t i : s.sited()) {
        float d = s.displacement.samples[i];
        if (s.distance(i, centre) <= brush.radius) {
            EXPECT_EQ(d, brush.strength * brush.radius) << i;
            subfacesTouched.push_back(s.samples->site(i).subface);
            ++inside;
        } else {
            EXPECT_EQ(bits(d), 0u) << i;
        }
    }
    EXPECT_EQ(record.changes.size(), inside);
    std::sort(subfacesTouched.begin(), subfacesTouched.end());
    subfacesTouched.erase(std::unique(subfacesTouched.begin(), subfacesTouched.end()), subfacesTouched.end());
    EXPECT_GE(subfacesTouched.size(), 3u);  // across the faces around the EV

    // The smooth falloff: highest at the centre, zero at the rim, never negative.
    Sculpt t(symmetricCube(), 8);
    brush.falloff = Falloff::Smooth;
    applyStroke(t.displacement, *t.samples, StrokeOptions{brush}, std::span(&centre, 1));
    for (uint32_t i : t.sited()) {
        float x = t.distance(i, centre) / brush.radius;
        float expected = x <= 1.0f ? brush.strength * falloffWeight(Falloff::Smooth, x) * brush.radius : 0.0f;
        EXPECT_NEAR(t.displacement.samples[i], expected, 1e-6f);
    }
}

TEST(Brush, DabOnACreaseChangesBothSidesAlike) {
    // A cube with a semi-sharp crease along the edge between vertices 1 and 2 (x = 1, z = -1).
    Cage cage = test::makeCube();
    cage.setEdgeSharpness(1, 2, 2.5f);
    Sculpt s(cage, 8);
    const DisplacementLayout& layout = s.displacement.layout;
    const SampleGridLayout& adjacency = layout.adjacency;
    uint32_t creaseSegment = UINT32_MAX;
    for (uint32_t k = 0; k < adjacency.segments.size(); ++k)
        if (std::minmax(adjacency.segments[k].pointA, adjacency.segments[k].pointB) == std::minmax(1u, 2u)) creaseSegment = k;
    ASSERT_NE(creaseSegment, UINT32_MAX);
    glm::vec3 centre(0.0f);
    for (uint32_t f = 0; f < 6; ++f)
        for (uint32_t e = 0; e < 4; ++e)
            if (adjacency.subfaces[f].edges[e].segment == creaseSegment) {
                const glm::vec2 uv = edgePoint(e, 0.5f);
                centre = s.planned->evaluate(f, uv.x, uv.y).position;
            }
    Brush brush{BrushKind::Raise, 0.5f, 0.2f, Falloff::Linear};
    applyStroke(s.displacement, *s.samples, StrokeOptions{brush}, std::span(&centre, 1));
    // Samples of both faces at the crease, at the same distance, get the same value; the
    // shared crease samples are one value for both faces.
    std::vector<uint32_t> faces;
    for (uint32_t i : s.sited()) {
        float distance = s.distance(i, centre);
        float expected = distance <= brush.radius ? brush.strength * (1.0f - distance / brush.radius) * brush.radius : 0.0f;
        EXPECT_NEAR(s.displacement.samples[i], expected, 1e-6f);
        if (distance < brush.radius) faces.push_back(s.samples->site(i).subface);
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    EXPECT_EQ(faces.size(), 2u);  // the two faces at the crease
    // Evaluated from either face, the crease reads the same bits.
    for (uint32_t a = 0; a < 6; ++a)
        for (uint32_t b = a + 1; b < 6; ++b)
            for (uint32_t ea = 0; ea < 4; ++ea)
                for (uint32_t eb = 0; eb < 4; ++eb)
                    if (adjacency.subfaces[a].edges[ea].segment == creaseSegment && adjacency.subfaces[b].edges[eb].segment == creaseSegment) {
                        bool opposite = (adjacency.subfaces[a].edges[ea].flags ^ adjacency.subfaces[b].edges[eb].flags) & kEdgeReversed;
                        for (float t : {0.1f, 0.3f, 0.5f, 0.77f}) {
                            glm::vec2 pa = edgePoint(ea, t), pb = edgePoint(eb, opposite ? 1.0f - t : t);
                            EXPECT_EQ(bits(evaluateDisplacement(s.displacement, a, pa.x, pa.y).value),
                                      bits(evaluateDisplacement(s.displacement, b, pb.x, pb.y).value));
                            EXPECT_GT(evaluateDisplacement(s.displacement, a, pa.x, pa.y).value, 0.0f);
                        }
                    }
}

TEST(Brush, LowerIsRaiseNegated) {
    // One dab: along a path, later dabs measure distances on the displaced surface, which raise
    // and lower move apart, so a whole stroke of one is not the negated other.
    Sculpt a(symmetricCube(), 4), b(symmetricCube(), 4);
    std::vector<glm::vec3> path = {{1.0f, 0.2f, 0.3f}};
    Brush brush{BrushKind::Raise, 0.5f, 0.1f, Falloff::Linear};
    applyStroke(a.displacement, *a.samples, StrokeOptions{brush}, path);
    brush.kind = BrushKind::Lower;
    applyStroke(b.displacement, *b.samples, StrokeOptions{brush}, path);
    for (uint32_t i = 0; i < a.displacement.samples.size(); ++i)
        EXPECT_EQ(a.displacement.samples[i], -b.displacement.samples[i] + 0.0f);
}

TEST(Brush, SmoothReducesVariance) {
    Sculpt s(test::makeMixedGrid(), 8);
    std::mt19937 rng(6);
    std::uniform_real_distribution<float> noise(-0.05f, 0.05f);
    for (uint32_t i : s.sited()) s.displacement.samples[i] = noise(rng);
    const glm::vec3 centre = s.planned->evaluate(s.planned->firstSubface(s.planned->cage().faceCount() - 1), 0.3f, 0.3f).position;
    const float radius = 0.8f;
    auto within = [&](float r) {
        std::vector<float> values;
        for (uint32_t i : s.sited())
            if (s.distance(i, centre) <= r) values.push_back(s.displacement.samples[i]);
        return values;
    };
    const float before = variance(within(0.5f * radius));
    // Dabs reach samples by their displaced positions, within |D| <= 0.05 of the limit ones
    // (smoothing keeps D within the noise's range).
    const float unreached = radius + 0.05f;
    std::vector<float> outside;
    for (uint32_t i : s.sited())
        if (s.distance(i, centre) > unreached) outside.push_back(s.displacement.samples[i]);
    Brush brush{BrushKind::Smooth, radius, 1.0f, Falloff::Smooth};
    Sculptor sculptor(s.displacement, *s.samples);
    sculptor.beginStroke();
    for (int k = 0; k < 5; ++k) sculptor.dab(brush, MirrorAxis::None, centre);
    sculptor.endStroke();
    const float after = variance(within(0.5f * radius));
    EXPECT_LT(after, 0.2f * before) << "variance " << before << " -> " << after;
    std::vector<float> outsideAfter;
    for (uint32_t i : s.sited())
        if (s.distance(i, centre) > unreached) outsideAfter.push_back(s.displacement.samples[i]);
    EXPECT_EQ(outside, outsideAfter);
}

TEST(Brush, FlattenBringsDisplacedPointsOntoAPlane) {
    Sculpt s(test::makeGrid(4), 8);
    const glm::vec3 centre = s.planned->evaluate(s.planned->firstSubface(5), 0.5f, 0.5f).position;
    std::vector<uint32_t> near;
    s.samples->query(centre, 0.6f, near);
    ASSERT_GT(near.size(), 50u);
    // Bumpy: a raise stroke off-centre.
    std::vector<glm::vec3> path = {centre + glm::vec3(-0.4f, 0.0f, 0.0f), centre + glm::vec3(0.2f, 0.3f, 0.0f)};
    applyStroke(s.displacement, *s.samples, StrokeOptions{{BrushKind::Raise, 0.5f, 0.1f, Falloff::Smooth}}, path);
    // Distance of the displaced samples in `near` from their best plane (normal = mean normal).
    auto planeError = [&] {
        glm::vec3 mean(0.0f), normal(0.0f);
        std::vector<glm::vec3> points;
        for (uint32_t i : near) {
            points.push_back(s.samples->position(i) + s.displacement.samples[i] * s.samples->normal(i));
            mean += points.back();
            normal += s.samples->normal(i);
        }
        mean /= float(points.size());
        normal = glm::normalize(normal);
        float worst = 0.0f;
        for (const glm::vec3& p : points) worst = std::max(worst, std::abs(glm::dot(p - mean, normal)));
        return worst;
    };
    const float before = planeError();
    Brush flatten{BrushKind::Flatten, 1.2f, 1.0f, Falloff::Constant};
    Sculptor sculptor(s.displacement, *s.samples);
    sculptor.beginStroke();
    sculptor.dab(flatten, MirrorAxis::None, centre);
    sculptor.endStroke();
    const float after = planeError();
    EXPECT_LT(after, 0.2f * before) << "distance from the plane " << before << " -> " << after;
}

TEST(Brush, EraseReturnsToExactlyZero) {
    Sculpt s(test::makeMixedGrid(), 4);
    std::vector<glm::vec3> path = {{0.5f, 0.5f, 0.0f}, {3.5f, 3.0f, 0.0f}};
    applyStroke(s.displacement, *s.samples, StrokeOptions{{BrushKind::Lower, 0.7f, 0.3f, Falloff::Sphere}}, path);
    ASSERT_GT(std::count_if(s.displacement.samples.begin(), s.displacement.samples.end(), [](float v) { return v != 0.0f; }), 100);
    StrokeOptions erase{{BrushKind::Erase, 0.9f, 1.0f, Falloff::Constant}};
    applyStroke(s.displacement, *s.samples, erase, path);
    uint32_t checked = 0;
    for (uint32_t i : s.sited()) {
        // Within the radius of the path (dabs every radius / 4): +0 exactly.
        glm::vec3 p = s.samples->position(i);
        glm::vec3 a = path[0], b = path[1];
        float t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0f, 1.0f);
        if (glm::length(p - (a + t * (b - a))) < 0.9f - 0.25f * 0.9f) {
            EXPECT_EQ(bits(s.displacement.samples[i]), 0u) << i;
            ++checked;
        }
    }
    EXPECT_GT(checked, 100u);
}

TEST(Brush, MirrorGivesMirroredValuesOnASymmetricCage) {
    for (BrushKind kind : {BrushKind::Raise, BrushKind::Flatten, BrushKind::Smooth}) {
        Sculpt s(symmetricCube(), 8);
        ASSERT_NEAR(s.samples->centre().x, 0.0f, 1e-6f);
        if (kind != BrushKind::Raise) {
            // A symmetric but bumpy start: a mirrored raise.
            std::vector<glm::vec3> bump = {{0.2f, 0.9f, 0.9f}, {0.9f, 0.9f, -0.3f}};
            applyStroke(s.displacement, *s.samples, {{BrushKind::Raise, 0.5f, 0.2f, Falloff::Smooth}, MirrorAxis::X}, bump);
        }
        // A stroke from one side across the mirror plane and onto the top face.
        std::vector<glm::vec3> path = {{0.6f, 1.0f, 0.8f}, {-0.1f, 1.0f, 0.6f}, {0.4f, 1.0f, -0.2f}};
        Brush brush{kind, 0.45f, kind == BrushKind::Raise ? 0.1f : 0.7f, Falloff::Smooth};
        StrokeRecord record = applyStroke(s.displacement, *s.samples, {brush, MirrorAxis::X}, path);
        EXPECT_GT(record.changes.size(), 50u);
        // Each sample against the one at its mirror image.
        std::vector<uint32_t> sited = s.sited();
        float worst = 0.0f;
        uint32_t compared = 0;
        for (uint32_t i : sited) {
            glm::vec3 mirrored = s.samples->position(i) * glm::vec3(-1.0f, 1.0f, 1.0f);
            std::vector<uint32_t> found;
            s.samples->query(mirrored, 1e-5f, found);
            ASSERT_EQ(found.size(), 1u) << "no sample at the mirror image of sample " << i;
            worst = std::max(worst, std::abs(s.displacement.samples[i] - s.displacement.samples[found[0]]));
            ++compared;
        }
        EXPECT_LT(worst, 1e-5f) << brushKindName(kind);
        EXPECT_EQ(compared, sited.size());
    }
}

TEST(Brush, UndoRestoresExactlyAndRedoReapplies) {
    Sculpt s(test::makeMixedGrid(), 8);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> noise(-0.05f, 0.05f);
    for (uint32_t i : s.sited()) s.displacement.samples[i] = noise(rng);
    const std::vector<float> original = s.displacement.samples;
    std::vector<glm::vec3> path = {{0.5f, 0.5f, 0.0f}, {3.5f, 2.0f, 0.2f}, {1.0f, 3.5f, 0.0f}};
    Sculptor sculptor(s.displacement, *s.samples);
    std::vector<StrokeRecord> records;
    std::vector<std::vector<float>> after;
    for (BrushKind kind : {BrushKind::Raise, BrushKind::Smooth, BrushKind::Flatten, BrushKind::Erase}) {
        sculptor.beginStroke();
        sculptor.dabsAlong({{kind, 0.6f, kind == BrushKind::Raise ? 0.1f : 0.5f, Falloff::Smooth}}, path);
        records.push_back(sculptor.endStroke());
        after.push_back(s.displacement.samples);
        EXPECT_GT(records.back().changes.size(), 0u) << brushKindName(kind);
        EXPECT_TRUE(std::is_sorted(records.back().changes.begin(), records.back().changes.end(),
                                   [](const SampleChange& a, const SampleChange& b) { return a.sample < b.sample; }));
    }
    for (size_t k = records.size(); k-- > 0;) {
        undoStroke(s.displacement, records[k]);
        const std::vector<float>& expected = k ? after[k - 1] : original;
        for (size_t i = 0; i < expected.size(); ++i) ASSERT_EQ(bits(s.displacement.samples[i]), bits(expected[i])) << i;
    }
    for (size_t k = 0; k < records.size(); ++k) {
        redoStroke(s.displacement, records[k]);
        for (size_t i = 0; i < after[k].size(); ++i) ASSERT_EQ(bits(s.displacement.samples[i]), bits(after[k][i])) << i;
    }
}

TEST(Brush, DabsAreSpacedAlongThePath) {
    Sculpt s(test::makeGrid(4), 4);
    // 1 + 3 along the first segment (length 3, spacing 1), then the leftover carries on.
    std::vector<glm::vec3> path = {{0.5f, 0.5f, 0.0f}, {3.5f, 0.5f, 0.0f}, {3.5f, 2.0f, 0.0f}};
    StrokeOptions options{{BrushKind::Raise, 0.4f, 0.1f, Falloff::Smooth}};
    options.spacing = 1.0f;
    StrokeRecord record = applyStroke(s.displacement, *s.samples, options, path);
    EXPECT_EQ(record.dabs, 5u);  // at 0, 1, 2, 3 along x, then 1 up the second segment
    options.spacing = 0.0f;      // a quarter of the radius: 0.1
    EXPECT_EQ(applyStroke(s.displacement, *s.samples, options, path).dabs, 46u);
}

// The editor feeds a stroke one cursor position per frame: dabTo in pieces must dab where the
// whole polyline does (the spacing's leftover carries over), and `reached` lists every dab's
// samples.
TEST(Brush, AStrokeGivenInPiecesDabsWhereTheWholePathDoes) {
    Sculpt whole(test::makeGrid(4), 4), pieces(test::makeGrid(4), 4);
    const std::vector<glm::vec3> path = {{0.5f, 0.5f, 0.0f}, {1.2f, 0.6f, 0.0f}, {1.3f, 0.6f, 0.0f}, {3.5f, 2.0f, 0.0f}};
    StrokeOptions options{{BrushKind::Raise, 0.4f, 0.1f, Falloff::Smooth}};
    options.spacing = 0.3f;
    const StrokeRecord expected = applyStroke(whole.displacement, *whole.samples, options, path);

    Sculptor sculptor(pieces.displacement, *pieces.samples);
    sculptor.beginStroke();
    std::vector<uint32_t> reached;
    for (const glm::vec3& p : path) sculptor.dabTo(options, p, &reached);
    const StrokeRecord record = sculptor.endStroke();
    EXPECT_EQ(record.dabs, expected.dabs);
    EXPECT_EQ(pieces.displacement.samples, whole.displacement.samples);
    std::sort(reached.begin(), reached.end());
    for (const SampleChange& c : record.changes)
        EXPECT_TRUE(std::binary_search(reached.begin(), reached.end(), c.sample)) << "changed but not reported: " << c.sample;

    // A new stroke starts afresh: its first call dabs at once.
    sculptor.beginStroke();
    EXPECT_GT(sculptor.dabTo(options, path[0]), 0u);
    EXPECT_EQ(sculptor.endStroke().dabs, 1u);
}

// The history entry of a stroke or a replacement: redo and undo restore the bits, and the
// listener hears of every change (the editor's renderer and caches depend on it).
TEST(DisplacementEdit, StrokesAndReplacementsUndoRedoAndTellTheListener) {
    Sculpt s(test::makeGrid(4), 4);
    std::vector<DisplacementChange> heard;  // spans not kept: heardSamples has the copies
    std::vector<std::vector<SampleChange>> heardSamples;
    auto listener = [&](const DisplacementChange& c) {
        heard.push_back(c);
        heardSamples.emplace_back(c.samples.begin(), c.samples.end());
    };
    const std::vector<float> zero = s.displacement.samples;
    StrokeOptions options{{BrushKind::Raise, 0.6f, 0.2f, Falloff::Smooth}};
    StrokeRecord record = applyStroke(s.displacement, *s.samples, options, std::vector<glm::vec3>{{1.5f, 1.5f, 0.0f}});
    ASSERT_FALSE(record.changes.empty());
    const std::vector<float> raised = s.displacement.samples;
    EditHistory history;
    ASSERT_TRUE(history.perform(*s.planned, "Stroke", std::make_unique<DisplacementEdit>(s.displacement, record, listener)).ok());
    EXPECT_EQ(s.displacement.samples, raised) << "performing re-applies the after values";
    ASSERT_TRUE(history.undo(*s.planned).ok());
    EXPECT_EQ(s.displacement.samples, zero);
    ASSERT_TRUE(history.redo(*s.planned).ok());
    EXPECT_EQ(s.displacement.samples, raised);
    ASSERT_EQ(heard.size(), 3u);
    for (size_t k = 0; k < heard.size(); ++k) {
        EXPECT_FALSE(heard[k].newLayout);
        EXPECT_EQ(heardSamples[k].size(), record.changes.size());
    }
    const Displacement before = s.displacement;
    Displacement cleared;
    ASSERT_TRUE(history.perform(*s.planned, "Clear", std::make_unique<DisplacementEdit>(s.displacement, before, cleared, listener)).ok());
    EXPECT_TRUE(s.displacement.empty());
    ASSERT_TRUE(history.undo(*s.planned).ok());
    EXPECT_EQ(s.displacement, before);
    EXPECT_TRUE(heard.back().newLayout);
    EXPECT_GT(history.bytes(), displacementBytes(before)) << "the replacement's memory counts in the history's budget";
    EXPECT_FALSE(checkDisplacementResolution(12));
    EXPECT_FALSE(checkDisplacementResolution(0));
    EXPECT_TRUE(checkDisplacementResolution(64));
}

TEST(Brush, ValidationAndUploadRanges) {
    EXPECT_FALSE(validateBrush({BrushKind::Raise, 0.0f, 0.1f, Falloff::Smooth}));
    EXPECT_FALSE(validateBrush({BrushKind::Smooth, 1.0f, 1.5f, Falloff::Smooth}));
    EXPECT_FALSE(validateBrush({BrushKind::Raise, 1.0f, NAN, Falloff::Smooth}));
    EXPECT_TRUE(validateBrush({BrushKind::Raise, 1.0f, 3.0f, Falloff::Smooth}));
    SampleBits samples;
    samples.assign(200, std::vector<uint32_t>{31, 3, 100, 4, 5, 30, 17});
    std::vector<SampleRange> ranges = uploadRanges(samples, 16);  // blocks [0, 16) [16, 32) [96, 112)
    ASSERT_EQ(ranges.size(), 2u);
    EXPECT_EQ(ranges[0].first, 0u);
    EXPECT_EQ(ranges[0].count, 32u);
    EXPECT_EQ(ranges[1].first, 96u);
    EXPECT_EQ(ranges[1].count, 5u);  // clipped after the last sample
    samples.assign(200, std::vector<uint32_t>{});
    EXPECT_TRUE(uploadRanges(samples, 16).empty());
    // Random sets (from lists with repeats, in any order) against the definition: every block
    // holding a sample, runs merged, the last clipped.
    std::mt19937 rng(5);
    for (uint32_t block : {16u, 4u, 64u})
        for (int trial = 0; trial < 20; ++trial) {
            std::vector<uint32_t> list(rng() % 300);
            for (uint32_t& sample : list) sample = rng() % 1000;
            SampleBits set;
            set.assign(1000, list);
            std::vector<SampleRange> expected;
            uint32_t end = 0;
            for (uint32_t first = 0; first < 1000; first += block) {
                bool held = false;
                for (uint32_t sample : list) held |= sample / block == first / block, end = std::max(end, sample + 1);
                if (!held) continue;
                if (!expected.empty() && expected.back().first + expected.back().count == first) expected.back().count += block;
                else expected.push_back({first, block});
            }
            if (!expected.empty()) expected.back().count = end - expected.back().first;
            const std::vector<SampleRange> got = uploadRanges(set, block);
            ASSERT_EQ(got.size(), expected.size()) << block;
            for (size_t r = 0; r < got.size(); ++r) {
                EXPECT_EQ(got[r].first, expected[r].first);
                EXPECT_EQ(got[r].count, expected[r].count);
            }
        }
    EXPECT_EQ(brushKindFromName("flatten"), BrushKind::Flatten);
    EXPECT_EQ(brushKindFromName("inflate"), BrushKind::Inflate);
    EXPECT_FALSE(brushKindFromName("pinch"));
}
