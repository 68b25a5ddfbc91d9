// A large, deterministic test cage for benchmarks: a closed torus of quads with a sprinkle of
// the features that make real cages expensive to plan (extraordinary vertices, non-quad
// faces, semi-sharp creases, corners), so plan sharing is not flattered by a regular grid.
//
// Layout for a given target (benchmarkCageCounts gives the exact numbers):
//   - a torus grid of `columns` x `rows` quads, columns = 2 * rows (major radius twice the
//     minor, so the quads are roughly square), G = columns * rows ~ targetFaces / 1.03;
//   - P = max(1, G / 100) distinct random quads are "poked": replaced by 4 triangles around a
//     new centre vertex lifted off the surface, which makes their corners valence 5 (or more
//     where poked quads meet);
//   - C = max(1, 2G / 100) distinct random grid edges get a crease: sharpness uniform in
//     [0.5, 4], or 10 (infinitely sharp) for about one in ten;
//   - 4 distinct random grid vertices get a corner, sharpness in [0.5, 4].
// So faces = G + 3P, vertices = G + P, edges = 2G + 4P; no boundary, no holes.
// The same (targetFaces, seed) always gives the same cage (std::mt19937, no std distributions,
// whose output differs between standard libraries).
#pragma once

#include <cstdint>

#include "mesh/cage.h"

namespace qp {

struct BenchmarkCageCounts {
    uint32_t columns = 0, rows = 0;
    uint32_t pokedQuads = 0, creases = 0, corners = 0;

    uint32_t gridQuads() const { return columns * rows; }
    uint32_t faces() const { return gridQuads() + 3 * pokedQuads; }
    uint32_t vertices() const { return gridQuads() + pokedQuads; }
    uint32_t edges() const { return 2 * gridQuads() + 4 * pokedQuads; }
};

BenchmarkCageCounts benchmarkCageCounts(uint32_t targetFaces);

Cage makeBenchmarkCage(uint32_t targetFaces, uint32_t seed);

// The same torus grid with nothing on it: every vertex valence 4, every face regular (about
// targetFaces quads, 2 n x n). The best case for macro faces (`quadplan bench macro`).
Cage makeRegularTorusCage(uint32_t targetFaces);

}  // namespace qp
