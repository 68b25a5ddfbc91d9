#include "culling/patch_cull_set.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>

namespace qp {

namespace {

void grow(CullBox& box, const CullBox& other) {
    box.lo = glm::min(box.lo, other.lo);
    box.hi = glm::max(box.hi, other.hi);
}

// The cone holding several cones (each axis within its half-angle).
NormalCone unionOf(std::span<const NormalCone> cones) {
    NormalCone out;
    glm::vec3 sum(0.0f);
    for (const NormalCone& c : cones) {
        if (!c.bounded) return out;
        sum += c.axis;
    }
    const float length = glm::length(sum);
    if (cones.empty() || !(length > 1e-6f)) return out;
    out.axis = sum / length;
    float widest = 0.0f;
    for (const NormalCone& c : cones)
        widest = std::max(widest, std::atan2(glm::length(glm::cross(out.axis, c.axis)), glm::dot(out.axis, c.axis)) + c.halfAngle);
    out.halfAngle = widest;
    out.bounded = widest < 0.5f * 3.14159265f;
    return out;
}

// With its interior points F_k(u, v), blends of Fp_k and Fm_k, a Gregory patch has
// B_u = D_u + e_u:
//   D_u, the Bézier net's u-derivative with the interior points held, 3 sum B2_i(u) B3_j(v) times
//       the net's u-differences, each interior point anywhere on [Fm_k, Fp_k] (so a positive
//       combination of the differences taken with either end): within the cone (a, alpha) of
//       those, and D_u . a >= m = 3 min(difference . a) (the weights sum to 1);
//   e_u = sum_k (d/du of the blend weight) B(interior point k) (Fp_k - Fm_k), each factor at most
//       4/3 in size (gregoryWeights: e.g. corner 0, v / (u + v)^2 * 9 u (1 - u)^2 v (1 - v)^2 <=
//       9 u (1 - u)^2 <= 4/3), so |e_u| <= E = 4/3 sum_k |Fp_k - Fm_k|.
// B_u then lies within alpha + asin(E / m) of a (when E < m); B_v likewise; Sederberg and
// Meyers' rule gives the normal cone. The patch has no polynomial normal patch: its ncone is
// that cone, and pplane tests the leaf with it.
NormalCone gregoryTangentCone(std::span<const glm::vec3> differences, float perturbation) {
    NormalCone cone = coneOfVectors(differences);
    if (!cone.bounded) return cone;
    float least = INFINITY;
    for (const glm::vec3& d : differences) least = std::min(least, 3.0f * glm::dot(d, cone.axis));
    if (!(perturbation < least)) return NormalCone{};
    cone.halfAngle += std::asin(perturbation / least);
    cone.bounded = cone.halfAngle < 0.5f * 3.14159265f;
    return cone;
}

}  // namespace

std::optional<CullMethod> parseCullMethod(std::string_view name) {
    for (CullMethod m : {CullMethod::None, CullMethod::Frustum, CullMethod::TCone, CullMethod::NCone, CullMethod::PPlane})
        if (name == cullMethodName(m)) return m;
    return std::nullopt;
}

const char* cullMethodName(CullMethod method) {
    switch (method) {
    case CullMethod::None: return "none";
    case CullMethod::Frustum: return "frustum";
    case CullMethod::TCone: return "tcone";
    case CullMethod::NCone: return "ncone";
    case CullMethod::PPlane: return "pplane";
    }
    return "?";
}

glm::vec4 homogeneousEye(const glm::mat4& m, const glm::vec3& eyePoint) {
    const glm::vec4 lastRow(m[0][3], m[1][3], m[2][3], m[3][3]);
    if (lastRow.x != 0.0f || lastRow.y != 0.0f || lastRow.z != 0.0f) return glm::vec4(eyePoint, 1.0f);
    // Orthographic: the rays run along the direction that changes neither clip x nor clip y, and
    // toward the viewer depth (row 2) falls. Not row 2 itself: under an object's non-uniform scale
    // or shear the depth gradient is not the rays' direction.
    const glm::vec3 row0(m[0][0], m[1][0], m[2][0]), row1(m[0][1], m[1][1], m[2][1]), row2(m[0][2], m[1][2], m[2][2]);
    glm::vec3 toViewer = glm::cross(row0, row1);
    if (glm::dot(row2, toViewer) > 0.0f) toViewer = -toViewer;
    return glm::vec4(glm::normalize(toViewer), 0.0f);
}

NormalCone gregoryNormalCone(const std::array<glm::vec3, 20>& g) {
    // The Bézier net, each interior point as its two ends: net(i, j) -> {a, b}.
    std::array<std::array<glm::vec3, 2>, 16> net;
    auto set = [&](int i, int j, const glm::vec3& a, const glm::vec3& b) { net[4 * j + i] = {a, b}; };
    // Corner k's P, Ep, Em and interior point in the net (patch_basis.h).
    const int corner[4][4][2] = {{{0, 0}, {1, 0}, {0, 1}, {1, 1}}, {{3, 0}, {3, 1}, {2, 0}, {2, 1}},
                                 {{3, 3}, {2, 3}, {3, 2}, {2, 2}}, {{0, 3}, {0, 2}, {1, 3}, {1, 2}}};
    float spread = 0.0f;
    for (int k = 0; k < 4; ++k) {
        for (int q = 0; q < 3; ++q) set(corner[k][q][0], corner[k][q][1], g[5 * k + q], g[5 * k + q]);
        set(corner[k][3][0], corner[k][3][1], g[5 * k + 3], g[5 * k + 4]);
        spread += glm::length(g[5 * k + 3] - g[5 * k + 4]);
    }
    std::vector<glm::vec3> alongU, alongV;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 3; ++i)
            for (const glm::vec3& a : net[4 * j + i + 1])
                for (const glm::vec3& b : net[4 * j + i]) alongU.push_back(a - b);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 3; ++j)
            for (const glm::vec3& a : net[4 * (j + 1) + i])
                for (const glm::vec3& b : net[4 * j + i]) alongV.push_back(a - b);
    const float perturbation = 4.0f / 3.0f * spread;
    return normalConeOfTangents(gregoryTangentCone(alongU, perturbation), gregoryTangentCone(alongV, perturbation));
}

