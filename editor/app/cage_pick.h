// Screen-space helpers for dragging in a viewport: where a point appears, and the world-space
// move that keeps a grabbed point under the cursor in the view plane. (Picking itself is the
// editing core's: core/edit/picking.h, used through tools.h.)
#pragma once

#include <optional>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

namespace qp::editor {

struct ScreenMapping {
    glm::mat4 viewProjection{1.0f};
    VkRect2D rect{};  // the viewport, in window pixels
};

// Window pixel position of `p`, or nothing when it lies behind the eye.
std::optional<glm::vec2> projectToWindow(const ScreenMapping& mapping, const glm::vec3& p);

// The world-space offset that moves `anchor` by `deltaPixels` on screen, keeping its depth.
glm::vec3 dragOffset(const ScreenMapping& mapping, const glm::vec3& anchor, glm::vec2 deltaPixels);

}  // namespace qp::editor
