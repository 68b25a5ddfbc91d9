// Minimal picking on the cage in screen space: the vertex or edge nearest the cursor in one
// viewport, and turning a cursor drag into a world-space move in the view plane. Occlusion is
// ignored (cage vertices usually lie outside the limit surface); the editing core's picking
// (core/picking) replaces this with picking on the cage and the limit surface.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "cage.h"
#include "topology.h"

namespace qp::editor {

struct ScreenMapping {
    glm::mat4 viewProjection{1.0f};
    VkRect2D rect{};  // the viewport, in window pixels
};

// Window pixel position of `p`, or nothing when it lies behind the eye.
std::optional<glm::vec2> projectToWindow(const ScreenMapping& mapping, const glm::vec3& p);

// The vertex whose projection is nearest `cursor` within `radius` pixels (ties: nearer the eye).
std::optional<uint32_t> pickVertex(const Cage& cage, const ScreenMapping& mapping, glm::vec2 cursor, float radius);

// The edge nearest `cursor` within `radius` pixels, as (a, b) with a < b.
std::optional<std::pair<uint32_t, uint32_t>> pickEdge(const Cage& cage, const Topology& topology,
                                                      const ScreenMapping& mapping, glm::vec2 cursor, float radius);

// The world-space offset that moves `anchor` by `deltaPixels` on screen, keeping its depth.
glm::vec3 dragOffset(const ScreenMapping& mapping, const glm::vec3& anchor, glm::vec2 deltaPixels);

}  // namespace qp::editor
