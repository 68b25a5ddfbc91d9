#include "pn.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "plans/face_config.h"

namespace qp {

namespace {

glm::dvec3 safeNormalize(glm::dvec3 v) {
    double length = glm::length(v);
    return length > 0.0 ? v / length : glm::dvec3(0.0);
}

std::vector<glm::dvec3> angleWeightedNormals(const Cage& cage) {
    std::vector<glm::dvec3> normals(cage.vertexCount(), glm::dvec3(0.0));
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        if (cage.isHole(f)) continue;
        const uint32_t n = cage.faceSize(f);
        const uint32_t* v = cage.faceBegin(f);
        for (uint32_t k = 0; k < n; ++k) {
            glm::dvec3 p(cage.positions[v[k]]), next(cage.positions[v[(k + 1) % n]]), prev(cage.positions[v[(k + n - 1) % n]]);
            glm::dvec3 a = next - p, b = prev - p;
            double la = glm::length(a), lb = glm::length(b);
            if (la == 0.0 || lb == 0.0) continue;
            glm::dvec3 corner = safeNormalize(glm::cross(a, b));
            double angle = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
            normals[v[k]] += angle * corner;
        }
    }
    for (glm::dvec3& n : normals) n = safeNormalize(n);
    return normals;
}

// Appends the 10 + 6 control points of one PN triangle.
void addTriangle(PnPatches& out, glm::dvec3 P1, glm::dvec3 P2, glm::dvec3 P3, glm::dvec3 N1, glm::dvec3 N2, glm::dvec3 N3) {
    auto edge = [](glm::dvec3 Pi, glm::dvec3 Pj, glm::dvec3 Ni) { return (2.0 * Pi + Pj - glm::dot(Pj - Pi, Ni) * Ni) / 3.0; };
    glm::dvec3 b210 = edge(P1, P2, N1), b120 = edge(P2, P1, N2), b021 = edge(P2, P3, N2), b012 = edge(P3, P2, N3),
               b102 = edge(P3, P1, N3), b201 = edge(P1, P3, N1);
    glm::dvec3 E = (b210 + b120 + b021 + b012 + b102 + b201) / 6.0, V = (P1 + P2 + P3) / 3.0;
    glm::dvec3 b111 = E + (E - V) / 2.0;
    for (glm::dvec3 p : {P1, P2, P3, b210, b120, b021, b012, b102, b201, b111}) out.positions.push_back(glm::vec3(p));
    auto mid = [](glm::dvec3 Pi, glm::dvec3 Pj, glm::dvec3 Ni, glm::dvec3 Nj) {
        glm::dvec3 d = Pj - Pi;
        double dd = glm::dot(d, d);
        double vij = dd > 0.0 ? 2.0 * glm::dot(d, Ni + Nj) / dd : 0.0;
        return safeNormalize(Ni + Nj - vij * d);
    };
    for (glm::dvec3 n : {N1, N2, N3, mid(P1, P2, N1, N2), mid(P2, P3, N2, N3), mid(P3, P1, N3, N1)})
        out.normals.push_back(glm::vec3(n));
}

// Barycentrics of a sub-face point and their (u, v) derivatives, with the triangle they are on.
struct TrianglePoint {
    uint32_t triangle = 0;
    glm::dvec3 b{0.0}, bu{0.0}, bv{0.0};
};

TrianglePoint locate(const PnPatches& p, uint32_t subface, double u, double v) {
    const auto& first = p.faceFirstSubface;
    const uint32_t face = uint32_t(std::upper_bound(first.begin(), first.end(), subface) - first.begin()) - 1;
    const uint32_t k = subface - first[face], n = p.faceSize[face], t0 = p.faceFirstTriangle[face];
    TrianglePoint at;
    if (n == 3) {
        glm::dvec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        glm::dvec3 q0 = e[k], q1 = 0.5 * (e[k] + e[(k + 1) % 3]), q2(1.0 / 3.0), q3 = 0.5 * (e[k] + e[(k + 2) % 3]);
        at.triangle = t0;
        at.b = (1 - u) * (1 - v) * q0 + u * (1 - v) * q1 + u * v * q2 + (1 - u) * v * q3;
        at.bu = (1 - v) * (q1 - q0) + v * (q2 - q3);
        at.bv = (1 - u) * (q3 - q0) + u * (q2 - q1);
    } else if (n == 4 && !p.quadDiagonal[face]) {
        if (u >= v) at = {t0, {1 - u, u - v, v}, {-1, 1, 0}, {0, -1, 1}};
        else at = {t0 + 1, {1 - v, u, v - u}, {0, 1, -1}, {-1, 0, 1}};
    } else if (n == 4) {
        if (u + v <= 1) at = {t0, {1 - u - v, u, v}, {-1, 1, 0}, {-1, 0, 1}};
        else at = {t0 + 1, {1 - v, u + v - 1, 1 - u}, {0, 1, -1}, {-1, 1, 0}};
    } else {
        if (u >= v) at = {t0 + k, {1 - u / 2 - v / 2, u / 2 - v / 2, v}, {-0.5, 0.5, 0}, {-0.5, -0.5, 1}};
        else at = {t0 + (k + n - 1) % n, {v / 2 - u / 2, 1 - u / 2 - v / 2, u}, {-0.5, -0.5, 1}, {0.5, -0.5, 0}};
    }
    return at;
}

struct TriangleEval {
    glm::dvec3 position{0.0}, d[3]{}, normal{0.0};  // d[i] = dP/db_i
};

TriangleEval evalTriangle(const PnPatches& p, uint32_t t, glm::dvec3 b) {
    const glm::vec3* c = &p.positions[size_t(t) * PnPatches::kPositionPoints];
    glm::dvec3 b300(c[0]), b030(c[1]), b003(c[2]), b210(c[3]), b120(c[4]), b021(c[5]), b012(c[6]), b102(c[7]),
        b201(c[8]), b111(c[9]);
    const double x = b.x, y = b.y, z = b.z;
    TriangleEval e;
    e.position = x * x * x * b300 + y * y * y * b030 + z * z * z * b003 + 3 * x * x * y * b210 + 3 * x * y * y * b120 +
                 3 * y * y * z * b021 + 3 * y * z * z * b012 + 3 * x * z * z * b102 + 3 * x * x * z * b201 +
                 6 * x * y * z * b111;
    e.d[0] = 3 * x * x * b300 + 6 * x * y * b210 + 3 * y * y * b120 + 3 * z * z * b102 + 6 * x * z * b201 + 6 * y * z * b111;
    e.d[1] = 3 * y * y * b030 + 3 * x * x * b210 + 6 * x * y * b120 + 6 * y * z * b021 + 3 * z * z * b012 + 6 * x * z * b111;
    e.d[2] = 3 * z * z * b003 + 3 * y * y * b021 + 6 * y * z * b012 + 6 * x * z * b102 + 3 * x * x * b201 + 6 * x * y * b111;
    const glm::vec3* n = &p.normals[size_t(t) * PnPatches::kNormalPoints];
    e.normal = safeNormalize(x * x * glm::dvec3(n[0]) + y * y * glm::dvec3(n[1]) + z * z * glm::dvec3(n[2]) +
                             2 * x * y * glm::dvec3(n[3]) + 2 * y * z * glm::dvec3(n[4]) + 2 * x * z * glm::dvec3(n[5]));
    return e;
}

}  // namespace

