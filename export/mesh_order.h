// The triangle and vertex order of an exported mesh, optimised with meshoptimizer for the GPUs
// that will draw it: triangles reordered for the post-transform vertex cache (Forsyth-style, as
// the course's tessellation chapter compares), then vertices renumbered in first-use order for
// fetch locality. The grid's own order (row by row, sub-face by sub-face) is the "scanline"
// baseline; the report gives the average cache miss ratio (ACMR: vertices transformed per
// triangle) of both, for a FIFO cache of kCacheSize entries.
#pragma once

#include "limit_mesh.h"

namespace qp {

inline constexpr unsigned kCacheSize = 16;

struct OrderReport {
    float acmrBefore = 0.0f, acmrAfter = 0.0f;
};

// Reorders `mesh`'s triangles and vertices (every per-vertex array moves together); the surface
// is unchanged.
OrderReport optimizeMeshOrder(LimitMesh& mesh);

// The ACMR of `indices` over `vertexCount` vertices.
float averageCacheMissRatio(std::span<const uint32_t> indices, uint32_t vertexCount);

}  // namespace qp
