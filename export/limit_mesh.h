// LimitMesh: a planned cage's surface as one welded triangle mesh, what `quadplan export`
// writes (mesh_files.h) and a game engine, renderer or printer reads.
//
// The vertices are the grid path's slots (render/grid_layout.h) at a uniform factor: every
// sub-face is an (n + 1)^2 grid, and a slot on a boundary that sub-faces share is evaluated
// once, by its owner, and copied by the others. Welding follows that ownership, not positions:
// each evaluated slot is one vertex and every copy refers to it, so the mesh is watertight by
// construction (a closed cage gives a closed 2-manifold; at factor F a closed all-quad cage with
// V vertices, E edges and N faces gives exactly V + (F-1)E + (F-1)^2 N vertices), whatever the
// scheme computes at each slot. Triangles that snapping made degenerate (an n-gon's sub-faces
// take half the factor) and those of holes are left out.
//
// Data are plain arrays: positions and unit normals per vertex, three indices per triangle, and
// for pipelines each vertex's sub-face (a Ptex face, core/plans/face_config.h) and (u, v) in it.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "cage_uvs.h"
#include "displacement/displacement.h"
#include "grid_layout.h"
#include "mesh/result.h"
#include "plans/plan_evaluator.h"
#include "plans/planned_cage.h"

namespace qp {

// How closed a triangle mesh is: edges used by one triangle (a border), by more than two or
// twice in the same direction (non-manifold). Watertight: neither.
struct MeshClosure {
    uint32_t borderEdges = 0, nonManifoldEdges = 0;
    bool watertight() const { return borderEdges == 0 && nonManifoldEdges == 0; }
};
MeshClosure meshClosure(std::span<const uint32_t> indices);

struct LimitMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;     // unit; zero where the surface has no tangent plane
    std::vector<uint32_t> indices;      // three per triangle, counter-clockwise seen from outside
    std::vector<uint32_t> subfaces;     // per vertex: the sub-face it was evaluated in
    std::vector<glm::vec2> parameters;  // per vertex: (u, v) there
    // With UVs (cage_uvs.h): per vertex, the cage's texture coordinates there. A vertex on a UV
    // seam is split into one per UV, so the index buffer opens there; `closure` is the
    // surface's, counted before the split.
    std::vector<glm::vec2> uvs;
    MeshClosure closure;

    uint32_t vertexCount() const { return uint32_t(positions.size()); }
    uint32_t triangleCount() const { return uint32_t(indices.size() / 3); }
};

// How finely the mesh samples the surface: a uniform `factor` (1..64; odd factors become even
// on cages with n-gons, as grid_layout.h says), or with `adaptive` the grid path's
// screen-adaptive factors for that view (each cage edge cut by its length on screen).
struct MeshDensity {
    uint32_t factor = 8;
    std::optional<AdaptiveView> adaptive;

    MeshDensity(uint32_t uniform = 8) : factor(uniform) {}
    explicit MeshDensity(const AdaptiveView& view) : factor(0), adaptive(view) {}
};

// The exact limit surface (the plans, evaluated on the CPU as the grid path does), with
// `displacement` applied when given (it must match `planned`).
Result<LimitMesh> exactLimitMesh(const PlannedCage& planned, const MeshDensity& density,
                                 const Displacement* displacement = nullptr, UvMode uv = UvMode::None);

// The same slots evaluated by another surface (a scheme plugin's CPU evaluator): `evaluate` gets
// each owned slot's (sub-face, u, v) once and returns positions and normals.
using SlotEvaluator = std::function<void(std::span<const SampleRequest>, std::span<glm::vec3> positions,
                                         std::span<glm::vec3> normals)>;
Result<LimitMesh> evaluatedLimitMesh(const PlannedCage& planned, const MeshDensity& density,
                                     const SlotEvaluator& evaluate, UvMode uv = UvMode::None);


}  // namespace qp
