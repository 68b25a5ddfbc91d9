#include "imgui_layer.h"

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include "vk_check.h"
#include "vk_commands.h"

namespace qp::editor {

namespace {

VkResult g_lastImGuiVkResult = VK_SUCCESS;  // the backend reports failures through a callback

void checkImGuiVkResult(VkResult result) {
    if (result != VK_SUCCESS) g_lastImGuiVkResult = result;
}

Status createRenderPass(const VulkanContext& ctx, ImGuiLayer& layer, VkFormat format) {
    VkAttachmentDescription color{};
    color.format = format;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // the viewports are already drawn
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    color.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkAttachmentReference reference{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &reference;
    // Earlier passes' colour writes (and copies from the image) before ours; ours before
    // whatever comes next (the transition to present, a read-back copy).
    VkSubpassDependency dependencies[2] = {};
    dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    dependencies[0].dstSubpass = 0;
    dependencies[0].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    dependencies[0].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dependencies[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependencies[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dependencies[1].srcSubpass = 0;
    dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    dependencies[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependencies[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dependencies[1].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    dependencies[1].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                    VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 1;
    info.pAttachments = &color;
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 2;
    info.pDependencies = dependencies;
    VK_CHECK(vkCreateRenderPass(ctx.device, &info, nullptr, &layer.renderPass));
    return success();
}

void destroyFramebuffers(const VulkanContext& ctx, ImGuiLayer& layer) {
    for (VkFramebuffer f : layer.framebuffers) vkDestroyFramebuffer(ctx.device, f, nullptr);
    layer.framebuffers.clear();
}

Status createFramebuffers(const VulkanContext& ctx, ImGuiLayer& layer, const SwapchainTarget& swap) {
    destroyFramebuffers(ctx, layer);
    for (VkImageView view : swap.views) {
        VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        info.renderPass = layer.renderPass;
        info.attachmentCount = 1;
        info.pAttachments = &view;
        info.width = swap.extent.width;
        info.height = swap.extent.height;
        info.layers = 1;
        VkFramebuffer framebuffer = VK_NULL_HANDLE;
        VK_CHECK(vkCreateFramebuffer(ctx.device, &info, nullptr, &framebuffer));
        layer.framebuffers.push_back(framebuffer);
    }
    layer.generation = swap.generation;
    return success();
}

Status initBackends(const VulkanContext& ctx, ImGuiLayer& layer, GLFWwindow* window, const SwapchainTarget& swap,
                    VkPipelineCache cache) {
    if (Status s = createRenderPass(ctx, layer, swap.surfaceFormat.format); !s) return s;
    if (Status s = createFramebuffers(ctx, layer, swap); !s) return s;
    // The backend allocates one descriptor set (the font texture).
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    poolInfo.maxSets = 4;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    VK_CHECK(vkCreateDescriptorPool(ctx.device, &poolInfo, nullptr, &layer.pool));

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsDark();
    layer.initialised = true;
    if (!ImGui_ImplGlfw_InitForVulkan(window, true)) return Error{"Dear ImGui's GLFW backend failed to start"};
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = ctx.instance;
    info.PhysicalDevice = ctx.physicalDevice;
    info.Device = ctx.device;
    info.QueueFamily = ctx.queueFamily;
    info.Queue = ctx.queue;
    info.PipelineCache = cache;
    info.DescriptorPool = layer.pool;
    info.MinImageCount = 2;
    info.ImageCount = std::max<uint32_t>(uint32_t(swap.images.size()), 2);
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkImGuiVkResult;
    if (!ImGui_ImplVulkan_Init(&info, layer.renderPass)) return Error{"Dear ImGui's Vulkan backend failed to start"};
    Status fonts = submitAndWait(ctx, [](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
    if (!fonts) return fonts;
    if (g_lastImGuiVkResult != VK_SUCCESS) return vkError("Dear ImGui's Vulkan backend", g_lastImGuiVkResult);
    return success();
}

}  // namespace

Result<ImGuiLayer> createImGuiLayer(const VulkanContext& ctx, GLFWwindow* window, const SwapchainTarget& swap,
                                    VkPipelineCache cache) {
    ImGuiLayer layer;
    if (Status s = initBackends(ctx, layer, window, swap, cache); !s) {
        destroyImGuiLayer(ctx, layer);
        return s.error();
    }
    return layer;
}

void destroyImGuiLayer(const VulkanContext& ctx, ImGuiLayer& layer) {
    vkDeviceWaitIdle(ctx.device);
    if (layer.initialised) {
        if (ImGui::GetIO().BackendRendererUserData) ImGui_ImplVulkan_Shutdown();
        if (ImGui::GetIO().BackendPlatformUserData) ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    destroyFramebuffers(ctx, layer);
    if (layer.pool) vkDestroyDescriptorPool(ctx.device, layer.pool, nullptr);
    if (layer.renderPass) vkDestroyRenderPass(ctx.device, layer.renderPass, nullptr);
    layer = ImGuiLayer{};
}

void beginImGuiBackends() {
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
}

Status recordImGui(const VulkanContext& ctx, ImGuiLayer& layer, const SwapchainTarget& swap,
                   const SwapchainFrame& frame, ImDrawData* drawData) {
    if (layer.generation != swap.generation) {
        if (Status s = createFramebuffers(ctx, layer, swap); !s) return s;  // the swapchain waited for the device
    }
    VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    begin.renderPass = layer.renderPass;
    begin.framebuffer = layer.framebuffers[frame.imageIndex];
    begin.renderArea = {{0, 0}, swap.extent};
    vkCmdBeginRenderPass(frame.cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(drawData, frame.cmd);
    vkCmdEndRenderPass(frame.cmd);
    if (g_lastImGuiVkResult != VK_SUCCESS) return vkError("Dear ImGui's Vulkan backend", g_lastImGuiVkResult);
    return success();
}

}  // namespace qp::editor