Result<PnPatches> buildPn(const Cage& cage, const std::string& source) {
    const auto start = std::chrono::steady_clock::now();
    if (Status valid = validateCage(cage, source); !valid) return valid.error();
    PnPatches out;
    std::vector<glm::dvec3> normals = angleWeightedNormals(cage);
    out.vertexNormals.assign(normals.begin(), normals.end());
    const uint32_t faces = cage.faceCount();
    out.faceFirstTriangle.assign(faces + 1, 0);
    out.faceFirstSubface.assign(faces + 1, 0);
    out.faceSize.resize(faces);
    out.quadDiagonal.assign(faces, 0);
    auto P = [&](uint32_t v) { return glm::dvec3(cage.positions[v]); };
    for (uint32_t f = 0; f < faces; ++f) {
        const uint32_t n = cage.faceSize(f);
        const uint32_t* v = cage.faceBegin(f);
        out.faceSize[f] = n;
        out.faceFirstSubface[f + 1] = out.faceFirstSubface[f] + subfaceCount(n);
        uint32_t before = uint32_t(out.triangleFace.size());
        if (!cage.isHole(f)) {
            if (n == 3) {
                addTriangle(out, P(v[0]), P(v[1]), P(v[2]), normals[v[0]], normals[v[1]], normals[v[2]]);
            } else if (n == 4) {
                bool oneThree = glm::length(P(v[1]) - P(v[3])) < glm::length(P(v[0]) - P(v[2]));
                out.quadDiagonal[f] = oneThree;
                const uint32_t tris[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{0, 1, 3}, {1, 2, 3}}};
                for (const auto& t : tris[oneThree])
                    addTriangle(out, P(v[t[0]]), P(v[t[1]]), P(v[t[2]]), normals[v[t[0]]], normals[v[t[1]]], normals[v[t[2]]]);
                ++out.stats.quadsSplit;
            } else {
                glm::dvec3 centre(0.0), centreNormal(0.0);
                for (uint32_t k = 0; k < n; ++k) {
                    centre += P(v[k]);
                    centreNormal += normals[v[k]];
                }
                centre /= double(n);
                centreNormal = safeNormalize(centreNormal);
                for (uint32_t k = 0; k < n; ++k)
                    addTriangle(out, P(v[k]), P(v[(k + 1) % n]), centre, normals[v[k]], normals[v[(k + 1) % n]], centreNormal);
                ++out.stats.fannedFaces;
            }
        }
        for (uint32_t t = before; t < out.positions.size() / PnPatches::kPositionPoints; ++t) out.triangleFace.push_back(f);
        out.faceFirstTriangle[f + 1] = uint32_t(out.triangleFace.size());
    }
    out.stats.triangles = uint32_t(out.triangleFace.size());
    out.stats.controlPoints = out.stats.triangles * (PnPatches::kPositionPoints + PnPatches::kNormalPoints);
    out.stats.ignoredCreases = uint32_t(cage.creases.size());
    out.stats.ignoredCorners = uint32_t(cage.corners.size());
    out.stats.setupMilliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
}

