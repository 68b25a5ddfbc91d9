// The sculpting mask (painting, invert, clear, undo, files), the inflate and crease brushes,
// dabs on the displaced surface (tall displacement) and refused input.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "displacement/brush.h"
#include "displacement/displacement.h"
#include "displacement/displacement_edit.h"
#include "displacement/displacement_io.h"
#include "displacement/sculpt_samples.h"
#include "displacement/sculpt_script.h"
#include "plans/planned_cage.h"
#include "scene/scene.h"
#include "sculpt_test_support.h"
#include "test_cages.h"

using namespace qp;
using test::Sculpt;

namespace {

uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }



constexpr BrushKind kHeightKinds[] = {BrushKind::Raise,   BrushKind::Lower,   BrushKind::Smooth, BrushKind::Flatten,
                                      BrushKind::Erase,   BrushKind::Inflate, BrushKind::Crease};

bool blends(BrushKind kind) { return kind == BrushKind::Smooth || kind == BrushKind::Flatten || kind == BrushKind::Erase; }

// A bumpy start, so that smoothing, flattening and erasing have something to change.
void roughen(Sculpt& s) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> value(-0.05f, 0.05f);
    for (uint32_t i : s.sited()) s.displacement.samples[i] = value(rng);
}

}  // namespace

TEST(BrushMask, FullyMaskedSamplesKeepTheirBitsUnderEveryBrush) {
    Sculpt s(test::makeSubdividedCube(2), 8);
    roughen(s);
    // Fully masked where x > 0.1, half masked in a band, free elsewhere.
    s.displacement.mask.assign(s.displacement.samples.size(), 0.0f);
    std::vector<uint32_t> masked;
    for (uint32_t i : s.sited()) {
        const float x = s.samples->position(i).x;
        if (x > 0.1f) s.displacement.mask[i] = 1.0f, masked.push_back(i);
        else if (x > -0.2f) s.displacement.mask[i] = 0.5f;
    }
    ASSERT_FALSE(masked.empty());
    const Displacement start = s.displacement;
    const glm::vec3 path[] = {{-0.6f, -0.3f, 0.55f}, {0.6f, 0.3f, 0.55f}};  // across the top, into the mask
    for (BrushKind kind : kHeightKinds)
        for (MirrorAxis mirror : {MirrorAxis::None, MirrorAxis::X}) {
            s.displacement = start;
            StrokeOptions options;
            options.brush = {kind, 0.5f, blends(kind) ? 0.7f : 0.1f, Falloff::Smooth};
            options.mirror = mirror;
            StrokeRecord record = applyStroke(s.displacement, *s.samples, options, path);
            ASSERT_FALSE(record.mask);
            uint32_t changedFree = 0;
            for (uint32_t i : s.sited())
                if (start.mask[i] == 0.0f && bits(s.displacement.samples[i]) != bits(start.samples[i])) ++changedFree;
            EXPECT_GT(changedFree, 0u) << brushKindName(kind) << " changed nothing at all";
            for (uint32_t i : masked)
                ASSERT_EQ(bits(s.displacement.samples[i]), bits(start.samples[i]))
                    << brushKindName(kind) << (mirror == MirrorAxis::X ? " mirrored" : "") << ", masked sample " << i;
            EXPECT_EQ(s.displacement.mask, start.mask);  // D brushes never paint the mask
        }
}

TEST(BrushMask, PartialMaskScalesTheChange) {
    Sculpt s(test::makeFlatGrid(4), 8);
    const uint32_t n = uint32_t(s.displacement.samples.size());
    s.displacement.mask.assign(n, 0.0f);
    std::vector<uint32_t> sited = s.sited();
    for (size_t k = 0; k < sited.size(); k += 2) s.displacement.mask[sited[k]] = 0.25f;
    StrokeOptions options;
    options.brush = {BrushKind::Raise, 1.0f, 0.1f, Falloff::Constant};
    const glm::vec3 centre(2.0f, 2.0f, 0.0f);
    applyStroke(s.displacement, *s.samples, options, std::span(&centre, 1));
    uint32_t checked = 0;
    for (uint32_t i : sited) {
        if (glm::length(s.samples->position(i) - centre) > 0.99f) continue;
        const float full = 0.1f * 1.0f;
        EXPECT_FLOAT_EQ(s.displacement.samples[i], full * (1.0f - s.displacement.mask[i])) << i;
        ++checked;
    }
    EXPECT_GT(checked, 20u);
}

