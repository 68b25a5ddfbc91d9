// A displaced triangle mesh on the CPU: one (n+1) x (n+1) vertex grid per sub-face with a
// surface, each vertex at s + D N with the shading normal of displacePoint (displacement.h).
//
// Quads get `factor` intervals per side and n-gon sub-faces factor / 2 (an n-gon sub-face
// spans half of each cage edge, as in the renderer), so grids meet vertex to vertex.
// Watertight by construction, as the renderer's: a vertex on a shared boundary takes the limit
// position and normal from the boundary's owner (computeBoundaryOwners) at a parameter rebuilt
// from integers, and its displacement from its OWN sub-face through evaluateDisplacement — the
// shared edge samples make that the same bits on every side.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "displacement/displacement.h"
#include "mesh/result.h"
#include "plans/planned_cage.h"

namespace qp {

// Any surface over the same sub-faces (a patching scheme's): position, derivatives and the unit
// normal the surface is displaced along, at (sub-face, u, v). Called concurrently.
struct SurfaceFrame {
    glm::vec3 position{0.0f}, du{0.0f}, dv{0.0f}, normal{0.0f};
};

struct DisplacedMesh {
    uint32_t factor = 0;                // quads' intervals per side
    std::vector<uint32_t> gridSubface;  // the sub-face of each grid
    std::vector<uint32_t> gridFactor;   // its intervals per side
    std::vector<uint32_t> gridOffset;   // its first vertex; (n+1)^2 vertices, u fastest
    std::vector<glm::vec3> positions, normals;
    std::vector<uint32_t> indices;      // triangles, counter-clockwise like the cage
    // Per vertex, what it was displaced from: the owner's position and normal on boundaries,
    // its own sub-face's derivatives (redisplaceGrids starts from these).
    std::vector<SurfaceFrame> frames;
};

// The smallest factor at which every sample is a mesh vertex: the required tessellation
// factor of each quad and twice that of each n-gon sub-face, at most 64 for quads.
uint32_t requiredMeshFactor(const PlannedCage& planned, const DisplacementLayout& layout);

// factor in 1..128; even when the cage has non-quads. An empty displacement displaces nothing.
Result<DisplacedMesh> buildDisplacedMesh(const PlannedCage& planned, const Displacement& displacement, uint32_t factor);

using SurfaceFunction = std::function<SurfaceFrame(uint32_t subface, float u, float v)>;

// The same mesh over `surface` instead of the limit surface: each scheme displaces along its
// own normal, and boundary vertices still take position and normal from the owner, so the
// result is watertight bit for bit even where the scheme's own surface is not.
Result<DisplacedMesh> buildDisplacedMesh(const PlannedCage& planned, const Displacement& displacement, uint32_t factor,
                                         const SurfaceFunction& surface);

// After samples changed in place (same layout): recomputes the positions and normals of these
// grids (indices into gridSubface) from the kept frames, with the bits a full build would give.
void redisplaceGrids(DisplacedMesh& mesh, const Displacement& displacement, std::span<const uint32_t> grids);

}  // namespace qp
