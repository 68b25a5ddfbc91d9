#include "camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace qp {

RenderCamera frameBounds(const glm::vec3& min, const glm::vec3& max, float aspect) {
    RenderCamera c;
    c.aspect = aspect;
    c.target = 0.5f * (min + max);
    // The bounding sphere must fit inside the narrower of the two fields of view.
    const float radius = std::max(0.5f * glm::length(max - min), 1e-4f);
    const float fovX = 2.0f * std::atan(std::tan(0.5f * c.fovY) * aspect);
    const float halfFov = 0.5f * std::min(c.fovY, fovX);
    const float distance = 1.05f * radius / std::sin(halfFov);
    // 35 degrees around from the front, 25 degrees above: the classic 3/4 product shot.
    const float azimuth = glm::radians(35.0f), elevation = glm::radians(25.0f);
    const glm::vec3 direction(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                              std::cos(elevation) * std::cos(azimuth));
    c.eye = c.target + distance * direction;
    c.nearZ = std::max(distance - 1.5f * radius, 0.01f * distance);
    c.farZ = distance + 1.5f * radius;
    return c;
}

glm::mat4 viewMatrix(const RenderCamera& c) { return glm::lookAt(c.eye, c.target, c.up); }

glm::mat4 projectionMatrix(const RenderCamera& c) {
    const float halfHeight = 0.5f * c.orthoHeight, halfWidth = halfHeight * c.aspect;
    glm::mat4 p = c.orthographic ? glm::ortho(-halfWidth, halfWidth, -halfHeight, halfHeight, c.nearZ, c.farZ)
                                 : glm::perspective(c.fovY, c.aspect, c.nearZ, c.farZ);
    p[1][1] *= -1.0f;  // Vulkan's framebuffer Y points down
    return p;
}

}  // namespace qp
