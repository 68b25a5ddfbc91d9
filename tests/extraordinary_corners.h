// Shared by the precision tests (test_plan.cpp on the CPU, test_render_plans.cpp on the device):
// a cube far from the origin, and how far normals at its valence-3 corners are from the exact
// limit tangent plane.
#pragma once

#include <cmath>
#include <functional>

#include <glm/geometric.hpp>

#include "mesh/topology.h"
#include "plans/limit_frame.h"
#include "plans/quad_ring.h"
#include "test_cages.h"

namespace qp::test {

// makeSubdividedCube(3) moved to (60, -40, 90): faces 1/3 wide at coordinates near 100, where
// float in absolute coordinates cannot hold the derivatives deep in a plan.
inline Cage makeFarOffCube() {
    Cage cage = makeSubdividedCube(3);
    for (glm::vec3& p : cage.positions) p += glm::vec3(60.0f, -40.0f, 90.0f);
    return cage;
}

// The largest angle in degrees between normalAt(face, corner) and the exact limit tangent
// plane's normal (computeVertexLimit, double), over every corner at a valence-3 vertex;
// `corners` counts them.
inline double worstValence3CornerDegrees(const Cage& cage,
                                         const std::function<glm::dvec3(uint32_t face, uint32_t corner)>& normalAt,
                                         uint32_t& corners) {
    const Topology topology = buildTopology(cage);
    double worst = 0.0;
    corners = 0;
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        for (uint32_t k = 0; k < 4; ++k) {
            if (topology.vertexFaceCount(cage.faceBegin(f)[k]) != 3) continue;
            const VertexLimit exact = computeVertexLimit(cage, gatherQuadRing(cage, topology, f, k));
            const glm::dvec3 n = glm::normalize(glm::cross(exact.tangents[0], exact.tangents[1]));
            const glm::dvec3 m = glm::normalize(normalAt(f, k));
            worst = std::max(worst, std::atan2(glm::length(glm::cross(n, m)), glm::dot(n, m)) * 180.0 / M_PI);
            ++corners;
        }
    return worst;
}

}  // namespace qp::test
