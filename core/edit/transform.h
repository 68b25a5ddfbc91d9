// Transforms of a vertex set (move, rotate, scale) about a pivot, in world or local axes, with
// numeric values; the result feeds PlannedCage::moveVertices (or EditHistory::moveVertices).
//
// A frame is a pivot plus three orthonormal axes. Numeric values are given in the frame's axes:
// translation(frame, {0, 0, 1}) moves one unit along the frame's z axis (world z in World
// space, the selection's normal in Local space); rotation(frame, {0, 0, 1}, 90) turns 90
// degrees counter-clockwise about the frame's z axis through the pivot; scaling(frame,
// {1, 1, 0}) flattens onto the plane through the pivot orthogonal to the frame's z axis.
// For an interactive drag, capture the start positions once (positionsOf) and transform those
// every frame, so rounding does not accumulate.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "mesh/topology.h"

namespace qp {

enum class TransformSpace : uint8_t { World, Local };

struct TransformFrame {
    glm::vec3 pivot{0.0f};
    glm::mat3 axes{1.0f};  // columns: the frame's x, y, z axes in world space (orthonormal, right-handed)
};

// Mean position of the vertices (the origin for an empty set).
glm::vec3 centroid(const Cage& cage, std::span<const uint32_t> vertices);

// Local axes of a vertex set: z is the area-weighted normal of the faces whose corners are all
// in the set, or, when there are none, of the faces at any of the vertices; x is world x
// projected onto the plane orthogonal to z (world y when x is nearly parallel to z); y = z x x.
// Identity when the normal vanishes (nothing to orient by).
glm::mat3 localAxes(const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices);

// Pivot at the centroid of the vertices unless `pivot` is given; axes by `space`.
TransformFrame makeTransformFrame(const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices,
                                  TransformSpace space, const glm::vec3* pivot = nullptr);

glm::mat4 translation(const TransformFrame& frame, const glm::vec3& offset);
glm::mat4 rotation(const TransformFrame& frame, const glm::vec3& axis, float degrees);
glm::mat4 scaling(const TransformFrame& frame, const glm::vec3& factors);

std::vector<glm::vec3> positionsOf(const Cage& cage, std::span<const uint32_t> vertices);

// The points under the matrix. Fails (with the offending index) when the matrix or a result is
// not finite, so a bad numeric entry never reaches the cage.
Result<std::vector<glm::vec3>> transformPoints(std::span<const glm::vec3> points, const glm::mat4& matrix);

}  // namespace qp
