// MeshPass: draws indexed triangle meshes (float3 position + float3 normal per vertex) with a
// lit, gamma-correct shader and depth test into a RenderTarget with dynamic rendering,
// plus an optional wireframe overlay (polygon mode LINE, width 1).
//
// A mesh may carry a second vertex stream of linear colours (one float3 per vertex, e.g. an
// error heat map); it is drawn with those colours blended over the lit surface, so the colour
// scale stays readable and the form still shows (MeshPass::solidColored).
#pragma once

#include <cstdint>
#include <span>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "render_target.h"
#include "scene/shading.h"
#include "vk_buffer.h"
#include "vk_context.h"

namespace qp {

struct MeshVertex {
    glm::vec3 position;
    glm::vec3 normal;
};
static_assert(sizeof(MeshVertex) == 24);

struct GpuMesh {
    Buffer vertices;  // MeshVertex[]; also usable as a storage buffer
    Buffer indices;   // uint32_t[], three per triangle
    Buffer colors;    // optional: glm::vec3 linear colour per vertex (null buffer when absent)
    uint32_t indexCount = 0;
};

// `colors` is empty or has one entry per vertex.
Result<GpuMesh> uploadMesh(const VulkanContext& context, std::span<const MeshVertex> vertices,
                           std::span<const uint32_t> indices, std::span<const glm::vec3> colors = {});
void destroyMesh(const VulkanContext& context, GpuMesh& mesh);

struct MeshPass {
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline solid = VK_NULL_HANDLE;
    VkPipeline solidColored = VK_NULL_HANDLE;  // meshes with a colour stream
    VkPipeline wireframe = VK_NULL_HANDLE;  // null when the device lacks fillModeNonSolid
    VkFormat colorFormat = VK_FORMAT_UNDEFINED;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
};

// The pipelines for targets of the given formats, built through `cache` (may be null) by the
// first request on a device and shared by every later one (shared_pipelines.h).
Result<MeshPass> createMeshPass(const VulkanContext& context, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat = VK_FORMAT_D32_SFLOAT);
// Forgets the handles; the device keeps the pipelines until destroyContext.
void destroyMeshPass(const VulkanContext& context, MeshPass& pass);

struct MeshView {
    glm::mat4 viewProjection{1.0f};  // Vulkan clip space (see camera.h)
    glm::vec3 eye{0.0f};             // world-space camera position, for the headlight
    glm::vec3 background{0.0f};      // linear colour the target is cleared to
    Shading shading = Shading::Studio;
    bool clear = true;               // false: draw over what target.area holds (later objects of a scene)
};

// Part of a mesh's index buffer: `count` indices from `first`.
struct IndexRange {
    uint32_t first = 0, count = 0;
};

struct MeshDraw {
    const GpuMesh* mesh = nullptr;
    glm::vec3 color{0.8f};  // linear base colour; ignored for meshes with a colour stream
    bool lit = true;        // false: flat colour, exactly
    bool wireframe = false;
    glm::vec3 wireColor{0.02f};
    // The parts of the index buffer drawn (e.g. all but the culled patches'); empty: all of it.
    std::span<const IndexRange> ranges = {};
};

// Records one pass: clears the target's area, draws every mesh (solid, then the wireframe
// overlays on top); the layout contract of render_target.h holds afterwards. The pass's formats must match the target's.
void recordMeshPass(VkCommandBuffer cmd, const MeshPass& pass, const RenderTarget& target, const MeshView& view,
                    std::span<const MeshDraw> draws);

}  // namespace qp
