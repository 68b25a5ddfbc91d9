// ImGuiLayer: Dear ImGui 1.86 on GLFW and Vulkan, drawn over the 3D viewports.
//
// ImGui 1.86's Vulkan backend needs a classic VkRenderPass: ours has one colour attachment
// (the swapchain image) loaded, not cleared, and left in COLOR_ATTACHMENT_OPTIMAL, so
// render_target.h's layout contract still holds after it. Framebuffers follow the swapchain's
// generation. The font atlas is uploaded once with submitAndWait.
#pragma once

#include <vector>

#include <vulkan/vulkan.h>

#include "swapchain_target.h"

struct GLFWwindow;
struct ImDrawData;

namespace qp::editor {

struct ImGuiLayer {
    VkRenderPass renderPass = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    std::vector<VkFramebuffer> framebuffers;  // one per swapchain image
    uint32_t generation = 0;                  // swapchain generation the framebuffers were made for
    bool initialised = false;                 // ImGui context and backends are live
};

// Creates the ImGui context and both backends (GLFW installs its input callbacks, chaining any
// set before). No ini file is written: the layout is the program's.
Result<ImGuiLayer> createImGuiLayer(const VulkanContext& context, GLFWwindow* window, const SwapchainTarget& swapchain,
                                    VkPipelineCache cache);
void destroyImGuiLayer(const VulkanContext& context, ImGuiLayer& layer);

// Starts an ImGui frame (backends first, then ImGui::NewFrame is the caller's).
void beginImGuiBackends();

// Records the draw data into the frame's image (after the 3D passes).
Status recordImGui(const VulkanContext& context, ImGuiLayer& layer, const SwapchainTarget& swapchain,
                   const SwapchainFrame& frame, ImDrawData* drawData);

}  // namespace qp::editor
