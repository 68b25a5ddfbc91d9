// FaceConfig: everything the limit surface over one (sub-)face depends on, in canonical order.
//
// The limit surface over a face depends only on its 1-ring: the faces that share a vertex with
// it, the sharpness of the edges at its corners, the sharpness of its corners and the scheme
// options. Outer-edge sharpness, outer-vertex sharpness and the hole flags of neighbours do
// not matter (their rules only produce points that no patch of this face uses), so they are
// left out of the key: more faces share a plan.
//
// Canonical order: local vertex 0 is the start corner; the face's own vertices come first in
// their winding order; then, corner by corner, the faces around that corner (rotating across
// shared edges, starting from the face) add their not-yet-numbered vertices in their own
// winding order starting at the corner. The key serialises that local mesh and its tags, so
// equal keys mean equal limit surfaces (no false sharing: the database compares whole keys).
//
// Quads try all four start corners and keep the smallest key (`rotation` = that corner), so a
// rotated copy of a configuration finds the same plan. A thread remembers, by the hash of a
// quad's key from corner 0, which corner gave the smallest key, and gathers a quad with that
// first key again only from that corner (when its corners' orbits are manifold): the same
// answer as trying all four, at a third of the work. An n-gon (n != 4) is split into n quad
// sub-faces (OpenSubdiv's / Ptex's numbering: sub-face k has its origin at corner k, u towards
// corner k+1); sub-face k uses start corner k and is always sub-face 0 of its local mesh.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/cage.h"
#include "mesh/topology.h"

namespace qp {

struct PlanOptions {
    uint32_t maxDepth = 6;        // quadtree depth; 6 serves tessellation factors up to 64
    bool useCreaseNodes = true;   // evaluate constant semi-sharp creases directly (B16 §4.3)

    bool operator==(const PlanOptions&) const = default;
};
constexpr uint32_t kMaxPlanDepth = 10;  // OpenSubdiv's isolation limit

struct FaceConfig {
    std::vector<uint32_t> ring;  // global vertex index of each local vertex
    std::vector<uint32_t> key;   // canonical serialisation (see layout in face_config.cpp)
    uint64_t hash = 0;
    uint32_t rotation = 0;       // quads: the corner that is the plan's origin; n-gons: 0
};

// Key layout, as 32-bit words: [version, depth, flags, options, localVertexCount,
// localFaceCount, then per face: size, local indices..., creaseCount, then per crease: a, b,
// float bits, cornerCount, then per corner: local vertex, float bits].
// A hole's own flag is not part of the key either: a hole gets the plan it would have without
// it (PlannedCage keeps holes planned and hides them).
// What gathering many faces looks up in a pass over the cage made once for all of them
// (buildGatherIndex; worth it from a few thousand faces). Gathering with it gives the same
// FaceConfig as without.
struct GatherIndex {
    std::vector<uint8_t> withCreases;  // verticesWithCreases(cage); empty when the cage has no creases
    // Per vertex, 1 where stepping from face to face across the edges at the vertex goes round
    // once through all of its faces (a manifold fan, consistently wound, no boundary): then the
    // faces around it from any face are a rotation of orbitFaces' cycle, which is laid out like
    // Topology::vertexFaces (the same offsets). Both empty when made without orbits.
    std::vector<uint8_t> cyclic;
    std::vector<uint32_t> orbitFaces;
};
// The orbits are a pass over every vertex into arrays the size of the cage: worth it only when
// the faces to gather are a good part of the cage.
GatherIndex buildGatherIndex(const Cage& cage, const Topology& topology, bool withOrbits = true);

FaceConfig gatherFaceConfig(const Cage& cage, const Topology& topology, uint32_t face, uint32_t subface,
                            const PlanOptions& options, const GatherIndex* index = nullptr);
// One thread's gathering: the arrays it gathers into and the corners it remembers (see the top
// of this file). gatherThread() is the calling thread's; a loop over many faces on one thread
// fetches it once (each fetch of a thread-local in a shared library is a call).
struct GatherThread;
GatherThread& gatherThread();
// The same as gatherFaceConfig, gathered into `thread`'s own arrays (it must be the calling
// thread's) and valid until its next gathering: no allocation once the arrays have grown.
const FaceConfig& gatherFaceConfig(GatherThread& thread, const Cage& cage, const Topology& topology, uint32_t face,
                                   uint32_t subface, const PlanOptions& options, const GatherIndex* index = nullptr);
// Makes every thread forget the corners it remembered (see the top of this file): for
// benchmarks that time a fresh process's planning within one process.
void forgetRememberedCorners();
// Per vertex, 1 where an edge with sharpness above 0 ends.
std::vector<uint8_t> verticesWithCreases(const Cage& cage);

// Number of quad sub-faces (primitives) a face contributes: 1 for a quad, n for an n-gon.
inline uint32_t subfaceCount(uint32_t faceSize) { return faceSize == 4 ? 1 : faceSize; }

uint64_t hashKey(const std::vector<uint32_t>& key);

}  // namespace qp
