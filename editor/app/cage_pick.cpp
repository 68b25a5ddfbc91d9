#include "cage_pick.h"

#include <algorithm>
#include <limits>

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

float distanceToSegment(glm::vec2 p, glm::vec2 a, glm::vec2 b) {
    const glm::vec2 ab = b - a;
    const float t = std::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-12f), 0.0f, 1.0f);
    return glm::length(p - (a + t * ab));
}

}  // namespace

std::optional<glm::vec2> projectToWindow(const ScreenMapping& m, const glm::vec3& p) {
    const glm::vec4 clip = m.viewProjection * glm::vec4(p, 1.0f);
    if (clip.w <= 1e-6f) return std::nullopt;
    return ndcToWindow(m.rect, glm::vec2(clip) / clip.w);
}

std::optional<uint32_t> pickVertex(const Cage& cage, const ScreenMapping& m, glm::vec2 cursor, float radius) {
    std::optional<uint32_t> best;
    float bestDistance = radius, bestDepth = std::numeric_limits<float>::max();
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        const glm::vec4 clip = m.viewProjection * glm::vec4(cage.positions[v], 1.0f);
        if (clip.w <= 1e-6f) continue;
        const float d = glm::length(ndcToWindow(m.rect, glm::vec2(clip) / clip.w) - cursor);
        const float depth = clip.z / clip.w;
        if (d > radius) continue;
        // Within a pixel of the best, the one nearer the eye wins.
        if (!best || d < bestDistance - 1.0f || (d <= bestDistance + 1.0f && depth < bestDepth)) {
            best = v;
            bestDistance = d;
            bestDepth = depth;
        }
    }
    return best;
}

std::optional<std::pair<uint32_t, uint32_t>> pickEdge(const Cage& cage, const Topology& topology,
                                                      const ScreenMapping& m, glm::vec2 cursor, float radius) {
    std::optional<std::pair<uint32_t, uint32_t>> best;
    float bestDistance = radius;
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
        const uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
        std::optional<glm::vec2> pa = projectToWindow(m, cage.positions[a]), pb = projectToWindow(m, cage.positions[b]);
        if (!pa || !pb) continue;
        const float d = distanceToSegment(cursor, *pa, *pb);
        if (d <= bestDistance) {
            bestDistance = d;
            best = std::make_pair(std::min(a, b), std::max(a, b));
        }
    }
    return best;
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