TEST(BrushMask, MaskBrushesPaintOnlyTheMaskAndUndoExactly) {
    Sculpt s(test::makeFlatGrid(4), 8);
    roughen(s);
    const Displacement start = s.displacement;
    ASSERT_FALSE(start.hasMask());
    StrokeOptions options;
    options.brush = {BrushKind::Mask, 0.8f, 0.6f, Falloff::Smooth};
    const glm::vec3 path[] = {{1.0f, 2.0f, 0.0f}, {3.0f, 2.0f, 0.0f}};
    Sculptor sculptor(s.displacement, *s.samples);
    sculptor.beginStroke();
    sculptor.dabsAlong(options, path);
    // A D brush in a mask stroke changes nothing.
    EXPECT_EQ(sculptor.dab({BrushKind::Raise, 0.8f, 0.1f, Falloff::Smooth}, MirrorAxis::None, path[0]), 0u);
    StrokeRecord record = sculptor.endStroke();
    EXPECT_TRUE(record.mask);
    ASSERT_TRUE(s.displacement.hasMask());
    EXPECT_EQ(s.displacement.samples, start.samples);
    float most = 0.0f;
    for (float m : s.displacement.mask) {
        EXPECT_GE(m, 0.0f);
        EXPECT_LE(m, 1.0f);
        most = std::max(most, m);
    }
    EXPECT_EQ(most, 1.0f);  // many overlapping dabs: clamped at 1
    const Displacement painted = s.displacement;

    // Unmask takes some back, never below 0.
    options.brush = {BrushKind::Unmask, 0.5f, 1.0f, Falloff::Constant};
    StrokeRecord unmask = applyStroke(s.displacement, *s.samples, options, std::span(path, 1));
    EXPECT_TRUE(unmask.mask);
    EXPECT_FALSE(unmask.changes.empty());
    for (const SampleChange& c : unmask.changes) EXPECT_EQ(c.after, 0.0f);

    // Undo through the history entry: the listener hears maskOnly.
    std::vector<bool> heard;
    auto listener = [&](const DisplacementChange& change) { heard.push_back(change.maskOnly); };
    PlannedCage& planned = *s.planned;
    DisplacementEdit undoUnmask(s.displacement, unmask, listener);
    ASSERT_TRUE(undoUnmask.undo(planned));
    EXPECT_EQ(s.displacement, painted);
    DisplacementEdit undoMask(s.displacement, record, listener);
    ASSERT_TRUE(undoMask.undo(planned));
    EXPECT_EQ(s.displacement, start);  // a mask of zeros equals no mask
    for (float m : s.displacement.mask) EXPECT_EQ(bits(m), 0u);
    ASSERT_TRUE(undoMask.redo(planned));
    EXPECT_EQ(s.displacement, painted);
    EXPECT_EQ(heard, std::vector<bool>({true, true, true}));
}

