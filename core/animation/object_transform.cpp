#include "animation/object_transform.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace qp {

glm::mat4 ObjectTransform::matrix() const {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), translation);
    m = glm::rotate(m, glm::radians(rotationDegrees.z), glm::vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(rotationDegrees.y), glm::vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(rotationDegrees.x), glm::vec3(1, 0, 0));
    return glm::scale(m, scale);
}

Result<ObjectTransform> decomposeTransform(const glm::mat4& matrix) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(matrix[c][r])) return Error{"the transform is not finite"};
    ObjectTransform t;
    t.translation = glm::vec3(matrix[3]);
    glm::mat3 axes(matrix);
    for (int i = 0; i < 3; ++i) {
        t.scale[i] = glm::length(axes[i]);
        if (!(t.scale[i] > 1e-12f)) return Error{"the transform flattens the object (an axis of length zero)"};
        axes[i] /= t.scale[i];
    }
    if (glm::determinant(axes) < 0.0f) {  // a mirror: carried by the x scale
        t.scale.x = -t.scale.x;
        axes[0] = -axes[0];
    }
    constexpr float kOrthogonal = 1e-3f;
    if (std::abs(glm::dot(axes[0], axes[1])) > kOrthogonal || std::abs(glm::dot(axes[0], axes[2])) > kOrthogonal ||
        std::abs(glm::dot(axes[1], axes[2])) > kOrthogonal)
        return Error{"the transform shears the object: scale it along its own axes"};
    // axes = Rz(c) Ry(b) Rx(a); glm indexes [column][row].
    const float sinB = std::clamp(-axes[0][2], -1.0f, 1.0f);
    float a = 0.0f, b = std::asin(sinB), c = 0.0f;
    if (std::abs(sinB) < 0.99999f) {
        a = std::atan2(axes[1][2], axes[2][2]);
        c = std::atan2(axes[0][1], axes[0][0]);
    } else {  // gimbal lock: only a - c (or a + c) is defined; put it all in c
        c = std::atan2(-axes[1][0], axes[1][1]);
    }
    t.rotationDegrees = glm::degrees(glm::vec3(a, b, c));
    return t;
}

float maxScale(const ObjectTransform& transform) {
    const glm::vec3 s = glm::abs(transform.scale);
    return std::max({s.x, s.y, s.z});
}

}  // namespace qp
