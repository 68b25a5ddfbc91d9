#include "mesh/generated_cage.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

namespace qp {

namespace {

constexpr float kPi = 3.14159265358979f;

// Uniform in [0, 1), from the top 24 bits (exactly representable in a float).
float unit(std::mt19937& rng) { return float(rng() >> 8) * (1.0f / 16777216.0f); }

// `count` distinct indices below `n`, in random order (partial Fisher-Yates).
std::vector<uint32_t> pickDistinct(std::mt19937& rng, uint32_t n, uint32_t count) {
    std::vector<uint32_t> all(n);
    std::iota(all.begin(), all.end(), 0u);
    count = std::min(count, n);
    for (uint32_t i = 0; i < count; ++i) std::swap(all[i], all[i + rng() % (n - i)]);
    all.resize(count);
    return all;
}

// The torus grid's vertices, row after row (major radius 2, minor 1).
void addTorusVertices(Cage& cage, uint32_t columns, uint32_t rows) {
    const float majorRadius = 2.0f, minorRadius = 1.0f;
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < columns; ++i) {
            float theta = 2.0f * kPi * float(i) / float(columns), phi = 2.0f * kPi * float(j) / float(rows);
            float ring = majorRadius + minorRadius * std::cos(phi);
            cage.positions.push_back({ring * std::cos(theta), ring * std::sin(theta), minorRadius * std::sin(phi)});
        }
}

}  // namespace

Cage makeRegularTorusCage(uint32_t targetFaces) {
    const uint32_t rows = std::max(3u, uint32_t(std::lround(std::sqrt(double(targetFaces) / 2.0)))), columns = 2 * rows;
    Cage cage;
    cage.positions.reserve(size_t(columns) * rows);
    addTorusVertices(cage, columns, rows);
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < columns; ++i) {
            const uint32_t quad[4] = {j * columns + i, j * columns + (i + 1) % columns,
                                      ((j + 1) % rows) * columns + (i + 1) % columns, ((j + 1) % rows) * columns + i};
            cage.addFace(quad, 4);
        }
    return cage;
}

BenchmarkCageCounts benchmarkCageCounts(uint32_t targetFaces) {
    BenchmarkCageCounts counts;
    // Poking adds 3 faces per 100 quads; at least 3 x 6 so the torus stays a manifold.
    counts.rows = std::max(3u, uint32_t(std::lround(std::sqrt(double(targetFaces) / 1.03 / 2.0))));
    counts.columns = 2 * counts.rows;
    counts.pokedQuads = std::max(1u, counts.gridQuads() / 100);
    counts.creases = std::max(1u, 2 * counts.gridQuads() / 100);
    counts.corners = 4;
    return counts;
}

Cage makeBenchmarkCage(uint32_t targetFaces, uint32_t seed) {
    const BenchmarkCageCounts counts = benchmarkCageCounts(targetFaces);
    const uint32_t columns = counts.columns, rows = counts.rows;
    std::mt19937 rng(seed);
    auto vertex = [&](uint32_t i, uint32_t j) { return (j % rows) * columns + (i % columns); };

    Cage cage;
    cage.positions.reserve(counts.vertices());
    addTorusVertices(cage, columns, rows);

    std::vector<bool> poked(counts.gridQuads(), false);
    for (uint32_t q : pickDistinct(rng, counts.gridQuads(), counts.pokedQuads)) poked[q] = true;
    for (uint32_t j = 0; j < rows; ++j)
        for (uint32_t i = 0; i < columns; ++i) {
            // Counter-clockwise seen from outside: d/dtheta x d/dphi is the outward normal.
            uint32_t quad[4] = {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)};
            if (!poked[j * columns + i]) {
                cage.addFace(quad, 4);
                continue;
            }
            glm::vec3 p[4];
            for (int k = 0; k < 4; ++k) p[k] = cage.positions[quad[k]];
            glm::vec3 normal = glm::normalize(glm::cross(p[2] - p[0], p[3] - p[1]));
            float edge = 0.25f * (glm::length(p[1] - p[0]) + glm::length(p[2] - p[1]) + glm::length(p[3] - p[2]) +
                                  glm::length(p[0] - p[3]));
            uint32_t centre = cage.vertexCount();
            cage.positions.push_back(0.25f * (p[0] + p[1] + p[2] + p[3]) + 0.2f * edge * normal);
            for (int k = 0; k < 4; ++k) {
                uint32_t tri[3] = {quad[k], quad[(k + 1) % 4], centre};
                cage.addFace(tri, 3);
            }
        }

    // Grid edge 2q runs along the columns from quad q's first corner, 2q + 1 along the rows;
    // both survive poking (they are sides of the triangles).
    for (uint32_t e : pickDistinct(rng, 2 * counts.gridQuads(), counts.creases)) {
        uint32_t i = (e / 2) % columns, j = (e / 2) / columns;
        uint32_t a = vertex(i, j), b = (e % 2 == 0) ? vertex(i + 1, j) : vertex(i, j + 1);
        float sharpness = (rng() % 10 == 0) ? kInfiniteSharpness : 0.5f + 3.5f * unit(rng);
        cage.creases.push_back({std::min(a, b), std::max(a, b), sharpness});
    }
    for (uint32_t v : pickDistinct(rng, counts.gridQuads(), counts.corners))
        cage.corners.push_back({v, 0.5f + 3.5f * unit(rng)});
    normalizeTags(cage);
    return cage;
}

}  // namespace qp