TEST(BrushMask, InvertAndClearUndoAndRedoExactly) {
    Sculpt s(test::makeFlatGrid(3), 4);
    roughen(s);
    const Displacement start = s.displacement;
    PlannedCage& planned = *s.planned;

    Result<StrokeRecord> inverted = invertMask(s.displacement);
    ASSERT_TRUE(inverted) << inverted.error().message;
    EXPECT_TRUE(inverted->mask);
    ASSERT_EQ(s.displacement.mask.size(), s.displacement.samples.size());
    for (float m : s.displacement.mask) ASSERT_EQ(m, 1.0f);  // no mask inverted: everything masked
    EXPECT_EQ(s.displacement.samples, start.samples);

    // A partial mask, inverted twice, comes back bit for bit.
    for (size_t i = 0; i < s.displacement.mask.size(); ++i) s.displacement.mask[i] = float(i % 5) / 4.0f;
    const Displacement partial = s.displacement;
    Result<StrokeRecord> again = invertMask(s.displacement);
    ASSERT_TRUE(again);
    for (size_t i = 0; i < s.displacement.mask.size(); ++i) EXPECT_EQ(s.displacement.mask[i], 1.0f - partial.mask[i]);
    DisplacementEdit edit(s.displacement, *again, nullptr);
    ASSERT_TRUE(edit.undo(planned));
    EXPECT_EQ(s.displacement, partial);
    ASSERT_TRUE(edit.redo(planned));
    const Displacement invertedPartial = s.displacement;

    Result<StrokeRecord> cleared = clearMask(s.displacement);
    ASSERT_TRUE(cleared);
    for (float m : s.displacement.mask) EXPECT_EQ(bits(m), 0u);
    EXPECT_EQ(s.displacement, start);
    DisplacementEdit clearEdit(s.displacement, *cleared, nullptr);
    ASSERT_TRUE(clearEdit.undo(planned));
    EXPECT_EQ(s.displacement.mask, invertedPartial.mask);
    ASSERT_TRUE(clearEdit.redo(planned));
    EXPECT_EQ(s.displacement, start);

    // No displacement: a clear error and nothing changed.
    Displacement none;
    for (auto f : {invertMask, clearMask}) {
        Result<StrokeRecord> refused = f(none);
        ASSERT_FALSE(refused);
        EXPECT_NE(refused.error().message.find("no sculpted displacement to mask"), std::string::npos);
        EXPECT_TRUE(none.mask.empty());
    }
    EXPECT_FALSE(checkMaskable(none));
}

TEST(BrushMask, MaskSurvivesASceneSaveAndLoadBitForBit) {
    Scene scene = sceneOfCage(test::makeMixedGrid(), "cage");
    Displacement d = makeDisplacement(scene.objects[0].cage, buildTopology(scene.objects[0].cage), 4);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> value(0.0f, 1.0f);
    d.mask.resize(d.samples.size());
    for (float& m : d.mask) m = value(rng);
    d.mask[0] = 1.0f, d.mask[1] = 0.0f, d.mask[2] = 1e-40f;  // the ends and a subnormal
    scene.objects[0].displacement = d;
    std::vector<std::string> warnings;
    Result<Scene> loaded = parseScene(formatScene(scene, CageStorage::Inline), "scene.json", ".", &warnings);
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_TRUE(warnings.empty()) << warnings.front();  // "mask" is a known field
    const Displacement& back = loaded->objects[0].displacement;
    ASSERT_EQ(back.mask.size(), d.mask.size());
    for (size_t i = 0; i < d.mask.size(); ++i) ASSERT_EQ(bits(back.mask[i]), bits(d.mask[i])) << i;
    EXPECT_EQ(back, d);

    // A mask of zeros is written as none and reads back as none.
    std::fill(d.mask.begin(), d.mask.end(), 0.0f);
    EXPECT_FALSE(displacementJson(d).contains("mask"));
}

TEST(BrushMask, MalformedMasksAreRefusedNamingTheField) {
    const Cage cage = test::makeMixedGrid();
    Displacement d = makeDisplacement(cage, buildTopology(cage), 2);
    const size_t n = d.samples.size();
    auto errorOf = [&](const nlohmann::json& mask) {
        nlohmann::json value = nlohmann::json::parse(displacementJson(d).dump());
        value["mask"] = mask;
        Result<Displacement> read = readDisplacementJson(value, cage, "scene.json");
        return read ? std::string() : read.error().message;
    };
    auto floats = [](std::vector<float> values) { return encodeFloats(values.data(), values.size()); };
    std::vector<float> good(n, 0.5f);
    EXPECT_EQ(errorOf(floats(good)), "");
    std::vector<float> shortMask(n - 1, 0.5f), nan = good, big = good, negative = good;
    nan[3] = NAN, big[4] = 1.5f, negative[5] = -0.25f;
    for (const auto& [mask, what] : std::vector<std::pair<nlohmann::json, std::string>>{
             {floats(shortMask), "values but"},
             {floats(nan), "NaN"},
             {floats(big), "between 0"},
             {floats(negative), "between 0"},
             {42, "base64"},
             {"not base64!", "base64"}}) {
        const std::string error = errorOf(mask);
        EXPECT_NE(error.find("displacement.mask"), std::string::npos) << error;
        EXPECT_NE(error.find(what), std::string::npos) << error;
    }
    // A mask with no displacement.
    nlohmann::json none = {{"version", 1}, {"subfaces", nlohmann::json::array()}, {"mask", floats(good)}};
    Result<Displacement> read = readDisplacementJson(none, cage, "scene.json");
    ASSERT_FALSE(read);
    EXPECT_NE(read.error().message.find("displacement.mask"), std::string::npos);
}