PnSample evaluatePnTriangle(const PnPatches& patches, uint32_t triangle, glm::vec3 barycentric) {
    TriangleEval e = evalTriangle(patches, triangle, glm::dvec3(barycentric));
    PnSample s;
    s.position = glm::vec3(e.position);
    s.normal = glm::vec3(e.normal);
    s.valid = true;
    return s;
}

PnSample evaluatePn(const PnPatches& patches, uint32_t subface, float u, float v) {
    const auto& first = patches.faceFirstSubface;
    const uint32_t face = uint32_t(std::upper_bound(first.begin(), first.end(), subface) - first.begin()) - 1;
    if (patches.faceFirstTriangle[face] == patches.faceFirstTriangle[face + 1]) return PnSample{};  // hole
    TrianglePoint at = locate(patches, subface, u, v);
    TriangleEval e = evalTriangle(patches, at.triangle, at.b);
    PnSample s;
    s.position = glm::vec3(e.position);
    s.du = glm::vec3(at.bu.x * e.d[0] + at.bu.y * e.d[1] + at.bu.z * e.d[2]);
    s.dv = glm::vec3(at.bv.x * e.d[0] + at.bv.y * e.d[1] + at.bv.z * e.d[2]);
    s.normal = glm::vec3(e.normal);
    s.valid = true;
    return s;
}

const char* pnRestrictions() {
    return "PN-triangles interpolate the cage (positions and averaged vertex normals) instead of "
           "approximating the Catmull-Clark limit, so they stand far from it on coarse cages. C0 "
           "geometry with a separate continuous normal field; quads are split along the shorter "
           "diagonal, other polygons fanned around their centroid. Creases, corners and boundary "
           "rules are ignored (no neighbour information).";
}

}  // namespace qp
