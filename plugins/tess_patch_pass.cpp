#include "tess_patch_pass.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <string>

#include <glm/glm.hpp>

#include "plan_pass.h"  // patchesPerDraw: the same lavapipe limit as the plans' tessellated path
#include "pipeline_builder.h"
#include "shader_code.h"
#include "shared_pipelines.h"
#include "vk_check.h"
#include "vk_commands.h"

namespace qp {

namespace {

// Mirrors TessPush in tess_patch.glsl; its first four members are mesh.frag's MeshPush.
struct TessPush {
    glm::mat4 viewProj;
    glm::vec4 eye;
    glm::vec4 color;
    glm::vec4 params;  // x: depth pull toward the eye, y: 0 lit / 1 flat, z: 1 matcap
    float uniformFactor;
    float pixelsPerSegment;
    float pixelsPerUnit;
    uint32_t capture;
};
static_assert(sizeof(TessPush) == 128, "push constants: 128 bytes guaranteed");

constexpr VkShaderStageFlags kStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT |
                                       VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
constexpr VkShaderStageFlags kBindingStages = kStages | VK_SHADER_STAGE_COMPUTE_BIT;
constexpr uint32_t kCaptureHeaderBytes = 16;
constexpr uint32_t kPrepareGroupSize = 64;  // local_size_x of a prepare stage
constexpr float kWireDepthPull = 2e-4f;  // as MeshPass's overlay
constexpr VkBufferUsageFlags kPatchListUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
constexpr VkDeviceSize kUpdateBufferBytes = 65536;  // vkCmdUpdateBuffer's most per call

Result<VkPipeline> createPipeline(const VulkanContext& ctx, VkPipelineCache cache, const TessPatchPass& pass,
                                  const VkShaderModule modules[4], bool wireframe) {
    // mesh.frag encodes sRGB itself unless the target does (GraphicsPipelineDesc::encodeColor).
    const ShaderStage stages[] = {{VK_SHADER_STAGE_VERTEX_BIT, modules[0]},
                                  {VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT, modules[1]},
                                  {VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT, modules[2]},
                                  {VK_SHADER_STAGE_FRAGMENT_BIT, modules[3]}};
    GraphicsPipelineDesc desc;
    desc.stages = stages;
    desc.layout = pass.layout;
    desc.colorFormat = pass.colorFormat;
    desc.depthFormat = pass.depthFormat;
    desc.patchControlPoints = 1;  // the patch index; the control points are in the buffer
    desc.polygonMode = wireframe ? VK_POLYGON_MODE_LINE : VK_POLYGON_MODE_FILL;
    desc.depthWrite = !wireframe;
    desc.depthCompare = wireframe ? VK_COMPARE_OP_LESS_OR_EQUAL : VK_COMPARE_OP_LESS;
    return createGraphicsPipeline(ctx, cache, desc);
}

// Mirrors TessPatchAddresses in tess_patch_buffers.glsl: the shaders reach the buffers by
// address, so none is held to the device's storage buffer range.
struct TessPatchAddresses {
    VkDeviceAddress patchData, capture, patchList;
};

void bindBuffers(const VulkanContext& ctx, const TessPatchPass& pass) {
    const TessPatchAddresses addresses{pass.patchData.address, pass.capture.address, pass.patchList.address};
    uploadBuffer(pass.addresses, &addresses, sizeof addresses);
    const VkDescriptorBufferInfo info{pass.addresses.buffer, 0, sizeof addresses};
    const VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, pass.set, 0, 0, 1,
                                     VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, nullptr, &info, nullptr};
    vkUpdateDescriptorSets(ctx.device, 1, &write, 0, nullptr);
}

// The layouts and pipelines of one scheme's shaders: made once per device, formats and shaders
// (render/shared_pipelines.h).
Status initPipelines(const VulkanContext& ctx, VkPipelineCache cache, TessPatchPass& pass, const TessPatchShaders& shaders) {
    if (!ctx.features.tessellationShader) return Error{"the device (" + ctx.deviceName + ") has no tessellation shaders"};
    const VkDescriptorSetLayoutBinding addresses{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, kBindingStages, nullptr};
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = 1;
    setInfo.pBindings = &addresses;
    VK_CHECK(vkCreateDescriptorSetLayout(ctx.device, &setInfo, nullptr, &pass.setLayout));
    VkPushConstantRange range{kStages, 0, sizeof(TessPush)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &pass.setLayout;
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &pass.layout));