TEST(BrushMask, ResamplingCarriesTheMask) {
    Sculpt s(test::makeMixedGrid(), 4);
    s.displacement.mask.assign(s.displacement.samples.size(), 0.0f);
    for (size_t i = 0; i < s.displacement.mask.size(); i += 3) s.displacement.mask[i] = 1.0f;
    const Displacement raised = resampleDisplacement(s.displacement, 8);
    ASSERT_EQ(raised.mask.size(), raised.samples.size());
    for (float m : raised.mask) ASSERT_TRUE(m >= 0.0f && m <= 1.0f);
    // Fully masked samples stay masked where the mask was 1 all around: the middle of a masked
    // region keeps 1 at the finer resolution.
    Displacement whole = s.displacement;
    std::fill(whole.mask.begin(), whole.mask.end(), 1.0f);
    for (float m : resampleDisplacement(whole, 8).mask) ASSERT_FLOAT_EQ(m, 1.0f);
    Displacement plain = s.displacement;
    plain.mask.clear();
    EXPECT_TRUE(resampleDisplacement(plain, 8).mask.empty());
}

TEST(BrushInflate, EqualsRaiseOnFlatDisplacementAndSwellsASlope) {
    Sculpt s(test::makeFlatGrid(4), 16);
    const glm::vec3 centre(2.0f, 2.0f, 0.0f);
    StrokeOptions raise, inflate;
    raise.brush = {BrushKind::Raise, 1.0f, 0.05f, Falloff::Smooth};
    inflate.brush = raise.brush;
    inflate.brush.kind = BrushKind::Inflate;

    // Flat D: the same bits as raise.
    Displacement a = s.displacement, b = s.displacement;
    applyStroke(a, *s.samples, raise, std::span(&centre, 1));
    applyStroke(b, *s.samples, inflate, std::span(&centre, 1));
    for (size_t i = 0; i < a.samples.size(); ++i) ASSERT_EQ(bits(a.samples[i]), bits(b.samples[i])) << i;

    // On a steep bump (slope about 1.2 at mid-radius), inflate raises the slope more, by at most 4x.
    StrokeOptions bump;
    bump.brush = {BrushKind::Raise, 1.5f, 0.6f, Falloff::Smooth};
    applyStroke(s.displacement, *s.samples, bump, std::span(&centre, 1));
    a = s.displacement, b = s.displacement;
    // Dab where the displaced surface is: at the bump's side.
    uint32_t side = UINT32_MAX;
    for (uint32_t i : s.sited())
        if (std::abs(glm::length(s.samples->position(i) - centre) - 0.7f) < 0.04f) side = i;
    ASSERT_NE(side, UINT32_MAX);
    const glm::vec3 at = s.displaced(side);
    StrokeRecord ra = applyStroke(a, *s.samples, raise, std::span(&at, 1));
    StrokeRecord rb = applyStroke(b, *s.samples, inflate, std::span(&at, 1));
    ASSERT_FALSE(ra.changes.empty());
    uint32_t more = 0;
    for (uint32_t i : s.sited()) {
        const float dr = a.samples[i] - s.displacement.samples[i], di = b.samples[i] - s.displacement.samples[i];
        ASSERT_GE(di, dr * (1.0f - 1e-5f)) << i;
        ASSERT_LE(di, 4.0f * dr + 1e-7f) << i;
        if (di > 1.2f * dr) ++more;
    }
    EXPECT_GT(more, 10u);
}

