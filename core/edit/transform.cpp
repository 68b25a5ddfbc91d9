#include "edit/transform.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace qp {

namespace {

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// The matrix that applies `inFrame` (a linear map in frame coordinates) about the pivot.
glm::mat4 aboutFrame(const TransformFrame& frame, const glm::mat3& inFrame) {
    glm::mat3 world = frame.axes * inFrame * glm::transpose(frame.axes);
    glm::mat4 m(world);
    m[3] = glm::vec4(frame.pivot - world * frame.pivot, 1.0f);
    return m;
}

}  // namespace

glm::vec3 centroid(const Cage& cage, std::span<const uint32_t> vertices) {
    if (vertices.empty()) return glm::vec3(0.0f);
    glm::dvec3 sum(0.0);
    for (uint32_t v : vertices) sum += glm::dvec3(cage.positions[v]);
    return glm::vec3(sum / double(vertices.size()));
}

glm::mat3 localAxes(const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices) {
    std::vector<bool> in(cage.vertexCount(), false);
    for (uint32_t v : vertices) in[v] = true;
    glm::vec3 inside(0.0f), around(0.0f);
    std::vector<uint32_t> seen;
    for (uint32_t v : vertices)
        for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k) {
            const uint32_t f = topology.vertexFaces[k];
            if (std::find(seen.begin(), seen.end(), f) != seen.end()) continue;
            seen.push_back(f);
            const uint32_t n = cage.faceSize(f);
            const uint32_t* fv = cage.faceBegin(f);
            glm::vec3 area(0.0f);
            bool all = true;
            for (uint32_t i = 0; i < n; ++i) {
                area += glm::cross(cage.positions[fv[i]], cage.positions[fv[(i + 1) % n]]);
                all = all && in[fv[i]];
            }
            around += area;
            if (all) inside += area;
        }
    glm::vec3 z = glm::length(inside) > 0.0f ? inside : around;
    if (!(glm::length(z) > 0.0f)) return glm::mat3(1.0f);
    z = glm::normalize(z);
    glm::vec3 x = glm::vec3(1, 0, 0) - z.x * z;
    if (glm::length(x) < 0.1f) x = glm::vec3(0, 1, 0) - z.y * z;
    x = glm::normalize(x);
    return glm::mat3(x, glm::cross(z, x), z);
}

TransformFrame makeTransformFrame(const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices,
                                  TransformSpace space, const glm::vec3* pivot) {
    TransformFrame frame;
    frame.pivot = pivot ? *pivot : centroid(cage, vertices);
    if (space == TransformSpace::Local) frame.axes = localAxes(cage, topology, vertices);
    return frame;
}

glm::mat4 translation(const TransformFrame& frame, const glm::vec3& offset) {
    return glm::translate(glm::mat4(1.0f), frame.axes * offset);
}

glm::mat4 rotation(const TransformFrame& frame, const glm::vec3& axis, float degrees) {
    if (!(glm::length(axis) > 0.0f)) return glm::mat4(std::nanf(""));  // rejected by transformPoints
    glm::mat3 r(glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::normalize(axis)));
    return aboutFrame(frame, r);
}

glm::mat4 scaling(const TransformFrame& frame, const glm::vec3& factors) {
    return aboutFrame(frame, glm::mat3(glm::scale(glm::mat4(1.0f), factors)));
}

std::vector<glm::vec3> positionsOf(const Cage& cage, std::span<const uint32_t> vertices) {
    std::vector<glm::vec3> out;
    out.reserve(vertices.size());
    for (uint32_t v : vertices) out.push_back(cage.positions[v]);
    return out;
}

Result<std::vector<glm::vec3>> transformPoints(std::span<const glm::vec3> points, const glm::mat4& matrix) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(matrix[c][r])) return Error{"the transform has a NaN or infinite value (check the numbers entered)"};
    std::vector<glm::vec3> out;
    out.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        glm::vec3 p = glm::vec3(matrix * glm::vec4(points[i], 1.0f));
        if (!finite(p)) return Error{"the transform moves point " + std::to_string(i + 1) + " to a NaN or infinite position"};
        out.push_back(p);
    }
    return out;
}

}  // namespace qp