    std::span<const uint32_t> fragment = shaderCode("mesh.frag");
    if (shaders.vertex.empty() || shaders.control.empty() || shaders.evaluation.empty() || fragment.empty())
        return Error{"a tessellation stage is missing from the module (is it in quadplan_scheme_shaders?)"};
    VkShaderModule modules[4] = {createShaderModule(ctx, shaders.vertex), createShaderModule(ctx, shaders.control),
                                 createShaderModule(ctx, shaders.evaluation), createShaderModule(ctx, fragment)};
    Result<VkPipeline> solid = createPipeline(ctx, cache, pass, modules, false);
    Result<VkPipeline> wire = VK_NULL_HANDLE;
    if (solid && ctx.features.fillModeNonSolid) wire = createPipeline(ctx, cache, pass, modules, true);
    for (VkShaderModule m : modules) vkDestroyShaderModule(ctx.device, m, nullptr);
    if (solid) pass.solid = *solid;
    if (!solid) return solid.error();
    if (!wire) return wire.error();
    pass.wire = *wire;
    if (shaders.prepare.empty()) return success();
    VkShaderModule compute = createShaderModule(ctx, shaders.prepare);
    Result<VkPipeline> prepare = createComputePipeline(ctx, cache, compute, pass.layout);
    vkDestroyShaderModule(ctx.device, compute, nullptr);
    if (!prepare) return prepare.error();
    pass.prepare = *prepare;
    return success();
}

void destroyPipelines(const VulkanContext& ctx, TessPatchPass& pass) {
    for (VkPipeline p : {pass.solid, pass.wire, pass.prepare})
        if (p) vkDestroyPipeline(ctx.device, p, nullptr);
    if (pass.layout) vkDestroyPipelineLayout(ctx.device, pass.layout, nullptr);
    if (pass.setLayout) vkDestroyDescriptorSetLayout(ctx.device, pass.setLayout, nullptr);
}