TEST(BrushCrease, CutsASharpVeeAlongTheStroke) {
    Sculpt s(test::makeFlatGrid(4), 16);
    // Samples sit at cell centres, (k + 1/2) / 16 on the unit faces: the stroke runs along a row of them.
    const float row = 2.0f + 1.0f / 32.0f;
    const glm::vec3 path[] = {{0.8f, row, 0.0f}, {3.2f, row, 0.0f}};
    StrokeOptions crease, lower;
    crease.brush = {BrushKind::Crease, 0.6f, 0.05f, Falloff::Smooth};
    lower.brush = crease.brush;
    lower.brush.kind = BrushKind::Lower;
    Displacement c = s.displacement, l = s.displacement;
    applyStroke(c, *s.samples, crease, path);
    applyStroke(l, *s.samples, lower, path);

    // The profile across the stroke at x = row: samples on that column, by y.
    std::vector<std::pair<float, uint32_t>> column;
    for (uint32_t i : s.sited())
        if (std::abs(s.samples->position(i).x - row) < 1e-4f) column.push_back({s.samples->position(i).y, i});
    std::sort(column.begin(), column.end());
    ASSERT_GT(column.size(), 40u);
    auto lowest = [&](const Displacement& d) {
        return std::min_element(column.begin(), column.end(),
                                [&](auto& a, auto& b) { return d.samples[a.second] < d.samples[b.second]; }) -
               column.begin();
    };
    const ptrdiff_t bottom = lowest(c);
    EXPECT_NEAR(column[size_t(bottom)].first, row, 1e-3f);  // the cut's minimum is on the stroke
    EXPECT_LT(c.samples[column[size_t(bottom)].second], 0.0f);
    auto secondDifference = [&](const Displacement& d, size_t k) {
        return d.samples[column[k - 1].second] + d.samples[column[k + 1].second] - 2.0f * d.samples[column[k].second];
    };
    const float sharp = secondDifference(c, size_t(bottom)), soft = secondDifference(l, size_t(bottom));
    EXPECT_GT(soft, 0.0f);
    EXPECT_GT(sharp, 1.5f * soft) << "crease " << sharp << " vs lower " << soft;
    // Away from the stroke nothing moved.
    for (auto [y, i] : column)
        if (std::abs(y - row) > 0.61f) {
            EXPECT_EQ(c.samples[i], 0.0f) << y;
        }
}

