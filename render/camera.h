// RenderCamera: a perspective or orthographic look-at camera with Vulkan conventions (depth 0..1 through
// GLM_FORCE_DEPTH_ZERO_TO_ONE, set by quadplan_core; Y flipped so +Y world is up on screen).
#pragma once

#include <glm/glm.hpp>

namespace qp {

struct RenderCamera {
    glm::vec3 eye{0.0f, 0.0f, 1.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovY = glm::radians(40.0f);  // vertical field of view, radians
    float aspect = 1.0f;               // width / height
    float nearZ = 0.01f;
    float farZ = 100.0f;
    bool orthographic = false;
    float orthoHeight = 2.0f;  // orthographic: world-space height of the view
};

// A camera that sees the whole box [min, max] from a 3/4 view (from the front-right, above;
// +Y up, +Z front), with a small margin, and near/far planes hugging the box.
RenderCamera frameBounds(const glm::vec3& min, const glm::vec3& max, float aspect);

glm::mat4 viewMatrix(const RenderCamera& camera);
glm::mat4 projectionMatrix(const RenderCamera& camera);  // Vulkan clip space
inline glm::mat4 viewProjection(const RenderCamera& camera) { return projectionMatrix(camera) * viewMatrix(camera); }

}  // namespace qp
