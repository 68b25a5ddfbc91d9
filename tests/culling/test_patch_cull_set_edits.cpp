// Editing a PatchCullSet in place (core/culling/patch_cull_set.h): replacing entries whose leaves
// fit their room or not, and renumbering entries as a topology edit does (dropped, kept, new),
// leaves every entry as a set built afresh from the same leaves would hold it, and the leaf
// arrays never hold more than twice what the entries name.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "culling/patch_cull_set.h"

using namespace qp;

namespace {

// An entry's leaves: 0 to 3 Bézier patches, maybe a Gregory patch and a flat triangle, or no surface.
PatchCullLeaves randomLeaves(std::mt19937& rng) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    PatchCullLeaves leaves;
    if (rng() % 8 == 0) return leaves;  // absent
    const glm::vec3 shift(unit(rng), unit(rng), unit(rng));
    const uint32_t beziers = rng() % 4;
    for (uint32_t b = 0; b < beziers; ++b) {
        BicubicPoints p;
        for (int k = 0; k < 16; ++k) p[k] = shift + glm::vec3(float(k % 4) / 3.0f, float(k / 4) / 3.0f, 0.2f * unit(rng));
        if (rng() % 2) addBezierLeaf(leaves, p, false);
        else addSmallBezierLeaf(leaves, p, false);
    }
    if (rng() % 3 == 0) {
        std::array<glm::vec3, 20> g;
        for (int k = 0; k < 20; ++k) g[k] = shift + glm::vec3(unit(rng), unit(rng), 0.1f * unit(rng));
        addGregoryLeaf(leaves, g, false);
    }
    if (rng() % 3 == 0 || beziers == 0) addFlatTriangle(leaves, shift, shift + glm::vec3(1, 0, 0), shift + glm::vec3(0, 1, 0));
    return leaves;
}

template <class T>
std::vector<T> named(const std::vector<T>& array, LeafRange range) {
    return std::vector<T>(array.begin() + range.first, array.begin() + range.first + range.count);
}

bool sameCone(const NormalCone& a, const NormalCone& b) {
    return a.bounded == b.bounded && (!a.bounded || (a.axis == b.axis && a.halfAngle == b.halfAngle));
}

void expectSameEntries(const PatchCullSet& edited, const PatchCullSet& fresh, const std::string& when) {
    ASSERT_EQ(edited.size(), fresh.size()) << when;
    for (uint32_t e = 0; e < fresh.size(); ++e) {
        const bool bothAbsent = !(fresh.boxes[e].lo.x <= fresh.boxes[e].hi.x) && !(edited.boxes[e].lo.x <= edited.boxes[e].hi.x);
        EXPECT_TRUE(bothAbsent || (edited.boxes[e].lo == fresh.boxes[e].lo && edited.boxes[e].hi == fresh.boxes[e].hi))
            << when << ", entry " << e;
        EXPECT_TRUE(sameCone(edited.tcones[e], fresh.tcones[e]) && sameCone(edited.ncones[e], fresh.ncones[e])) << when << ", " << e;
        EXPECT_EQ(named(edited.planes, edited.planeRanges[e]), named(fresh.planes, fresh.planeRanges[e])) << when << ", " << e;
        const auto a = named(edited.coneLeaves, edited.coneLeafRanges[e]), b = named(fresh.coneLeaves, fresh.coneLeafRanges[e]);
        ASSERT_EQ(a.size(), b.size()) << when << ", " << e;
        for (size_t k = 0; k < a.size(); ++k)
            EXPECT_TRUE(sameCone(a[k].cone, b[k].cone) && a[k].box.lo == b[k].box.lo && a[k].box.hi == b[k].box.hi) << when << ", " << e;
        EXPECT_EQ(named(edited.flats, edited.flatRanges[e]), named(fresh.flats, fresh.flatRanges[e])) << when << ", " << e;
    }
    size_t planes = 0;
    for (const LeafRange& r : edited.planeRanges) planes += r.count;
    EXPECT_LE(edited.planes.size(), 2 * planes + 3) << when << ": unnamed leaves are compacted away";
}

}  // namespace

TEST(PatchCullSetEdits, ReplacedAndRenumberedEntriesEqualAFreshSet) {
    std::mt19937 rng(41);
    std::vector<PatchCullLeaves> reference;  // what each entry holds now
    std::vector<glm::vec3> origins;
    PatchCullSet set;
    for (uint32_t e = 0; e < 200; ++e) {
        reference.push_back(randomLeaves(rng));
        origins.push_back(glm::vec3(float(e), 0.0f, 0.0f));
        appendPatch(set, reference.back(), origins.back());
    }
    auto fresh = [&] {
        PatchCullSet out;
        for (size_t e = 0; e < reference.size(); ++e) appendPatch(out, reference[e], origins[e]);
        return out;
    };
    for (int round = 0; round < 30; ++round) {
        // Replace a few entries: some keep their shape (a move), most take other leaves.
        std::vector<uint32_t> entries;
        for (uint32_t e = 0; e < set.size(); ++e)
            if (rng() % 10 == 0) entries.push_back(e);
        std::vector<PatchCullLeaves> leaves;
        std::vector<glm::vec3> at;
        for (uint32_t e : entries) {
            leaves.push_back(rng() % 2 ? reference[e] : randomLeaves(rng));
            at.push_back(origins[e] + glm::vec3(0.0f, 1.0f, 0.0f));
            reference[e] = leaves.back();
            origins[e] = at.back();
        }
        replacePatches(set, entries, leaves, at);
        expectSameEntries(set, fresh(), "round " + std::to_string(round) + ", replaced");

        // Renumber: drop some entries, shuffle the rest a little, add new ones (absent until replaced).
        std::vector<uint32_t> previousOf;
        for (uint32_t e = 0; e < set.size(); ++e)
            if (rng() % 12 != 0) previousOf.push_back(e);
        for (size_t k = 0; k + 1 < previousOf.size(); k += 7) std::swap(previousOf[k], previousOf[k + 1]);
        for (int n = 0; n < 15; ++n) previousOf.insert(previousOf.begin() + std::ptrdiff_t(rng() % (previousOf.size() + 1)), UINT32_MAX);
        renumberPatches(set, previousOf);
        std::vector<PatchCullLeaves> renumbered;
        std::vector<glm::vec3> renumberedOrigins;
        std::vector<uint32_t> added;
        for (uint32_t k = 0; k < previousOf.size(); ++k) {
            renumbered.push_back(previousOf[k] == UINT32_MAX ? PatchCullLeaves{} : reference[previousOf[k]]);
            renumberedOrigins.push_back(previousOf[k] == UINT32_MAX ? glm::vec3(0.0f) : origins[previousOf[k]]);
            if (previousOf[k] == UINT32_MAX) added.push_back(k);
        }
        reference = std::move(renumbered);
        origins = std::move(renumberedOrigins);
        expectSameEntries(set, fresh(), "round " + std::to_string(round) + ", renumbered");
        std::vector<PatchCullLeaves> newLeaves;
        std::vector<glm::vec3> newOrigins;
        for (uint32_t k : added) {
            newLeaves.push_back(randomLeaves(rng));
            newOrigins.push_back(glm::vec3(float(k), 2.0f, 0.0f));
            reference[k] = newLeaves.back();
            origins[k] = newOrigins.back();
        }
        replacePatches(set, added, newLeaves, newOrigins);
        expectSameEntries(set, fresh(), "round " + std::to_string(round) + ", new entries");
    }
}