TEST(SculptSamples, DisplacedQueriesFindSamplesOnATallBump) {
    Sculpt s(test::makeSubdividedCube(2), 8);
    // A bump 20% of the diagonal tall on the top face, a smaller dent elsewhere.
    float diagonal = 0.0f;
    {
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (uint32_t i : s.sited()) lo = glm::min(lo, s.samples->position(i)), hi = glm::max(hi, s.samples->position(i));
        diagonal = glm::length(hi - lo);
    }
    const float tall = 0.2f * diagonal;
    // The limit points nearest to far-away points: on the top face (off its centre) and on a side.
    auto nearest = [&](const glm::vec3& far) {
        uint32_t best = s.sited()[0];
        for (uint32_t i : s.sited())
            if (glm::length(s.samples->position(i) - far) < glm::length(s.samples->position(best) - far)) best = i;
        return s.samples->position(best);
    };
    const glm::vec3 peak = nearest({1.0f, 0.5f, 20.0f}), dent = nearest({-20.0f, 0.0f, 0.0f});
    for (uint32_t i : s.sited()) {
        const glm::vec3 p = s.samples->position(i);
        const float r = glm::length(p - peak) / (0.15f * diagonal);
        if (r < 1.0f) s.displacement.samples[i] = tall * (1.0f - r * r * (3.0f - 2.0f * r));
        if (glm::length(p - dent) < 0.1f * diagonal) s.displacement.samples[i] = -0.3f * tall;
    }
    DisplacedCells cells;
    cells.rebuild(*s.samples, s.displacement.samples);
    ASSERT_TRUE(cells.current(*s.samples));
    std::vector<uint32_t> sited = s.sited();
    auto brute = [&](const glm::vec3& centre, float radius) {
        std::vector<uint32_t> out;
        for (uint32_t i : sited) {
            const glm::vec3 d = s.displaced(i) - centre;
            if (glm::dot(d, d) <= radius * radius) out.push_back(i);
        }
        return out;
    };
    uint32_t top = sited[0];
    for (uint32_t i : sited)
        if (s.displacement.samples[i] > s.displacement.samples[top]) top = i;
    std::mt19937 rng(9);
    uint32_t farFromLimit = 0;
    for (int k = 0; k < 60; ++k) {
        // Every third query near the bump's top, the others anywhere.
        const uint32_t at = k % 3 == 0 ? top : sited[rng() % sited.size()];
        const glm::vec3 centre = s.displaced(at) + glm::vec3(0.01f, -0.02f, 0.015f);
        const float radius = 0.05f + 0.05f * float(k % 4);
        std::vector<uint32_t> found;
        s.samples->queryDisplaced(centre, radius, cells, found);
        std::sort(found.begin(), found.end());
        ASSERT_EQ(found, brute(centre, radius)) << "query " << k;
        for (uint32_t i : found)
            if (glm::length(s.samples->position(i) - centre) > radius + 0.5f * tall) ++farFromLimit;
    }
    // The tip: samples whose limit positions lie far below it.
    uint32_t highest = sited[0];
    for (uint32_t i : sited)
        if (s.displacement.samples[i] > s.displacement.samples[highest]) highest = i;
    ASSERT_GT(s.displacement.samples[highest], 0.9f * tall);
    const glm::vec3 tip = s.displaced(highest);
    std::vector<uint32_t> found;
    s.samples->queryDisplaced(tip, 0.1f, cells, found);
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, brute(tip, 0.1f));
    ASSERT_FALSE(found.empty());
    for (uint32_t i : found) EXPECT_GT(glm::length(s.samples->position(i) - tip), 0.1f + 0.5f * tall);
    EXPECT_GT(farFromLimit, 0u);

    // A dab at the tip reaches exactly those samples, and its weights are by displaced distance.
    Sculptor sculptor(s.displacement, *s.samples);
    sculptor.beginStroke();
    const Displacement before = s.displacement;
    sculptor.dab({BrushKind::Raise, 0.1f, 0.01f, Falloff::Constant}, MirrorAxis::None, tip);
    std::vector<uint32_t> reached(sculptor.lastDabSamples().begin(), sculptor.lastDabSamples().end());
    std::sort(reached.begin(), reached.end());
    EXPECT_EQ(reached, found);
    for (uint32_t i : found) EXPECT_NEAR(s.displacement.samples[i] - before.samples[i], 0.01f * 0.1f, 1e-6f);
    sculptor.endStroke();
}

TEST(SculptSamples, DabsFindTheSurfaceTheStrokeItselfRaised) {
    // One stroke raises a column tall (many dabs at one spot): each dab must find the samples
    // where the earlier dabs of the same stroke put them (the cells grow after every dab).
    Sculpt s(test::makeFlatGrid(4), 8);
    Sculptor sculptor(s.displacement, *s.samples);
    sculptor.beginStroke();
    const Brush brush{BrushKind::Raise, 0.5f, 0.5f, Falloff::Constant};
    uint32_t middle = s.sited()[0];
    for (uint32_t i : s.sited())
        if (glm::length(s.samples->position(i) - glm::vec3(2, 2, 0)) < glm::length(s.samples->position(middle) - glm::vec3(2, 2, 0)))
            middle = i;
    ASSERT_LT(glm::length(s.samples->position(middle) - glm::vec3(2, 2, 0)), 0.1f);
    for (int k = 0; k < 30; ++k) {
        // Follow the top of the column: the dab centre is on the displaced surface.
        sculptor.dab(brush, MirrorAxis::None, s.displaced(middle));
        ASSERT_FALSE(sculptor.lastDabSamples().empty()) << "dab " << k;
    }
    sculptor.endStroke();
    float top = 0.0f;
    for (float d : s.displacement.samples) top = std::max(top, std::abs(d));
    EXPECT_GT(top, 5.0f);  // 30 dabs of a quarter unit each reached the column's top every time
}

