// Buffers in host-visible, coherent memory, mapped for their whole life.
//
// lavapipe has a single memory type (device-local + host-visible + coherent); on a GPU this
// picks host-visible coherent memory as well, preferring a device-local type (resizable BAR)
// when there is one. Staging to device-only memory can come later, behind the same interface.
#pragma once

#include <cstddef>
#include <cstdint>

#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "vk_context.h"

namespace qp {

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* data = nullptr;  // persistently mapped
    VkDeviceSize size = 0;
    VkDeviceAddress address = 0;  // storage buffers: where shaders reach it (buffer_reference)
};

// The index of a memory type allowed by `typeBits` with all `required` properties, preferring
// one that also has all `preferred` ones; UINT32_MAX when none qualifies.
uint32_t findMemoryType(const VkPhysicalDeviceMemoryProperties& properties, uint32_t typeBits,
                        VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred = 0);

// A mapped buffer of `size` bytes (> 0); a storage buffer also gets its device address. Fails,
// saying so, when the device makes no buffer that large (VulkanContext::maxBufferBytes), when
// memory runs out or no host-visible coherent memory type accepts the buffer.
Result<Buffer> createBuffer(const VulkanContext& context, VkDeviceSize size, VkBufferUsageFlags usage);

// Copies `size` bytes into the buffer at `offset`; the range must lie inside the buffer. Visible
// to commands submitted afterwards (coherent memory, and queue submission orders host writes).
void uploadBuffer(const Buffer& buffer, const void* data, size_t size, size_t offset = 0);

void destroyBuffer(const VulkanContext& context, Buffer& buffer);

}  // namespace qp