// The pass's own descriptor set and buffers.
Status initInstance(const VulkanContext& ctx, TessPatchPass& pass) {
    if (Status made = createDescriptorSet(ctx, pass.setLayout, {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}, pass.pool, pass.set); !made)
        return made;

    Result<Buffer> addresses = createBuffer(ctx, sizeof(TessPatchAddresses), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
    if (!addresses) return addresses.error();
    pass.addresses = *addresses;
    // Placeholders until the scheme uploads patches or a test asks for a capture.
    Result<Buffer> data = createBuffer(ctx, 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (!data) return data.error();
    pass.patchData = *data;
    Result<Buffer> capture =
        createBuffer(ctx, kCaptureHeaderBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    if (!capture) return capture.error();
    pass.capture = *capture;
    std::memset(pass.capture.data, 0, kCaptureHeaderBytes);
    Result<Buffer> list = createBuffer(ctx, 16, kPatchListUsage);
    if (!list) return list.error();
    pass.patchList = *list;
    bindBuffers(ctx, pass);
    return success();
}

// FNV-1a of the scheme's stages: the shared pipelines' key, whatever address the module has.
uint64_t shaderHash(const TessPatchShaders& shaders) {
    uint64_t hash = 1469598103934665603ull;
    for (std::span<const uint32_t> code : {shaders.vertex, shaders.control, shaders.evaluation, shaders.prepare})
        for (uint32_t word : code) hash = (hash ^ word) * 1099511628211ull;
    return hash;
}

}  // namespace

Result<TessPatchPass> createTessPatchPass(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat,
                                          VkFormat depthFormat, const TessPatchShaders& shaders) {
    const std::string key = sharedPassKey("tess-patch", colorFormat, depthFormat) + ":" + std::to_string(shaderHash(shaders));
    Result<TessPatchPass> shared = sharedPass<TessPatchPass>(
        ctx, key, colorFormat, depthFormat,
        [&](TessPatchPass& pipelines) { return initPipelines(ctx, cache, pipelines, shaders); }, destroyPipelines);
    if (!shared) return shared.error();
    TessPatchPass pass = *shared;
    if (Status s = initInstance(ctx, pass); !s) {
        destroyTessPatchPass(ctx, pass);
        return s.error();
    }
    return pass;
}

void destroyTessPatchPass(const VulkanContext& ctx, TessPatchPass& pass) {
    // The pipelines and layouts stay with the device (render/shared_pipelines.h).
    if (pass.pool) vkDestroyDescriptorPool(ctx.device, pass.pool, nullptr);
    if (pass.patchData.buffer) destroyBuffer(ctx, pass.patchData);
    if (pass.capture.buffer) destroyBuffer(ctx, pass.capture);
    if (pass.patchList.buffer) destroyBuffer(ctx, pass.patchList);
    if (pass.addresses.buffer) destroyBuffer(ctx, pass.addresses);
    pass = TessPatchPass{};
}

Status uploadTessPatches(const VulkanContext& ctx, TessPatchPass& pass, const void* data, size_t bytes, uint32_t patchCount) {
    if (bytes > pass.patchData.size) {
        Result<Buffer> grown = createBuffer(ctx, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
        if (!grown) return grown.error();
        destroyBuffer(ctx, pass.patchData);
        pass.patchData = *grown;
        bindBuffers(ctx, pass);
    }
    if (bytes) uploadBuffer(pass.patchData, data, bytes);
    // The patch list: the identity, and as much room again for a draw's own list.
    const VkDeviceSize listBytes = 2 * VkDeviceSize(patchCount) * sizeof(uint32_t);
    bool writeIdentity = patchCount != pass.patchCount;
    if (listBytes > pass.patchList.size) {
        Result<Buffer> grown = createBuffer(ctx, listBytes, kPatchListUsage);
        if (!grown) return grown.error();
        destroyBuffer(ctx, pass.patchList);
        pass.patchList = *grown;
        bindBuffers(ctx, pass);
        writeIdentity = true;
    }
    if (writeIdentity && patchCount) {
        std::vector<uint32_t> identity(patchCount);
        for (uint32_t p = 0; p < patchCount; ++p) identity[p] = p;
        uploadBuffer(pass.patchList, identity.data(), identity.size() * sizeof(uint32_t));
    }
    pass.patchCount = patchCount;
    return success();
}

void writeTessPatchData(TessPatchPass& pass, const void* data, size_t bytes, size_t offset) {
    assert(offset + bytes <= pass.patchData.size);
    uploadBuffer(pass.patchData, data, bytes, offset);
}

void recordTessPrepare(VkCommandBuffer cmd, const TessPatchPass& pass, uint32_t invocations) {
    assert(pass.prepare && "the scheme has no prepare stage");
    if (invocations == 0) return;
    const uint32_t groups = (invocations + kPrepareGroupSize - 1) / kPrepareGroupSize;
    const uint32_t rowGroups = std::min(groups, 65535u);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pass.prepare);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pass.layout, 0, 1, &pass.set, 0, nullptr);
    vkCmdDispatch(cmd, rowGroups, (groups + rowGroups - 1) / rowGroups, 1);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_TESSELLATION_CONTROL_SHADER_BIT | VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                  VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

void recordTessPatches(VkCommandBuffer cmd, const TessPatchPass& pass, const RenderTarget& target, const DrawView& view,
                       const TessPatchSettings& settings, std::span<const uint32_t> culled) {
    const bool capture = settings.capture && pass.captureCapacity > 0;
    // The patches drawn: slots [listFirst, listFirst + listCount) of the patch list.
    uint32_t listFirst = 0, listCount = pass.patchCount;
    if (!culled.empty()) {
        std::vector<uint32_t> kept;
        kept.reserve(pass.patchCount);
        size_t next = 0;
        for (uint32_t p = 0; p < pass.patchCount; ++p) {
            while (next < culled.size() && culled[next] < p) ++next;
            if (next == culled.size() || culled[next] != p) kept.push_back(p);
        }
        listFirst = pass.patchCount;
        listCount = uint32_t(kept.size());
        // An earlier draw of this command buffer may still read the slots (DrawView::sameFrame).
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                      VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        const VkDeviceSize bytes = VkDeviceSize(listCount) * sizeof(uint32_t);
        for (VkDeviceSize done = 0; done < bytes; done += kUpdateBufferBytes)
            vkCmdUpdateBuffer(cmd, pass.patchList.buffer, VkDeviceSize(listFirst) * sizeof(uint32_t) + done,
                              std::min(kUpdateBufferBytes, bytes - done), reinterpret_cast<const char*>(kept.data()) + done);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    }
    if (capture) {
        vkCmdFillBuffer(cmd, pass.capture.buffer, 0, 4, 0);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    }
    beginRendering(cmd, target, view.clear, view.background);
    const uint32_t maxFactor = settings.largestLevel ? std::min(settings.largestLevel, 64u)
                               : settings.uniformFactor == 0 ? 64u
                                                             : std::min(settings.uniformFactor, 64u);
    const uint32_t perDraw = patchesPerDraw(maxFactor);
    for (VkPipeline pipeline : {pass.solid, view.wireframe ? pass.wire : VkPipeline(VK_NULL_HANDLE)}) {
        if (!pipeline || listCount == 0) continue;
        const bool wire = pipeline == pass.wire;
        TessPush push{};
        push.viewProj = view.viewProjection;
        push.eye = glm::vec4(view.eye, 1.0f);
        push.color = wire ? glm::vec4(0.02f, 0.02f, 0.02f, 1.0f) : glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
        push.params = glm::vec4(wire ? kWireDepthPull : 0.0f, wire ? 1.0f : 0.0f,
                                view.shading == Shading::Matcap ? 1.0f : 0.0f, 0.0f);
        push.uniformFactor = float(settings.uniformFactor);
        push.pixelsPerSegment = settings.pixelsPerSegment;
        push.pixelsPerUnit = view.pixelsPerUnit;
        push.capture = capture && !wire ? 1u : 0u;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.layout, 0, 1, &pass.set, 0, nullptr);
        vkCmdPushConstants(cmd, pass.layout, kStages, 0, sizeof(push), &push);
        for (uint32_t first = 0; first < listCount; first += perDraw) {
            // Captured draws append to one buffer: order them (barriers may not sit inside a
            // rendering instance at these stages).
            if (push.capture && first > 0) {
                vkCmdEndRendering(cmd);
                memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                              VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                              VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                              VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
                beginRendering(cmd, target, false, view.background);
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.layout, 0, 1, &pass.set, 0, nullptr);
                vkCmdPushConstants(cmd, pass.layout, kStages, 0, sizeof(push), &push);
            }
            vkCmdDraw(cmd, std::min(perDraw, listCount - first), 1, listFirst + first, 0);
        }
    }
    vkCmdEndRendering(cmd);
    if (capture)
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

Status enableTessCapture(const VulkanContext& ctx, TessPatchPass& pass, uint32_t capacity) {
    Result<Buffer> capture = createBuffer(ctx, kCaptureHeaderBytes + VkDeviceSize(capacity) * sizeof(TessCaptureRecord),
                                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    if (!capture) return capture.error();
    destroyBuffer(ctx, pass.capture);
    pass.capture = *capture;
    pass.captureCapacity = capacity;
    const uint32_t header[4] = {0, capacity, 0, 0};
    uploadBuffer(pass.capture, header, sizeof(header));
    bindBuffers(ctx, pass);
    return success();
}

std::vector<TessCaptureRecord> readTessCapture(const TessPatchPass& pass, uint32_t* overflowed) {
    uint32_t count = 0;
    std::memcpy(&count, pass.capture.data, sizeof(count));
    const uint32_t kept = std::min(count, pass.captureCapacity);
    if (overflowed) *overflowed = count - kept;
    std::vector<TessCaptureRecord> records(kept);
    std::memcpy(records.data(), static_cast<const char*>(pass.capture.data) + kCaptureHeaderBytes,
                kept * sizeof(TessCaptureRecord));
    return records;
}

Result<PatchPath> patchPathOption(const SchemeSettings& settings, const char* scheme) {
    const std::string* path = settings.option("path");
    if (!path || *path == "tess") return PatchPath::Tessellated;
    if (*path == "cpu") return PatchPath::Cpu;
    return Error{std::string(scheme) + ": unknown path '" + *path + "'; use tess (patches through the tessellator) or cpu"};
}

void checkPatchOptions(SupportReport& report, const SchemeSettings& settings, const char* scheme,
                       std::span<const char* const> known) {
    Result<PatchPath> path = patchPathOption(settings, scheme);
    if (!path) report.refusals.push_back(path.error().message);
    for (const auto& [key, value] : settings.options)
        if (key != "path" && std::find_if(known.begin(), known.end(), [&](const char* k) { return key == k; }) == known.end())
            report.approximations.push_back(std::string(scheme) + " ignores the unknown option '" + key + "'");
    if (path && *path == PatchPath::Cpu && settings.adaptivePixels > 0.0f)
        report.approximations.push_back(std::string(scheme) + " path=cpu has no screen-adaptive mode: it uses factor 16");
}

std::vector<glm::vec4> paddedPoints(std::span<const glm::vec3> points) {
    std::vector<glm::vec4> out(points.size());
    for (size_t i = 0; i < points.size(); ++i) out[i] = glm::vec4(points[i], 1.0f);
    return out;
}

uint64_t tessTriangles(uint32_t factor, bool triangleDomain) {
    const uint64_t f = factor;
    return triangleDomain ? f * f : 2 * f * f;
}

}  // namespace qp
