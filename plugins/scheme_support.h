// Helpers for scheme modules and the host: uniform sample grids over sub-faces and the
// triangle meshes made from them.
//
// The CPU grid is a first-class way for a scheme to draw: evaluate the surface on a grid per
// sub-face (in parallel), upload the triangles once per update and draw them with MeshPass. On
// lavapipe the tessellator runs on one core while the CPU path uses all of them
// (/work/shared/notes/platform-notes.md); the host's error heat map is built the same way.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "displacement/displaced_mesh.h"
#include "mesh_pass.h"
#include "scheme_api.h"

namespace qp {

// Samples on a uniform grid over every sub-face that has a surface: a quad sub-face gets
// `factor` segments per side, an n-gon sub-face (half the size) max(1, factor / 2), as the
// plans' grid path does. Vertices of one sub-face are consecutive, rows of constant v, u
// fastest; triangles follow the sub-face's winding.
struct SubfaceGrid {
    std::vector<SampleRequest> samples;
    std::vector<uint32_t> indices;        // three per triangle, into samples
    std::vector<uint32_t> subfaces;       // the sub-faces gridded, in order
    std::vector<uint32_t> firstSample;    // parallels subfaces, plus the total at the end
    uint32_t factor = 0;
};
SubfaceGrid buildSubfaceGrid(const PlannedCage& planned, uint32_t factor);

// The face a sub-face belongs to.
uint32_t faceOfSubface(const PlannedCage& planned, uint32_t subface);

// Segments per side of sub-face `subface` in a grid of `factor` (quad or n-gon sub-face).
uint32_t subfaceGridFactor(const PlannedCage& planned, uint32_t subface, uint32_t factor);

// Unit normal of du x dv (zero when degenerate).
glm::vec3 normalOf(const glm::vec3& du, const glm::vec3& dv);

// A SurfacePoint from position and derivatives, its normal from them.
SurfacePoint surfacePoint(const glm::vec3& position, const glm::vec3& du, const glm::vec3& dv);

// A scheme's own sample (position, normal, du, dv in float or double, and `valid`: it has a
// surface there) as a SurfacePoint.
template <class Sample>
SurfacePoint surfacePointOf(const Sample& s) {
    return SurfacePoint{glm::vec3(s.position), glm::vec3(s.normal), glm::vec3(s.du), glm::vec3(s.dv), s.valid};
}

// Evaluates `scheme` at every request, spread over all cores in chunks (Scheme::evaluate is
// thread-safe by contract).
void evaluateParallel(const Scheme& scheme, std::span<const SampleRequest> requests, std::span<SurfacePoint> out);

std::vector<MeshVertex> meshVertices(std::span<const SurfacePoint> points);
std::vector<MeshVertex> meshVertices(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals);

// ---- Drawing triangles (MeshPass) -------------------------------------------------------------

// The MeshPass for `gpu`'s target formats, as createGpu makes it.
Status createSchemeMeshPass(MeshPass& pass, const GpuContext& gpu);

// Destroys `mesh` (if it holds one) and uploads these triangles in its place; none when there
// are no vertices.
Status replaceMesh(const VulkanContext& context, GpuMesh& mesh, std::span<const MeshVertex> vertices,
                   std::span<const uint32_t> indices);

// ---- Culling (DrawView::cull) ----------------------------------------------------------------

// The entries of `set` culled for `view` (sorted), their counts and the time taken into `stats`.
// `closed`: closedOutwardSurface of the cage (back-patch tests apply unless the view hides faces); `margins` as cullPatches.
std::vector<uint32_t> cullForView(const PatchCullSet& set, bool closed, std::span<const float> margins,
                                  const DrawView& view, DrawStats& stats);

// ---- Displacement (Scheme::setDisplacement) --------------------------------------------------

// The grid factor for drawing `displacement` when `requested` was asked for: at least
// requiredMeshFactor (core/displacement/displaced_mesh.h), so every stored sample is a vertex and raising
// a tile's resolution raises the tessellation with it; even on cages with non-quads; at most
// 128 (n-gon sub-faces then get 64).
uint32_t displacedGridFactor(const PlannedCage& planned, const Displacement& displacement, uint32_t requested);

// The displaced triangle mesh of `scheme`'s own surface (its evaluate(): position, derivatives,
// the normal it shades with): buildDisplacedMesh over the scheme, so boundary vertices come from
// their owner and the mesh is watertight bit for bit. For schemes that draw a CPU mesh
// (displaced_drawing.h keeps it for incremental updates).
Result<DisplacedMesh> displacedSchemeMesh(const Scheme& scheme, const PlannedCage& planned,
                                          const Displacement& displacement, uint32_t factor);

}  // namespace qp