namespace {

// A Bézier leaf's box and, as far as out.detail reads them, its cones; its ncone when made.
std::optional<NormalCone> addBezierBounds(PatchCullLeaves& out, const BicubicPoints& bezier, bool reversed) {
    grow(out.box, boxOf(bezier));
    if (out.detail < CullMethod::TCone) return std::nullopt;
    NormalCone t = tangentCone(bezier);
    if (reversed) t.axis = -t.axis;
    out.tcones.push_back(t);
    if (out.detail < CullMethod::NCone) return std::nullopt;
    NormalCone n = normalPatchCone(bezier);
    if (reversed) n.axis = -n.axis;
    out.ncones.push_back(n);
    return n;
}

}  // namespace

void addBezierLeaf(PatchCullLeaves& out, const BicubicPoints& bezier, bool reversed) {
    if (!addBezierBounds(out, bezier, reversed) || out.detail < CullMethod::PPlane) return;
    TangentPlanes planes = tangentPlanesOf(bezier);
    if (reversed)
        for (glm::vec4& p : planes) p = -p;
    out.planes.push_back(planes);
}

void addSmallBezierLeaf(PatchCullLeaves& out, const BicubicPoints& bezier, bool reversed) {
    const std::optional<NormalCone> ncone = addBezierBounds(out, bezier, reversed);
    if (ncone && out.detail >= CullMethod::PPlane) out.coneLeaves.push_back({*ncone, boxOf(bezier)});
}

