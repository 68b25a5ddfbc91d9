#include "patch_cull_set.h"

#include <algorithm>
#include <cmath>

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
    // Orthographic: depth grows away from the viewer along row 2.
    return glm::vec4(-glm::normalize(glm::vec3(m[0][2], m[1][2], m[2][2])), 0.0f);
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

void addBezierLeaf(PatchCullLeaves& out, const BicubicPoints& bezier, bool reversed) {
    grow(out.box, boxOf(bezier));
    NormalCone t = tangentCone(bezier), n = normalPatchCone(bezier);
    TangentPlanes planes = tangentPlanesOf(bezier);
    if (reversed) {
        t.axis = -t.axis, n.axis = -n.axis;
        for (glm::vec4& p : planes) p = -p;
    }
    out.tcones.push_back(t);
    out.ncones.push_back(n);
    out.planes.push_back(planes);
}

void addGregoryLeaf(PatchCullLeaves& out, const std::array<glm::vec3, 20>& g, bool reversed) {
    CullBox box{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (const glm::vec3& p : g) grow(box, CullBox{p, p});
    grow(out.box, box);
    NormalCone cone = gregoryNormalCone(g);
    if (reversed) cone.axis = -cone.axis;
    out.tcones.push_back(cone);
    out.ncones.push_back(cone);
    out.gregories.push_back({cone, box});
}

void addConelessBox(PatchCullLeaves& out, const CullBox& box) {
    grow(out.box, box);
    out.coneless = true;
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
    set.planeOffsets.push_back(uint32_t(set.planes.size()));
    set.gregoryOffsets.push_back(uint32_t(set.gregories.size()));
}

void appendPatch(PatchCullSet& set, const PatchCullLeaves& leaves, const glm::vec3& origin) {
    appendAbsentPatch(set);
    if (!(leaves.box.lo.x <= leaves.box.hi.x)) return;
    const uint32_t entry = set.size() - 1;
    set.boxes[entry] = CullBox{leaves.box.lo + origin, leaves.box.hi + origin};
    set.origins[entry] = origin;
    if (leaves.coneless) return;
    set.tcones[entry] = unionOf(leaves.tcones);
    set.ncones[entry] = unionOf(leaves.ncones);
    set.planes.insert(set.planes.end(), leaves.planes.begin(), leaves.planes.end());
    set.planeOffsets[entry + 1] = uint32_t(set.planes.size());
    for (GregoryCullLeaf leaf : leaves.gregories) {
        leaf.box = CullBox{leaf.box.lo + origin, leaf.box.hi + origin};
        set.gregories.push_back(leaf);
    }
    set.gregoryOffsets[entry + 1] = uint32_t(set.gregories.size());
}

bool tangentPlanesBackFacing(const PatchCullSet& set, uint32_t entry, const glm::vec4& eye) {
    const uint32_t first = set.planeOffsets[entry], last = set.planeOffsets[entry + 1];
    const uint32_t firstGregory = set.gregoryOffsets[entry], lastGregory = set.gregoryOffsets[entry + 1];
    if (first == last && firstGregory == lastGregory) return false;
    for (uint32_t k = firstGregory; k < lastGregory; ++k)
        if (!backFacing(set.gregories[k].cone, set.gregories[k].box, eye)) return false;
    // The planes are relative to the entry's origin: move the eye there (a direction stays).
    const glm::vec4 relative(glm::vec3(eye) - eye.w * set.origins[entry], eye.w);
    for (uint32_t k = first; k < last; ++k)
        if (!tangentPlanesBackFacing(set.planes[k], relative)) return false;
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
    if (backPatch && method >= CullMethod::TCone) {
        const CullBox all = set.bounds();
        if (eye.w != 0.0f) {
            const glm::vec3 e = glm::vec3(eye) / eye.w;
            backPatch = glm::any(glm::lessThan(e, all.lo)) || glm::any(glm::greaterThan(e, all.hi));
        }
        const glm::vec4& nearPlane = frustum.planes[4];
        for (int corner = 0; corner < 8 && backPatch; ++corner) {
            const glm::vec3 p(corner & 1 ? all.hi.x : all.lo.x, corner & 2 ? all.hi.y : all.lo.y, corner & 4 ? all.hi.z : all.lo.z);
            backPatch = glm::dot(glm::vec3(nearPlane), p) + nearPlane.w > 0.0f;
        }
    }
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
        const bool testable = set.tcones[s].bounded || set.ncones[s].bounded ||
                              set.planeOffsets[s] != set.planeOffsets[s + 1] || set.gregoryOffsets[s] != set.gregoryOffsets[s + 1];
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
