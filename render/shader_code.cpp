#include "shader_code.h"

#include <cassert>

#include "vk_check.h"

namespace qp {

VkShaderModule createShaderModule(const VulkanContext& ctx, std::span<const uint32_t> code) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = code.size_bytes();
    info.pCode = code.data();
    VkShaderModule module = VK_NULL_HANDLE;
    VK_ASSERT(vkCreateShaderModule(ctx.device, &info, nullptr, &module));
    return module;
}

VkShaderModule loadShaderModule(const VulkanContext& ctx, std::string_view name) {
    const std::span<const uint32_t> code = shaderCode(name);
    assert(!code.empty() && "shader not embedded: is it in render/shaders/?");
    return createShaderModule(ctx, code);
}

}  // namespace qp
