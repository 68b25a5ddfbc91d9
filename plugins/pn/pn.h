// PN-triangles: Vlachos, Peters, Boyd, Mitchell 2001, "Curved PN Triangles" (C §1.8.2, S §3.6.1,
// digest §1.4). Per triangle a cubic Bezier triangle (10 points) for position and a quadratic
// one (6 points) for normals, built from the three vertex positions and vertex normals only: no
// neighbours, C0 geometry, continuous normals, interpolates the cage. It does not approximate
// the Catmull-Clark limit (it interpolates the cage vertices, the limit does not pass through
// them): large errors against the exact limit are expected.
//
// Vertex normals: angle-weighted average of the corner normals of the faces around the vertex
// (corner normal = normalize((next - v) x (prev - v)), weight = the corner's angle); holes do
// not count. Per triangle (P1, P2, P3 with normals N1, N2, N3), w_ij = (P_j - P_i) . N_i:
//   b300 = P1, b210 = (2 P1 + P2 - w12 N1) / 3, ... (the six edge points alike)
//   b111 = E + (E - V) / 2, E = average of the six edge points, V = average of the corners
//   n200 = N1, n110 = normalize(N1 + N2 - v12 (P2 - P1)), v12 = 2 (P2 - P1).(N1 + N2) / |P2 - P1|^2
//
// Faces and (sub-face, u, v):
//   - triangle: one PN triangle (v0, v1, v2). Its 3 sub-faces are the quads (v_k, mid(v_k,
//     v_k+1), centroid, mid(v_k-1, v_k)) in barycentric space, mapped bilinearly: the point is
//     (1-u)(1-v) e_k + u(1-v) (e_k + e_k+1)/2 + uv (1,1,1)/3 + (1-u)v (e_k + e_k-1)/2.
//   - quad (one sub-face): split along its shorter diagonal (0-2 on a tie), piecewise affine:
//       diagonal 0-2: u >= v -> triangle (v0, v1, v2), barycentrics (1-u, u-v, v);
//                     u <  v -> triangle (v0, v2, v3), barycentrics (1-v, u, v-u);
//       diagonal 1-3: u+v <= 1 -> triangle (v0, v1, v3), barycentrics (1-u-v, u, v);
//                     u+v >  1 -> triangle (v1, v2, v3), barycentrics (1-v, u+v-1, 1-u).
//   - n-gon, n >= 5: a fan of n triangles (v_k, v_k+1, c) around the centroid c of its
//     vertices, whose normal is the normalised sum of the vertex normals. Sub-face k (the quad
//     v_k, mid_k, c, mid_k-1) is cut along v_k-c, piecewise affine:
//       u >= v -> triangle k   (v_k, v_k+1, c): barycentrics (1 - u/2 - v/2, u/2 - v/2, v);
//       u <  v -> triangle k-1 (v_k-1, v_k, c): barycentrics (v/2 - u/2, 1 - u/2 - v/2, u).
// Derivatives in the sub-face frame follow by the chain rule through these maps.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

struct PnStats {
    uint32_t triangles = 0, controlPoints = 0;  // control points: 10 position + 6 normal each
    uint32_t quadsSplit = 0, fannedFaces = 0;
    uint32_t ignoredCreases = 0, ignoredCorners = 0;
    double setupMilliseconds = 0.0;
};

struct PnPatches {
    static constexpr uint32_t kPositionPoints = 10, kNormalPoints = 6;
    // Per triangle: b300 b030 b003 b210 b120 b021 b012 b102 b201 b111 (b_ijk weights P1^i P2^j P3^k)
    std::vector<glm::vec3> positions;
    // Per triangle: n200 n020 n002 n110 n011 n101
    std::vector<glm::vec3> normals;
    std::vector<uint32_t> triangleFace;      // source face of each triangle
    std::vector<uint32_t> faceFirstTriangle; // per face (faces + 1); holes get none
    std::vector<uint32_t> faceFirstSubface;  // per face (faces + 1), PlannedCage's numbering
    std::vector<uint32_t> faceSize;
    std::vector<uint8_t> quadDiagonal;       // per face: 1 if a quad is split along 1-3
    std::vector<glm::vec3> vertexNormals;    // the cage's, as used
    PnStats stats;
};

struct PnSample {
    glm::vec3 position{0.0f}, du{0.0f}, dv{0.0f};  // geometry patch, sub-face frame
    glm::vec3 normal{0.0f};                        // the quadratic normal patch, normalised
    bool valid = false;                            // false on holes
};

Result<PnPatches> buildPn(const Cage& cage, const std::string& source = "cage");

PnSample evaluatePn(const PnPatches& patches, uint32_t subface, float u, float v);
// Barycentrics (b1, b2, b3) on triangle `triangle` (b1 + b2 + b3 = 1).
PnSample evaluatePnTriangle(const PnPatches& patches, uint32_t triangle, glm::vec3 barycentric);

const char* pnRestrictions();

}  // namespace qp
