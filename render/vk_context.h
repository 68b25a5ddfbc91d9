// VulkanContext: the instance, the one device and queue everything else renders with.
//
// Headless by construction: no surface or window-system extensions unless a caller asks for
// them (ContextOptions::instanceExtensions), and no GLFW.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "mesh/result.h"

namespace qp {

struct ContextOptions {
    // Enables VK_LAYER_KHRONOS_validation (with synchronization validation) and a debug
    // messenger that records every warning and error in VulkanContext::validation.
    bool validation = false;
    // Pick a CPU implementation (lavapipe) even when a GPU is present.
    bool preferSoftware = false;
    // When not empty, only a device whose name contains this text is acceptable.
    std::string forceDevice;
    // Core features the device must support; devices without them are skipped. The optional
    // features the renderer uses (tessellation, geometry, fillModeNonSolid, wideLines,
    // pipelineStatisticsQuery, vertexPipelineStoresAndAtomics, shaderFloat64) are enabled
    // whenever supported, without being listed here. Always required, whatever this says:
    // shaderInt64 and (Vulkan 1.2) bufferDeviceAddress, for buffers reached by address.
    VkPhysicalDeviceFeatures requiredFeatures = {};
    // Extra extensions, e.g. the surface extensions a windowed front end needs.
    std::vector<std::string> instanceExtensions;
    std::vector<std::string> deviceExtensions;
};

// What the debug messenger saw. Written from the driver's threads, hence the mutex.
struct ValidationLog {
    std::mutex mutex;
    uint32_t warnings = 0;
    uint32_t errors = 0;
    std::vector<std::string> messages;  // "error: <text>" / "warning: <text>", in order
    bool fatal = false;  // forced by QUADPLAN_VALIDATE: destroyContext exits with status 4 on messages
};

struct VulkanContext {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT debugMessenger = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;  // graphics + compute + transfer
    uint32_t queueFamily = 0;
    VkCommandPool commandPool = VK_NULL_HANDLE;  // for queueFamily; buffers resettable
    VkPhysicalDeviceProperties properties = {};
    VkPhysicalDeviceMemoryProperties memoryProperties = {};
    VkPhysicalDeviceFeatures features = {};  // what was enabled
    // The largest buffer the device makes (maxBufferSize and maxMemoryAllocationSize): buffers
    // are one allocation each (vk_buffer.h).
    VkDeviceSize maxBufferBytes = 0;
    std::string deviceName;
    bool isSoftware = false;  // a CPU implementation such as lavapipe (then malloc keeps freed
                              // memory for the process: see keepFreedMemory in vk_context.cpp)
    // Heap-allocated so its address, which the messenger holds, survives moves of the context.
    // Kept by destroyContext, so messages from teardown (leaked objects) can still be read.
    std::unique_ptr<ValidationLog> validation;
};

// Creates a Vulkan 1.3 context with dynamic rendering and synchronization2. Prefers a discrete,
// then an integrated GPU, and falls back to a CPU implementation (lavapipe); honours
// options.preferSoftware and options.forceDevice. Fails with a message naming what is missing
// (no loader or driver, no 1.3 device, validation layer not installed, a required feature).
//
// QUADPLAN_VALIDATE=1 in the environment turns validation on for contexts that did not ask for
// it and makes their messages fatal (see destroyContext). The test command sets it, so every
// process that renders in a test (commands, benchmarks, the editor) runs validated without each
// test having to remember a flag.
Result<VulkanContext> createContext(const ContextOptions& options);

// Waits for the device to go idle and destroys everything created by createContext. Validation
// messages emitted during teardown are still counted. A context whose validation was forced by
// QUADPLAN_VALIDATE and that saw any message ends the process here with exit status 4, after
// printing the count (the messages themselves went to stderr as they came).
void destroyContext(VulkanContext& context);

// Warnings + errors reported by the validation layer so far (0 when validation is off).
uint32_t validationMessageCount(const VulkanContext& context);
std::vector<std::string> validationMessages(const VulkanContext& context);

}  // namespace qp
