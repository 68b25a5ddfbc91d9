#include "cage_pick.h"

namespace qp::editor {

namespace {

glm::vec2 ndcToWindow(const VkRect2D& r, glm::vec2 ndc) {
    return {float(r.offset.x) + (0.5f * ndc.x + 0.5f) * float(r.extent.width),
            float(r.offset.y) + (0.5f * ndc.y + 0.5f) * float(r.extent.height)};
}

glm::vec2 windowToNdc(const VkRect2D& r, glm::vec2 p) {
    return {2.0f * (p.x - float(r.offset.x)) / float(r.extent.width) - 1.0f,
            2.0f * (p.y - float(r.offset.y)) / float(r.extent.height) - 1.0f};
}

}  // namespace

std::optional<glm::vec2> projectToWindow(const ScreenMapping& m, const glm::vec3& p) {
    const glm::vec4 clip = m.viewProjection * glm::vec4(p, 1.0f);
    if (clip.w <= 1e-6f) return std::nullopt;
    return ndcToWindow(m.rect, glm::vec2(clip) / clip.w);
}

glm::vec3 dragOffset(const ScreenMapping& m, const glm::vec3& anchor, glm::vec2 delta) {
    const glm::vec4 clip = m.viewProjection * glm::vec4(anchor, 1.0f);
    if (clip.w <= 1e-6f) return glm::vec3(0.0f);
    const glm::vec3 ndc = glm::vec3(clip) / clip.w;
    const glm::vec2 moved = windowToNdc(m.rect, ndcToWindow(m.rect, glm::vec2(ndc)) + delta);
    const glm::vec4 world = glm::inverse(m.viewProjection) * glm::vec4(moved, ndc.z, 1.0f);
    return glm::vec3(world) / world.w - anchor;
}

}  // namespace qp::editor
