// SceneCache: the 3D viewports of the last frame, kept in an image of the window's size, so a
// frame in which only the interface changed (hover, typing, a slider) copies them instead of
// drawing the limit surfaces again. On a CPU device (lavapipe) the surfaces cost tens to
// hundreds of milliseconds and the copy about one.
//
// The cache's images follow render_target.h's layout contract; SceneRenderer draws into them
// like into any RenderTarget. A frame redraws them when its SceneKey (everything the 3D
// depends on) differs from the cached one.
#pragma once

#include <string>

#include "offscreen_target.h"
#include "render_target.h"
#include "swapchain_target.h"

namespace qp::editor {

struct SceneCache {
    Image color, depth;
    VkExtent2D extent{};
    std::string key;  // SceneKey bytes of what the images hold; empty: nothing valid
};

// (Re)creates the images when the size or format changed (after waiting for the device).
Status ensureSceneCache(const VulkanContext& context, SceneCache& cache, VkExtent2D extent, VkFormat colorFormat);
void destroySceneCache(const VulkanContext& context, SceneCache& cache);

RenderTarget sceneCacheTarget(const SceneCache& cache);

// The cache's colour format for a swapchain of `swapchainFormat` (UNORM holding sRGB-encoded
// bytes): its _SRGB twin where the device can draw into it and copy from it, so the device
// encodes each written colour instead of every fragment shader (on lavapipe the shaders' curve
// cost about 2 ms of a catmark_car frame at 1280 x 800, encoding on store about half of that).
// The bytes are the same sRGB encoding either way, within rounding, and the copy to the frame
// is bitwise. Otherwise the swapchain's own format.
VkFormat sceneCacheFormat(const VulkanContext& context, VkFormat swapchainFormat);

// Copies the cached picture into the frame's image (both keep the layout contract).
void recordCopyToFrame(VkCommandBuffer cmd, const SceneCache& cache, const SwapchainFrame& frame);

// Appends the raw bytes of `value` to `key` (for plain structs without padding surprises).
template <class T>
void appendKey(std::string& key, const T& value) {
    key.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

}  // namespace qp::editor