TEST(SculptSamples, GrownDisplacedCellsAnswerAsRebuiltOnes) {
    // Cells grown dab after dab (big lists spread over the cores, cells held whole given their
    // exact boxes, partly reached ones widened) keep the displaced positions a rebuild computes,
    // to the bit, and answer every query as a rebuild and a brute-force search do.
    Sculpt s(test::makeSubdividedCube(4), 16);
    const std::vector<uint32_t> sited = s.sited();
    DisplacedCells grown;
    grown.rebuild(*s.samples, s.displacement.samples);
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    size_t biggest = 0;
    for (int dab = 0; dab < 24; ++dab) {
        const glm::vec3 centre = s.displaced(sited[rng() % sited.size()]);
        std::vector<uint32_t> found, indexed;
        s.samples->queryDisplaced(centre, 0.3f + 2.2f * unit(rng), grown, found, &indexed);
        std::vector<float> values(found.size());
        for (size_t i = 0; i < found.size(); ++i)
            values[i] = s.displacement.samples[found[i]] += (dab % 3 == 2 ? -0.2f : 0.3f) * unit(rng);
        grown.growIndexed(*s.samples, indexed, values);
        biggest = std::max(biggest, found.size());
    }
    ASSERT_GT(biggest, 8192u);  // some dabs took the parallel path (chunks of 8192)
    DisplacedCells rebuilt;
    rebuilt.rebuild(*s.samples, s.displacement.samples);
    for (uint32_t k = 0; k < sited.size(); ++k)
        ASSERT_EQ(std::bit_cast<glm::uvec3>(grown.indexedDisplaced(k)), std::bit_cast<glm::uvec3>(rebuilt.indexedDisplaced(k)))
            << "index place " << k;
    for (int query = 0; query < 40; ++query) {
        const glm::vec3 centre = s.displaced(sited[rng() % sited.size()]) + glm::vec3(0.01f, -0.02f, 0.03f);
        const float radius = 0.05f + 1.0f * unit(rng);
        std::vector<uint32_t> a, b, brute;
        s.samples->queryDisplaced(centre, radius, grown, a);
        s.samples->queryDisplaced(centre, radius, rebuilt, b);
        for (uint32_t i : sited)
            if (const glm::vec3 d = s.displaced(i) - centre; glm::dot(d, d) <= radius * radius) brute.push_back(i);
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        ASSERT_EQ(a, brute) << "query " << query;
        ASSERT_EQ(b, brute) << "query " << query;
    }
}

