// TessPatchPass: one patch primitive per element of a storage buffer through the hardware
// tessellator, for the schemes that were designed for it (ACC-1, ACC-2, PN-triangles).
//
// The scheme brings the control stage (tessellation factors) and the evaluation stage (its
// patch, evaluated at gl_TessCoord), both reading its patch data by address
// (tess_patch_buffers.glsl: no buffer is held to the device's storage buffer range), and
// includes tess_patch.glsl for the shared push constants, edge factors and outputs. The pass
// supplies the rest: a vertex stage that only passes the patch index on (tess_patch.vert), the
// renderer's mesh.frag (so tessellated and CPU-grid pictures are lit alike), uniform or
// screen-adaptive factors, a wireframe overlay, and draw splitting: lavapipe corrupts a draw
// whose tessellator emits more than 65,535 vertices (platform notes), so draws hold at most
// patchesPerDraw(largest factor) patches, as render/plan_pass.cpp does.
//
// Prepare: a scheme may bring a compute stage too (its points from the cage on the device, as
// osd-fas applies Far's stencils): recordTessPrepare dispatches it over the same descriptor set,
// with a barrier before the tessellation stages read what it wrote.
//
// Culling: the vertex stage reads each primitive's patch from a list: the identity
// 0 .. patchCount - 1, or, when a draw leaves out culled patches, the others written into the
// list by the command buffer itself (vkCmdUpdateBuffer), so the objects of one frame that share
// the pass (DrawView::sameFrame) each draw their own list and no host write races a recorded draw.
//
// Capture: with `capture` set, the evaluation stage appends every vertex it evaluates
// (patch, domain coordinate, position, normal) to a capture buffer, so tests can
// check the GPU evaluation against the scheme's CPU evaluation.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "render_target.h"
#include "scheme_api.h"
#include "vk_buffer.h"
#include "vk_context.h"

namespace qp {

struct TessPatchShaders {
    std::span<const uint32_t> vertex, control, evaluation;  // SPIR-V (module_shader_code.h)
    std::span<const uint32_t> prepare;                      // optional compute stage
};

struct TessPatchPass {
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline solid = VK_NULL_HANDLE, wire = VK_NULL_HANDLE;  // wire: null without fillModeNonSolid
    VkPipeline prepare = VK_NULL_HANDLE;                        // null without a prepare stage
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED, depthFormat = VK_FORMAT_UNDEFINED;
    Buffer patchData;              // the scheme's patches
    uint32_t patchCount = 0;
    Buffer patchList;              // the identity list (patchCount), then room for a draw's own
    Buffer capture;                // header (count, capacity) + TessCaptureRecord[]
    uint32_t captureCapacity = 0;
    Buffer addresses;              // where the shaders find the three (tess_patch_buffers.glsl)
};

// Fails with a message when the device has no tessellation shaders. The layouts and pipelines
// are made once per device, formats and shaders and shared (render/shared_pipelines.h); the
// descriptor set and buffers are the pass's own, and destroyTessPatchPass frees only those.
Result<TessPatchPass> createTessPatchPass(const VulkanContext& context, VkPipelineCache cache, VkFormat colorFormat,
                                          VkFormat depthFormat, const TessPatchShaders& shaders);
void destroyTessPatchPass(const VulkanContext& context, TessPatchPass& pass);

// Copies the patch data (its layout is the scheme's) for `patchCount` patches, growing the
// buffer when it is too small. Call outside of recording.
Status uploadTessPatches(const VulkanContext& context, TessPatchPass& pass, const void* data, size_t bytes,
                         uint32_t patchCount);

// Writes `bytes` at `offset` of the patch data (its buffer as uploadTessPatches sized it). Call
// outside of recording, while no submitted work reads the buffer.
void writeTessPatchData(TessPatchPass& pass, const void* data, size_t bytes, size_t offset);
// Dispatches the prepare stage over `invocations` (64 a group, in rows of at most 65,535 groups)
// and orders its writes before the tessellation stages. Record outside of rendering.
void recordTessPrepare(VkCommandBuffer cmd, const TessPatchPass& pass, uint32_t invocations);

struct TessPatchSettings {
    uint32_t uniformFactor = 8;     // 1..64; 0: screen-adaptive
    float pixelsPerSegment = 8.0f;  // adaptive: target screen length of one segment
    bool capture = false;
    uint32_t largestLevel = 0;      // the most segments an edge gets (splits draws); 0: the factor
};

// Clears target.area and draws every patch but `culled` (sorted, unique; then the wireframe
// when view.wireframe). Record outside of rendering.
void recordTessPatches(VkCommandBuffer cmd, const TessPatchPass& pass, const RenderTarget& target, const DrawView& view,
                       const TessPatchSettings& settings, std::span<const uint32_t> culled = {});

// Mirrors CaptureRecord in tess_patch.glsl. (u, v, w): gl_TessCoord (w = 0 on quads).
struct TessCaptureRecord {
    uint32_t patch;
    float u, v, w;
    float position[3];
    float normal[3];
};
Status enableTessCapture(const VulkanContext& context, TessPatchPass& pass, uint32_t capacity);
// Records of the last captured draw (clamped to the capacity; `overflowed` gets the rest).
std::vector<TessCaptureRecord> readTessCapture(const TessPatchPass& pass, uint32_t* overflowed = nullptr);

// vec3 control points as the vec4s a std430 storage buffer holds.
std::vector<glm::vec4> paddedPoints(std::span<const glm::vec3> points);

// Triangles a patch makes at a uniform factor: 2 f^2 on quads, f^2 on triangles.
uint64_t tessTriangles(uint32_t factor, bool triangleDomain);

// ---- The `path` option of schemes that draw both ways ----------------------------------------

enum class PatchPath { Tessellated, Cpu };
// path=tess (the default) or path=cpu (GridDrawing); other values fail with a message naming
// the scheme.
Result<PatchPath> patchPathOption(const SchemeSettings& settings, const char* scheme);
// support() helper: refuses a bad path, warns about options other than `known` (and `path`),
// and says when a screen-adaptive request is drawn at a fixed factor (the CPU path).
void checkPatchOptions(SupportReport& report, const SchemeSettings& settings, const char* scheme,
                       std::span<const char* const> known = {});

}  // namespace qp
