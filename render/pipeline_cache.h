// PipelineCache: a VkPipelineCache kept on disk, so that GPU drivers need not recompile
// pipelines on every start.
//
// Measured on lavapipe (Mesa 22.3): its VkPipelineCache stores nothing but the 32-byte header,
// and it compiles at the first draw, not at vkCreateGraphicsPipelines. What makes its second
// run fast is Mesa's own shader disk cache (~/.cache/mesa_shader_cache, disabled by
// MESA_SHADER_CACHE_DISABLE=true): ~0.17 s -> ~0.015 s for the mesh pass's first draw.
//
// File format: a 24-byte Quadplan header (magic "QPPCACHE", format version, data size, FNV-1a
// 64 hash of the data) followed by the driver's cache data. The hash catches truncated or
// damaged files before the driver sees them; the driver data's own header (vendor ID, device
// ID, pipeline cache UUID) is compared with the current device. A file that fails either check
// is ignored with a warning and the cache starts empty: a bad cache must never stop the program.
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "vk_context.h"

namespace qp {

struct PipelineCache {
    VkPipelineCache cache = VK_NULL_HANDLE;
    std::string path;             // where savePipelineCache writes; empty: not persisted
    bool loadedFromFile = false;  // the file existed and was accepted
};

// $XDG_CACHE_HOME/quadplan/pipelines.bin, else ~/.cache/quadplan/pipelines.bin; empty when
// neither variable is set.
std::string defaultPipelineCachePath();

// Creates a cache seeded from `path` when that file exists and is valid for this device. A
// missing file is silent; an unreadable, damaged or foreign one adds a message to `warnings`.
// Fails only when the device cannot create a pipeline cache at all.
Result<PipelineCache> loadPipelineCache(const VulkanContext& context, const std::string& path,
                                        std::vector<std::string>* warnings = nullptr);

// Writes the cache's current contents to cache.path atomically, creating its directory.
Status savePipelineCache(const VulkanContext& context, const PipelineCache& cache);

void destroyPipelineCache(const VulkanContext& context, PipelineCache& cache);

}  // namespace qp
