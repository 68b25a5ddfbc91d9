// Small cages built in code, so the core tests never depend on files outside the project.
#pragma once

#include <cmath>
#include <numbers>

#include "mesh/cage.h"

namespace qp::test {

// A closed torus of columns x rows quads, every vertex valence 4 (a regular cage without
// boundary), slightly wavy so no patch is planar.
inline Cage makeTorus(uint32_t columns = 12, uint32_t rows = 6, double major = 2.0, double minor = 0.7) {
    Cage cage;
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < columns; ++i) {
            double a = 2.0 * std::numbers::pi * i / columns, b = 2.0 * std::numbers::pi * j / rows;
            double r = minor * (1.0 + 0.15 * std::sin(3.0 * a + b));
            cage.positions.push_back(glm::vec3(float((major + r * std::cos(b)) * std::cos(a)),
                                               float((major + r * std::cos(b)) * std::sin(a)), float(r * std::sin(b))));
        }
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < columns; ++i) {
            uint32_t i1 = (i + 1) % columns, j1 = (j + 1) % rows;
            uint32_t quad[4] = {j * columns + i, j * columns + i1, j1 * columns + i1, j1 * columns + i};
            cage.addFace(quad, 4);
        }
    return cage;
}

// n x n unit quads in the xy-plane, with a gentle bump of height `bump` so surfaces are not flat.
inline Cage makeGrid(uint32_t n, float bump = 0.3f) {
    Cage cage;
    for (uint32_t y = 0; y <= n; ++y)
        for (uint32_t x = 0; x <= n; ++x)
            cage.positions.push_back(
                {float(x), float(y), bump == 0.0f ? 0.0f : bump * std::sin(float(x) * 1.3f) * std::cos(float(y) * 0.7f)});
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            uint32_t v = y * (n + 1) + x;
            uint32_t quad[4] = {v, v + 1, v + n + 2, v + n + 1};
            cage.addFace(quad, 4);
        }
    return cage;
}

// n x n unit quads in the plane z = 0: a flat limit surface inside (normal along z).
inline Cage makeFlatGrid(uint32_t n) { return makeGrid(n, 0.0f); }

inline Cage makeCube() {
    Cage cage;
    cage.positions = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                      {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    uint32_t faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    for (auto& f : faces) cage.addFace(f, 4);
    return cage;
}

// A cube whose faces are split 3 x 3, so each face has regular interior vertices and the
// corners are valence-3 extraordinary vertices surrounded by regular faces.
inline Cage makeSubdividedCube(uint32_t n = 3) {
    Cage cage;
    auto index = [&](int x, int y, int z) -> uint32_t {
        glm::vec3 p{float(x) / float(n) * 2.0f - 1.0f, float(y) / float(n) * 2.0f - 1.0f, float(z) / float(n) * 2.0f - 1.0f};
        for (uint32_t i = 0; i < cage.positions.size(); ++i)
            if (cage.positions[i] == p) return i;
        cage.positions.push_back(p);
        return uint32_t(cage.positions.size() - 1);
    };
    int m = int(n);
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            for (int a = 0; a < m; ++a)
                for (int b = 0; b < m; ++b) {
                    int corners[4][2] = {{a, b}, {a + 1, b}, {a + 1, b + 1}, {a, b + 1}};
                    uint32_t quad[4];
                    for (int k = 0; k < 4; ++k) {
                        int c[3];
                        c[axis] = side * m;
                        c[(axis + 1) % 3] = corners[side ? k : 3 - k][0];
                        c[(axis + 2) % 3] = corners[side ? k : 3 - k][1];
                        quad[k] = index(c[0], c[1], c[2]);
                    }
                    cage.addFace(quad, 4);
                }
    return cage;
}

// A grid whose centre quad is replaced by a pentagon-triangle pair, giving non-quads and
// valence-5 / valence-3 vertices inside a boundary.
inline Cage makeMixedGrid() {
    Cage cage = makeGrid(4);
    // Replace quad (1,1) [vertices 6,7,12,11] by a triangle and a pentagon sharing a new vertex.
    uint32_t centre = uint32_t(cage.positions.size());
    cage.positions.push_back({1.5f, 1.5f, 0.4f});
    Cage out;
    out.positions = cage.positions;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        if (f == 5) continue;  // quad 6,7,12,11
        out.addFace(cage.faceBegin(f), cage.faceSize(f));
    }
    uint32_t tri[3] = {6, 7, centre};
    uint32_t pent[4] = {7, 12, 11, 6};
    out.addFace(tri, 3);
    uint32_t pentagon[5] = {pent[0], pent[1], pent[2], pent[3], centre};
    out.addFace(pentagon, 5);
    return out;
}

// EVs, an n-gon next to quads, semi-sharp and infinite creases, a corner, a hole, a boundary.
inline Cage makeFeatureCage() {
    Cage cage = makeMixedGrid();
    for (uint32_t x = 15; x < 19; ++x) cage.setEdgeSharpness(x, x + 1, 2.5f);  // an interior grid line
    cage.setEdgeSharpness(12, 13, kInfiniteSharpness);
    cage.setVertexSharpness(24, 3.0f);
    cage.setHole(0, true);
    return cage;
}

}  // namespace qp::test
