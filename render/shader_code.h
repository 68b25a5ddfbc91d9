// The SPIR-V of every shader in render/shaders/, compiled by glslc at build time and embedded in
// the binary (render/embed_shaders.cmake), so nothing is read from disk at run time.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "vk_context.h"

namespace qp {

// The code of the shader whose source is render/shaders/<name> (for example "mesh.vert"), or
// an empty span when there is no such shader.
std::span<const uint32_t> shaderCode(std::string_view name);

// A shader module of `code`; the caller destroys it.
VkShaderModule createShaderModule(const VulkanContext& context, std::span<const uint32_t> code);
// The same for shaderCode(name) (asserts the shader is embedded).
VkShaderModule loadShaderModule(const VulkanContext& context, std::string_view name);

}  // namespace qp
