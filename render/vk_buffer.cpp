#include "vk_buffer.h"

#include <cassert>
#include <cstring>

#include "vk_check.h"

namespace qp {

uint32_t findMemoryType(const VkPhysicalDeviceMemoryProperties& properties, uint32_t typeBits,
                        VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) {
    uint32_t fallback = UINT32_MAX;
    for (uint32_t i = 0; i < properties.memoryTypeCount; ++i) {
        const VkMemoryPropertyFlags flags = properties.memoryTypes[i].propertyFlags;
        if (!(typeBits & (1u << i)) || (flags & required) != required) continue;
        if ((flags & preferred) == preferred) return i;
        if (fallback == UINT32_MAX) fallback = i;
    }
    return fallback;
}

namespace {

Status allocate(const VulkanContext& ctx, Buffer& b, VkDeviceSize size, VkBufferUsageFlags usage) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(ctx.device, &info, nullptr, &b.buffer));

    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(ctx.device, b.buffer, &requirements);
    const uint32_t type = findMemoryType(ctx.memoryProperties, requirements.memoryTypeBits,
                                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                         VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type == UINT32_MAX) return Error{"no host-visible coherent memory type can hold a buffer on " + ctx.deviceName};

    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex = type;
    VK_CHECK(vkAllocateMemory(ctx.device, &alloc, nullptr, &b.memory));
    VK_CHECK(vkBindBufferMemory(ctx.device, b.buffer, b.memory, 0));
    VK_CHECK(vkMapMemory(ctx.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.data));
    b.size = size;
    return success();
}

}  // namespace

Result<Buffer> createBuffer(const VulkanContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage) {
    assert(size > 0);
    Buffer b;
    if (Status s = allocate(ctx, b, size, usage); !s) {
        destroyBuffer(ctx, b);
        return s.error();
    }
    return b;
}

void uploadBuffer(const Buffer& buffer, const void* data, size_t size, size_t offset) {
    assert(buffer.data && offset + size <= buffer.size);
    std::memcpy(static_cast<char*>(buffer.data) + offset, data, size);
}

void destroyBuffer(const VulkanContext& ctx, Buffer& b) {
    if (b.buffer) vkDestroyBuffer(ctx.device, b.buffer, nullptr);
    if (b.memory) vkFreeMemory(ctx.device, b.memory, nullptr);  // unmaps implicitly
    b = Buffer{};
}

}  // namespace qp
