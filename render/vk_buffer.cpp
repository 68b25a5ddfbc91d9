#include "vk_buffer.h"

#include <cassert>
#include <cstring>
#include <string>

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
    const bool addressed = usage & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    if (addressed) usage |= VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
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

    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, addressed ? &flags : nullptr};
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex = type;
    if (VkResult r = vkAllocateMemory(ctx.device, &alloc, nullptr, &b.memory); r != VK_SUCCESS)
        return Error{"out of memory for a buffer of " + std::to_string(size >> 20) + " MiB on " + ctx.deviceName + " (" +
                     vkResultName(r) + ")"};
    VK_CHECK(vkBindBufferMemory(ctx.device, b.buffer, b.memory, 0));
    if (addressed) {
        VkBufferDeviceAddressInfo where{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
        where.buffer = b.buffer;
        b.address = vkGetBufferDeviceAddress(ctx.device, &where);
    }
    VK_CHECK(vkMapMemory(ctx.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.data));
    b.size = size;
    return success();
}

}  // namespace

Result<Buffer> createBuffer(const VulkanContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage) {
    assert(size > 0);
    if (ctx.maxBufferBytes && size > ctx.maxBufferBytes)
        return Error{"a buffer of " + std::to_string(size >> 20) + " MiB is larger than " + ctx.deviceName +
                     " can make (" + std::to_string(ctx.maxBufferBytes >> 20) +
                     " MiB): use a lower tessellation factor or a smaller cage"};
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