void addGregoryLeaf(PatchCullLeaves& out, const std::array<glm::vec3, 20>& g, bool reversed) {
    CullBox box{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (const glm::vec3& p : g) grow(box, CullBox{p, p});
    grow(out.box, box);
    if (out.detail < CullMethod::TCone) return;
    NormalCone cone = gregoryNormalCone(g);
    if (reversed) cone.axis = -cone.axis;
    out.tcones.push_back(cone);
    if (out.detail >= CullMethod::NCone) out.ncones.push_back(cone);
    if (out.detail >= CullMethod::PPlane) out.coneLeaves.push_back({cone, box});
}

void addConelessBox(PatchCullLeaves& out, const CullBox& box) {
    grow(out.box, box);
    out.coneless = true;
}

void addCubicTriangleLeaf(PatchCullLeaves& out, const CubicTrianglePoints& points) {
    grow(out.box, boxOf(points));
    if (out.detail < CullMethod::TCone) return;
    const NormalCone cone = cubicTriangleNormalCone(points);
    out.tcones.push_back(cone);
    if (out.detail >= CullMethod::NCone) out.ncones.push_back(cone);
}

void addFlatTriangle(PatchCullLeaves& out, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    grow(out.box, boxOf(std::array<glm::vec3, 3>{a, b, c}));
    if (out.detail < CullMethod::TCone) return;
    // In double: a thin triangle's normal is a difference of nearly equal products.
    const glm::dvec3 normal = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
    const double length = glm::length(normal);
    if (!(length > 0.0)) {
        out.coneless = true;
        return;
    }
    out.tcones.push_back(NormalCone{glm::vec3(normal / length), 0.0f, true});
    if (out.detail >= CullMethod::NCone) out.ncones.push_back(out.tcones.back());
    if (out.detail >= CullMethod::PPlane) out.flats.push_back(glm::vec4(glm::vec3(normal), float(glm::dot(normal, glm::dvec3(a)))));
}

BicubicPoints withPhantoms(BicubicPoints p, uint32_t mask) {
    auto at = [&](int column, int row) -> glm::vec3& { return p[4 * row + column]; };
    for (int c = 0; c < 4; ++c) {
        if (mask & 1) at(c, 0) = 2.0f * at(c, 1) - at(c, 2);
        if (mask & 4) at(c, 3) = 2.0f * at(c, 2) - at(c, 1);
    }
    for (int r = 0; r < 4; ++r) {
        if (mask & 8) at(0, r) = 2.0f * at(1, r) - at(2, r);
        if (mask & 2) at(3, r) = 2.0f * at(2, r) - at(1, r);
    }
    return p;
}

void addSemiSharpCreaseLeaf(PatchCullLeaves& out, const BicubicPoints& real, uint32_t boundaryMask, uint32_t creaseBit) {
    // Sharp surface + c d, c in [0, 1/2], d = real - sharp beyond the crease (zero elsewhere).
    const BicubicPoints sharp = withPhantoms(real, boundaryMask | creaseBit);
    const BicubicPoints smooth = withPhantoms(real, boundaryMask);
    CullBox box = boxOf(bsplineToBezier(sharp));
    CullBox d{glm::vec3(0.0f), glm::vec3(0.0f)};
    for (uint32_t k = 0; k < 16; ++k) {
        const glm::vec3 difference = 0.5f * (smooth[k] - sharp[k]);
        d.lo = glm::min(d.lo, difference), d.hi = glm::max(d.hi, difference);
    }
    box.lo += d.lo;
    box.hi += d.hi;
    addConelessBox(out, box);
}

CullBox PatchCullSet::bounds() const {
    CullBox all{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (const CullBox& box : boxes)
        if (box.lo.x <= box.hi.x) grow(all, box);
    return all;
}

void appendAbsentPatch(PatchCullSet& set) {
    set.boxes.push_back(CullBox{glm::vec3(INFINITY), glm::vec3(-INFINITY)});
    set.tcones.push_back(NormalCone{});
    set.ncones.push_back(NormalCone{});
    set.origins.push_back(glm::vec3(0.0f));
    set.planeRanges.push_back({});
    set.coneLeafRanges.push_back({});
    set.flatRanges.push_back({});
}

namespace {

// Writes `values` into `array` at `range` when it holds exactly as many, else at the end.
template <class T, class Values>
void place(std::vector<T>& array, LeafRange& range, const Values& values) {
    if (range.count != values.size()) range = LeafRange{uint32_t(array.size()), uint32_t(values.size())};
    if (range.first == array.size()) array.insert(array.end(), values.begin(), values.end());
    else std::copy(values.begin(), values.end(), array.begin() + range.first);
}

// Entry `entry` from its leaves (relative to `origin`), its leaves written over its old ones
// where they fit.
void setPatch(PatchCullSet& set, uint32_t entry, const PatchCullLeaves& leaves, const glm::vec3& origin) {
    set.boxes[entry] = CullBox{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    set.tcones[entry] = set.ncones[entry] = NormalCone{};
    set.origins[entry] = glm::vec3(0.0f);
    const bool withLeaves = leaves.box.lo.x <= leaves.box.hi.x && !leaves.coneless;
    if (leaves.box.lo.x <= leaves.box.hi.x) {
        set.boxes[entry] = CullBox{leaves.box.lo + origin, leaves.box.hi + origin};
        set.origins[entry] = origin;
    }
    if (withLeaves) {
        set.tcones[entry] = unionOf(leaves.tcones);
        set.ncones[entry] = unionOf(leaves.ncones);
    }
    std::vector<ConeCullLeaf> cones;
    if (withLeaves)
        for (ConeCullLeaf leaf : leaves.coneLeaves) {
            leaf.box = CullBox{leaf.box.lo + origin, leaf.box.hi + origin};
            cones.push_back(leaf);
        }
    const std::span<const TangentPlanes> planes = withLeaves ? std::span<const TangentPlanes>(leaves.planes) : std::span<const TangentPlanes>();
    const std::span<const glm::vec4> flats = withLeaves ? std::span<const glm::vec4>(leaves.flats) : std::span<const glm::vec4>();
    place(set.planes, set.planeRanges[entry], planes);
    place(set.coneLeaves, set.coneLeafRanges[entry], cones);
    place(set.flats, set.flatRanges[entry], flats);
}

// The leaves the entries name, in entry order, and nothing else (when more than half of an
// array's leaves are no longer named).
template <class T>
void compactLeaves(std::vector<T>& array, std::vector<LeafRange>& ranges) {
    size_t named = 0;
    for (const LeafRange& r : ranges) named += r.count;
    if (2 * named >= array.size()) return;
    std::vector<T> kept;
    kept.reserve(named);
    for (LeafRange& r : ranges) {
        const uint32_t first = uint32_t(kept.size());
        kept.insert(kept.end(), array.begin() + r.first, array.begin() + r.first + r.count);
        r.first = first;
    }
    array = std::move(kept);
}

void compactSet(PatchCullSet& set) {
    compactLeaves(set.planes, set.planeRanges);
    compactLeaves(set.coneLeaves, set.coneLeafRanges);
    compactLeaves(set.flats, set.flatRanges);
}

}  // namespace

void appendPatch(PatchCullSet& set, const PatchCullLeaves& leaves, const glm::vec3& origin) {
    appendAbsentPatch(set);
    setPatch(set, set.size() - 1, leaves, origin);
}

void replacePatches(PatchCullSet& set, std::span<const uint32_t> entries, std::span<const PatchCullLeaves> leaves,
                    std::span<const glm::vec3> origins) {
    for (size_t k = 0; k < entries.size(); ++k) setPatch(set, entries[k], leaves[k], origins[k]);
    compactSet(set);
}

void renumberPatches(PatchCullSet& set, std::span<const uint32_t> previousOf) {
    PatchCullSet out;
    const size_t count = previousOf.size();
    out.boxes.reserve(count), out.tcones.reserve(count), out.ncones.reserve(count), out.origins.reserve(count);
    out.planeRanges.reserve(count), out.coneLeafRanges.reserve(count), out.flatRanges.reserve(count);
    for (uint32_t previous : previousOf) {
        if (previous >= set.size()) {
            appendAbsentPatch(out);
            continue;
        }
        out.boxes.push_back(set.boxes[previous]);
        out.tcones.push_back(set.tcones[previous]);
        out.ncones.push_back(set.ncones[previous]);
        out.origins.push_back(set.origins[previous]);
        out.planeRanges.push_back(set.planeRanges[previous]);
        out.coneLeafRanges.push_back(set.coneLeafRanges[previous]);
        out.flatRanges.push_back(set.flatRanges[previous]);
    }
    out.planes = std::move(set.planes);
    out.coneLeaves = std::move(set.coneLeaves);
    out.flats = std::move(set.flats);
    set = std::move(out);
    compactSet(set);
}

bool tangentPlanesBackFacing(const PatchCullSet& set, uint32_t entry, const glm::vec4& eye) {
    const uint32_t first = set.planeRanges[entry].first, last = first + set.planeRanges[entry].count;
    const uint32_t firstCone = set.coneLeafRanges[entry].first, lastCone = firstCone + set.coneLeafRanges[entry].count;
    const uint32_t firstFlat = set.flatRanges[entry].first, lastFlat = firstFlat + set.flatRanges[entry].count;
    if (first == last && firstCone == lastCone && firstFlat == lastFlat) return false;
    for (uint32_t k = firstCone; k < lastCone; ++k)
        if (!backFacing(set.coneLeaves[k].cone, set.coneLeaves[k].box, eye)) return false;
    // The planes are relative to the entry's origin: move the eye there (a direction stays).
    const glm::vec4 relative(glm::vec3(eye) - eye.w * set.origins[entry], eye.w);
    // A flat triangle's plane is a one-coefficient tangent-plane function.
    if (!tangentPlanesBackFacing(std::span<const glm::vec4>(set.flats).subspan(firstFlat, lastFlat - firstFlat), relative))
        return false;
    for (uint32_t k = first; k < last; ++k)
        if (!tangentPlanesBackFacing(set.planes[k], relative)) return false;
    return true;
}

bool backSideHidden(const CullBox& bounds, const glm::mat4& viewProjection, const glm::vec4& eye) {
    if (eye.w != 0.0f) {
        const glm::vec3 e = glm::vec3(eye) / eye.w;
        if (!glm::any(glm::lessThan(e, bounds.lo)) && !glm::any(glm::greaterThan(e, bounds.hi))) return false;
    }
    const CullFrustum frustum = frustumOf(viewProjection);
    const glm::vec4& nearPlane = frustum.planes[4];
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p(corner & 1 ? bounds.hi.x : bounds.lo.x, corner & 2 ? bounds.hi.y : bounds.lo.y,
                          corner & 4 ? bounds.hi.z : bounds.lo.z);
        if (!(glm::dot(glm::vec3(nearPlane), p) + nearPlane.w > 0.0f)) return false;
    }
    return true;
}

std::vector<uint32_t> cullPatches(const PatchCullSet& set, CullMethod method, const glm::mat4& viewProjection,
                                  const glm::vec4& eye, bool backPatch, std::span<const float> margins,
                                  CullCounts* counts) {
    std::vector<uint32_t> culled;
    CullCounts local;
    CullCounts& count = counts ? *counts : local;
    count = CullCounts{};
    if (method == CullMethod::None) return culled;
    const CullFrustum frustum = frustumOf(viewProjection);
    // Back-patch tests need the eye outside the surface (outside the box of every entry), and
    // the near plane clear of it: where the near plane cuts the surface open, its back side
    // shows through the cut.
    // A displaced surface (margins) is tested against the frustum only: the cones bound the
    // undisplaced surface's normals, and a displacement can turn pieces of it inside out.
    if (!margins.empty()) backPatch = false;
    if (backPatch && method >= CullMethod::TCone) backPatch = backSideHidden(set.bounds(), viewProjection, eye);
    for (uint32_t s = 0; s < set.size(); ++s) {
        CullBox box = set.boxes[s];
        if (!(box.lo.x <= box.hi.x)) continue;
        ++count.tested;
        const float margin = margins.empty() ? 0.0f : margins[s];
        box.lo -= glm::vec3(margin), box.hi += glm::vec3(margin);
        if (outsideFrustum(frustum, box)) {
            ++count.frustum;
            culled.push_back(s);
            continue;
        }
        if (method < CullMethod::TCone) continue;
        // Entries without any back-patch test (coneless ones have no cone and no leaf tests).
        const bool testable = set.tcones[s].bounded || set.ncones[s].bounded || set.planeRanges[s].count != 0 ||
                              set.coneLeafRanges[s].count != 0 || set.flatRanges[s].count != 0;
        if (!backPatch || !testable) {
            ++count.frustumOnly;
            continue;
        }
        // Each back-patch method also takes the cheaper ones' answers (all are conservative), so
        // what tcone culls ncone culls too, and pplane both.
        bool away = backFacing(set.tcones[s], box, eye);
        if (!away && method >= CullMethod::NCone) away = backFacing(set.ncones[s], box, eye);
        if (!away && method == CullMethod::PPlane) away = tangentPlanesBackFacing(set, s, eye);
        if (away) {
            ++count.backFacing;
            culled.push_back(s);
        }
    }
    return culled;
}

}  // namespace qp