TEST(Brush, BadStrokesAreRefusedAndChangeNothing) {
    Sculpt s(test::makeFlatGrid(3), 4);
    roughen(s);
    const Displacement start = s.displacement;
    StrokeOptions options;
    options.brush = {BrushKind::Raise, 0.5f, 0.1f, Falloff::Smooth};
    const glm::vec3 path[] = {{1, 1, 0}, {NAN, 1, 0}, {2, 2, 0}};
    Status refused = validateStroke(options, path);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("point 2"), std::string::npos) << refused.error().message;
    EXPECT_TRUE(applyStroke(s.displacement, *s.samples, options, path).changes.empty());
    EXPECT_EQ(s.displacement, start);
    const glm::vec3 infinite[] = {{1, INFINITY, 0}};
    EXPECT_FALSE(validateStroke(options, infinite));
    Sculptor sculptor(s.displacement, *s.samples);
    sculptor.beginStroke();
    EXPECT_EQ(sculptor.dab(options.brush, MirrorAxis::None, glm::vec3(NAN)), 0u);
    EXPECT_EQ(sculptor.dabTo(options, glm::vec3(1, INFINITY, 0)), 0u);
    EXPECT_TRUE(sculptor.endStroke().changes.empty());
    EXPECT_EQ(s.displacement, start);

    for (float radius : {0.0f, -1.0f, NAN, INFINITY, 1e31f}) {
        options.brush.radius = radius;
        EXPECT_FALSE(validateBrush(options.brush)) << radius;
        const glm::vec3 ok[] = {{1, 1, 0}};
        EXPECT_FALSE(validateStroke(options, ok));
        EXPECT_TRUE(applyStroke(s.displacement, *s.samples, options, ok).changes.empty());
        EXPECT_EQ(s.displacement, start);
    }
    EXPECT_TRUE(checkBrushRadiusForModel(1e6f, 1.5f));
    EXPECT_FALSE(checkBrushRadiusForModel(2e6f, 1.5f));
    options.brush.radius = 0.5f;
    options.spacing = NAN;
    EXPECT_FALSE(validateStroke(options, std::span(path, 1)));
    options.spacing = 0.0f;

    // Strength ranges, kind by kind.
    for (BrushKind kind : {BrushKind::Raise, BrushKind::Lower, BrushKind::Smooth, BrushKind::Flatten, BrushKind::Erase,
                           BrushKind::Inflate, BrushKind::Crease, BrushKind::Mask, BrushKind::Unmask}) {
        const bool unit = blends(kind) || isMaskBrush(kind);
        EXPECT_TRUE(validateBrush({kind, 0.5f, 1.0f, Falloff::Smooth})) << brushKindName(kind);
        EXPECT_EQ(bool(validateBrush({kind, 0.5f, 1.5f, Falloff::Smooth})), !unit) << brushKindName(kind);
        EXPECT_FALSE(validateBrush({kind, 0.5f, -0.1f, Falloff::Smooth})) << brushKindName(kind);
        EXPECT_FALSE(validateBrush({kind, 0.5f, NAN, Falloff::Smooth})) << brushKindName(kind);
        EXPECT_FALSE(validateBrush({kind, 0.5f, 11.0f, Falloff::Smooth})) << brushKindName(kind);
        EXPECT_EQ(brushKindFromName(brushKindName(kind)), kind);
    }

    // Mask brushes on a scene without displacement change nothing.
    Displacement none;
    Sculptor empty(none, *s.samples);
    empty.beginStroke();
    EXPECT_EQ(empty.dab({BrushKind::Mask, 0.5f, 1.0f, Falloff::Smooth}, MirrorAxis::None, glm::vec3(1, 1, 0)), 0u);
    EXPECT_TRUE(none.mask.empty());
}

TEST(SculptScript, NewBrushNamesAndBadValuesNameTheField) {
    auto parse = [](const std::string& stroke) { return parseStrokeFile("{\"strokes\": [" + stroke + "]}", "s.json"); };
    for (const char* name : {"inflate", "crease", "mask", "unmask"}) {
        auto ok = parse(std::string("{\"brush\": \"") + name + "\", \"radius\": 0.3, \"strength\": 0.5, \"path\": [[0,0,0]]}");
        ASSERT_TRUE(ok) << ok.error().message;
        EXPECT_EQ(brushKindName((*ok)[0].options.brush.kind), std::string(name));
    }
    auto tooStrong = parse("{\"brush\": \"mask\", \"radius\": 0.3, \"strength\": 2, \"path\": [[0,0,0]]}");
    ASSERT_FALSE(tooStrong);
    EXPECT_NE(tooStrong.error().message.find("strokes[0]"), std::string::npos) << tooStrong.error().message;
    EXPECT_NE(tooStrong.error().message.find("between 0 and 1"), std::string::npos) << tooStrong.error().message;
    auto huge = parse("{\"brush\": \"crease\", \"radius\": 1e31, \"strength\": 0.1, \"path\": [[0,0,0]]}");
    ASSERT_FALSE(huge);
    EXPECT_NE(huge.error().message.find("strokes[0]"), std::string::npos) << huge.error().message;
    auto unknown = parse("{\"brush\": \"pinch\", \"radius\": 0.3, \"strength\": 0.1, \"path\": [[0,0,0]]}");
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("strokes[0].brush"), std::string::npos);
    EXPECT_NE(unknown.error().message.find("\"unmask\""), std::string::npos);
}
