// IdPass: an ID buffer. Triangles drawn unlit, depth-tested, each in a flat colour that encodes
// a number carried by its vertices (24 bits, read back with decodeId), into an RGBA8 UNORM
// target. `quadplan cull-stats` draws every sub-face of a scheme's surface in its own number to
// learn which sub-faces own a pixel of a view.
//
// Back sides are drawn (no face culling), as every scheme draws them: an ID buffer shows what a
// scheme's picture shows.
#pragma once

#include <cstdint>
#include <span>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "render_target.h"
#include "vk_buffer.h"
#include "vk_context.h"

namespace qp {

struct IdVertex {
    glm::vec3 position;
    uint32_t id;  // the number its triangles show; at most kMaxId
};
static_assert(sizeof(IdVertex) == 16);

// 2^24 - 1 codes, one of which (0) is the cleared background.
inline constexpr uint32_t kMaxId = (1u << 24) - 2;
inline constexpr uint32_t kNoId = UINT32_MAX;

// The number an RGBA8 pixel of an ID buffer holds, or kNoId where nothing was drawn.
inline uint32_t decodeId(const uint8_t* rgba) {
    const uint32_t code = uint32_t(rgba[0]) | uint32_t(rgba[1]) << 8 | uint32_t(rgba[2]) << 16;
    return code == 0 ? kNoId : code - 1;
}

struct IdMesh {
    Buffer vertices;  // IdVertex[]
    Buffer indices;   // uint32_t[], three per triangle
    uint32_t indexCount = 0;
};

// `vertices` and `indices` must not be empty; indices come in threes.
Result<IdMesh> uploadIdMesh(const VulkanContext& context, std::span<const IdVertex> vertices,
                            std::span<const uint32_t> indices);
void destroyIdMesh(const VulkanContext& context, IdMesh& mesh);

struct IdPass {
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED, depthFormat = VK_FORMAT_UNDEFINED;
};

// Shared per device and formats (shared_pipelines.h), like the other passes. `colorFormat` must
// be a UNORM format (an sRGB one would re-encode the codes).
Result<IdPass> createIdPass(const VulkanContext& context, VkPipelineCache cache, VkFormat colorFormat = VK_FORMAT_R8G8B8A8_UNORM,
                            VkFormat depthFormat = VK_FORMAT_D32_SFLOAT);
// Forgets the handles; the device keeps the pipeline until destroyContext.
void destroyIdPass(const VulkanContext& context, IdPass& pass);

// Draws `mesh` under `viewProjection` into target.area; with `clear` the area is cleared first
// (to no number, depth 1), else it draws over what is there (depth-tested against it).
void recordIdPass(VkCommandBuffer cmd, const IdPass& pass, const RenderTarget& target, const glm::mat4& viewProjection,
                  bool clear, const IdMesh& mesh);

}  // namespace qp
