// BSplinePass: a COST BASELINE for benchmarks, not a renderer of the exact surface.
//
// It draws "plain B-spline patches": the same one-patch-per-sub-face tessellation pipeline as
// PlanPass's tessellated path (plan.vert, plan.tesc with the same factors and draw splitting,
// plan.frag), but its evaluation stage (shaders/bspline.tese) evaluates ONE bicubic B-spline per
// sub-face instead of walking the plan's quadtree. On regular faces that is the limit surface;
// on irregular faces (extraordinary vertices, creases, boundaries, n-gons) it is not, although
// it costs the same. `quadplan bench render` uses it to show what exact evaluation costs over
// the cheapest tessellated surface (docs/renderer.md).
//
// It reuses PlanPass's descriptor set and pipeline layout, and reads the control points that
// PlanPass's stencil pass last wrote: run recordTessellated or recordGridEvaluation at a factor
// at least as high first (the draw alone is what the baseline times).
#pragma once

#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "plan_pass.h"
#include "render_target.h"
#include "vk_context.h"

namespace qp {

struct BSplinePass {
    VkPipeline pipeline = VK_NULL_HANDLE;
};

// `plans` must outlive the returned pass; its formats are the target's.
Result<BSplinePass> createBSplinePass(const VulkanContext& context, VkPipelineCache cache, const PlanPass& plans);
void destroyBSplinePass(const VulkanContext& context, BSplinePass& pass);

// Clears `target` and draws every sub-face at the uniform factor settings.uniformFactor (> 0).
void recordBSplinePatches(VkCommandBuffer cmd, const BSplinePass& pass, const PlanPass& plans,
                          const PlanBuffers& buffers, const RenderTarget& target, const PlanView& view,
                          const TessellationSettings& settings);

}  // namespace qp
