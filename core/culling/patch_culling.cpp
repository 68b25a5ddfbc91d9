#include "culling/patch_culling.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

namespace qp {

namespace {

// Angles carry a margin for float rounding in the cone arithmetic: a cone or an angle a hair
// wider than exact only culls a hair less.
constexpr float kAngleMargin = 1e-4f;
constexpr float kHalfPi = 0.5f * std::numbers::pi_v<float>;

float angleBetweenUnit(const glm::vec3& a, const glm::vec3& b) {
    // atan2 resolves small angles that acos of a dot product cannot.
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

constexpr double kBinomial[9][9] = {
    {1}, {1, 1}, {1, 2, 1}, {1, 3, 3, 1}, {1, 4, 6, 4, 1}, {1, 5, 10, 10, 5, 1}, {1, 6, 15, 20, 15, 6, 1},
    {1, 7, 21, 35, 35, 21, 7, 1}, {1, 8, 28, 56, 70, 56, 28, 8, 1}};

// The weight of B^m_i B^n_k in B^(m+n)_(i+k).
constexpr double productWeight(int m, int i, int n, int k) {
    return kBinomial[m][i] * kBinomial[n][k] / kBinomial[m + n][i + k];
}

// productWeight(5, a, 3, c), what every tangent-plane coefficient sums with (a table: the loops
// below run for thousands of leaves when a view is first culled).
struct QuinticCubicWeights {
    double w[6][4];
    constexpr QuinticCubicWeights() : w{} {
        for (int a = 0; a < 6; ++a)
            for (int c = 0; c < 4; ++c) w[a][c] = productWeight(5, a, 3, c);
    }
};
constexpr QuinticCubicWeights kQuinticCubic;

// The Bernstein control vectors n(a, b), a along u, of the normal patch B_u x B_v (bidegree
// (5, 5)), in double.
std::array<glm::dvec3, 36> normalPatch(const BicubicPoints& p) {
    auto at = [&](int column, int row) { return glm::dvec3(p[4 * row + column]); };
    std::array<glm::dvec3, 36> n{};
    // B_u = 3 sum B2_i(u) B3_j(v) (P(i+1, j) - P(i, j)); B_v = 3 sum B3_k(u) B2_l(v) (P(k, l+1) - P(k, l)).
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) {
            const glm::dvec3 du = 3.0 * (at(i + 1, j) - at(i, j));
            for (int k = 0; k < 4; ++k)
                for (int l = 0; l < 3; ++l) {
                    const glm::dvec3 dv = 3.0 * (at(k, l + 1) - at(k, l));
                    const double weight = productWeight(2, i, 3, k) * productWeight(3, j, 2, l);
                    n[6 * (j + l) + (i + k)] += weight * glm::cross(du, dv);
                }
        }
    return n;
}

NormalCone coneOfUnit(std::span<const glm::vec3> units) {
    glm::vec3 sum(0.0f);
    for (const glm::vec3& u : units) sum += u;
    NormalCone cone;
    const float length = glm::length(sum);
    if (units.empty() || !(length > 1e-6f * float(units.size()))) return cone;
    cone.axis = sum / length;
    float widest = 0.0f;
    for (const glm::vec3& u : units) widest = std::max(widest, angleBetweenUnit(cone.axis, u));
    cone.halfAngle = widest + kAngleMargin;
    cone.bounded = cone.halfAngle < kHalfPi;
    return cone;
}

}  // namespace

BicubicPoints bsplineToBezier(const BicubicPoints& b) {
    // Per 4 points of a uniform cubic B-spline span, the Bézier points of the same curve.
    auto convert = [](const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3) {
        return std::array<glm::vec3, 4>{(p0 + 4.0f * p1 + p2) / 6.0f, (2.0f * p1 + p2) / 3.0f, (p1 + 2.0f * p2) / 3.0f,
                                        (p1 + 4.0f * p2 + p3) / 6.0f};
    };
    BicubicPoints rows{}, out{};
    for (int r = 0; r < 4; ++r) {
        const auto c = convert(b[4 * r], b[4 * r + 1], b[4 * r + 2], b[4 * r + 3]);
        for (int i = 0; i < 4; ++i) rows[4 * r + i] = c[i];
    }
    for (int i = 0; i < 4; ++i) {
        const auto c = convert(rows[i], rows[4 + i], rows[8 + i], rows[12 + i]);
        for (int r = 0; r < 4; ++r) out[4 * r + i] = c[r];
    }
    return out;
}

CullBox boxOf(std::span<const glm::vec3> points) {
    CullBox box{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (const glm::vec3& p : points) box.lo = glm::min(box.lo, p), box.hi = glm::max(box.hi, p);
    return box;
}

CullFrustum frustumOf(const glm::mat4& m) {
    auto row = [&](int i) { return glm::vec4(m[0][i], m[1][i], m[2][i], m[3][i]); };
    return {{row(3) + row(0), row(3) - row(0), row(3) + row(1), row(3) - row(1), row(2), row(3) - row(2)}};
}

bool outsideFrustum(const CullFrustum& frustum, const CullBox& box) {
    for (const glm::vec4& plane : frustum.planes) {
        // The box corner farthest along the plane's normal.
        const glm::vec3 far(plane.x >= 0.0f ? box.hi.x : box.lo.x, plane.y >= 0.0f ? box.hi.y : box.lo.y,
                            plane.z >= 0.0f ? box.hi.z : box.lo.z);
        if (glm::dot(glm::vec3(plane), far) + plane.w < 0.0f) return true;
    }
    return false;
}

NormalCone coneOfVectors(std::span<const glm::vec3> vectors) {
    std::vector<glm::vec3> units;
    units.reserve(vectors.size());
    for (const glm::vec3& v : vectors) {
        const float length = glm::length(v);
        if (length > 0.0f && std::isfinite(length)) units.push_back(v / length);
    }
    return coneOfUnit(units);
}

NormalCone normalConeOfTangents(const NormalCone& u, const NormalCone& v) {
    NormalCone cone;
    if (!u.bounded || !v.bounded) return cone;
    // With tangent cones of half-angles a, b whose axes make the angle t, and a + b < min(t,
    // pi - t), every u x v lies within g of the axes' cross product, where
    // sin g = sqrt(sin^2 a + 2 sin a sin b |cos t| + sin^2 b) / sin t.
    // |cos t|: u x v = -(u x -v), so the bound cannot change from t to pi - t; with the signed
    // cosine an obtuse t (a skewed frame, e.g. a PN triangle's edges, tangents at a valence-3
    // vertex) gave cones narrower than the normals they had to hold.
    const float t = angleBetweenUnit(u.axis, v.axis);
    const float a = u.halfAngle, b = v.halfAngle;
    if (!(a + b < std::min(t, std::numbers::pi_v<float> - t))) return cone;
    const float sa = std::sin(a), sb = std::sin(b);
    const float sine = std::sqrt(sa * sa + 2.0f * sa * sb * std::abs(std::cos(t)) + sb * sb) / std::sin(t);
    if (!(sine < 1.0f)) return cone;
    cone.axis = glm::normalize(glm::cross(u.axis, v.axis));
    cone.halfAngle = std::asin(sine) + kAngleMargin;
    cone.bounded = cone.halfAngle < kHalfPi;
    return cone;
}

NormalCone tangentCone(const BicubicPoints& p) {
    std::array<glm::vec3, 12> alongU, alongV;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 3; ++c) {
            alongU[3 * r + c] = p[4 * r + c + 1] - p[4 * r + c];
            alongV[3 * r + c] = p[4 * (c + 1) + r] - p[4 * c + r];
        }
    return normalConeOfTangents(coneOfVectors(alongU), coneOfVectors(alongV));
}

NormalCone cubicTriangleNormalCone(const CubicTrianglePoints& p) {
    // b_ijk (k = 3 - i - j) in CubicTrianglePoints' order, by [i][j].
    constexpr int kIndex[4][4] = {{2, 6, 5, 1}, {7, 9, 4, -1}, {8, 3, -1, -1}, {0, -1, -1, -1}};
    auto at = [&](int i, int j) { return p[size_t(kIndex[i][j])]; };
    std::array<glm::vec3, 6> towards2, towards3;
    size_t n = 0;
    for (int i = 0; i <= 2; ++i)
        for (int j = 0; i + j <= 2; ++j, ++n) {
            towards2[n] = at(i, j + 1) - at(i + 1, j);  // b_{i,j+1,k} - b_{i+1,j,k}, i + j + k = 2
            towards3[n] = at(i, j) - at(i + 1, j);      // b_{i,j,k+1} - b_{i+1,j,k}
        }
    return normalConeOfTangents(coneOfVectors(towards2), coneOfVectors(towards3));
}

NormalCone normalPatchCone(const BicubicPoints& bezier) {
    std::array<glm::vec3, 36> vectors;
    const std::array<glm::dvec3, 36> n = normalPatch(bezier);
    for (size_t k = 0; k < n.size(); ++k) vectors[k] = glm::vec3(n[k]);
    return coneOfVectors(vectors);
}

bool backFacing(const NormalCone& cone, const CullBox& box, const glm::vec4& eye) {
    if (!cone.bounded) return false;
    if (eye.w == 0.0f) {
        const glm::vec3 toViewer = glm::normalize(glm::vec3(eye));
        return angleBetweenUnit(cone.axis, toViewer) > kHalfPi + cone.halfAngle + kAngleMargin;
    }
    // Every direction from a point of the box to the eye lies within `spread` of the direction
    // from the box's centre (the box's bounding sphere seen from the eye).
    const glm::vec3 e = glm::vec3(eye) / eye.w;
    const glm::vec3 centre = 0.5f * (box.lo + box.hi);
    const float radius = 0.5f * glm::length(box.hi - box.lo);
    const glm::vec3 toEye = e - centre;
    const float distance = glm::length(toEye);
    if (!(distance > radius)) return false;
    const float spread = std::asin(std::min(1.0f, radius / distance));
    return angleBetweenUnit(cone.axis, toEye / distance) > kHalfPi + cone.halfAngle + spread + kAngleMargin;
}

TangentPlanes tangentPlanesOf(const BicubicPoints& bezier) {
    const std::array<glm::dvec3, 36> n = normalPatch(bezier);
    // g = N . (E - w B) = sum B5_a B5_b B3_c B3_d n(a, b) . (E - w P(c, d)): per coefficient
    // a = sum of weighted n(a, b), b = sum of weighted n(a, b) . P(c, d).
    std::array<glm::dvec4, 81> sums{};
    std::array<glm::dvec3, 16> points;
    for (int k = 0; k < 16; ++k) points[k] = glm::dvec3(bezier[k]);
    for (int b = 0; b < 6; ++b)
        for (int a = 0; a < 6; ++a) {
            const glm::dvec3& normal = n[6 * b + a];
            for (int d = 0; d < 4; ++d)
                for (int c = 0; c < 4; ++c) {
                    const double weight = kQuinticCubic.w[a][c] * kQuinticCubic.w[b][d];
                    sums[9 * (b + d) + (a + c)] += weight * glm::dvec4(normal, glm::dot(normal, points[4 * d + c]));
                }
        }
    TangentPlanes planes;
    for (int k = 0; k < 81; ++k) planes[k] = glm::vec4(sums[k]);
    return planes;
}

bool tangentPlanesBackFacing(std::span<const glm::vec4> planes, const glm::vec4& eye) {
    const glm::vec3 e(eye);
    for (const glm::vec4& p : planes) {
        const glm::vec3 a(p);
        const float g = glm::dot(a, e) - p.w * eye.w;
        // The coefficients are float: negative by more than their rounding could move them.
        const float rounding = 1e-5f * (glm::length(a) * glm::length(e) + std::abs(p.w * eye.w));
        if (!(g < -rounding)) return false;
    }
    return true;
}

}  // namespace qp
