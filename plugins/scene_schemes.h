// Drawing a scene of many objects through one scheme: an instance of the scheme per cage of a
// PlannedScene (core/scene/planned_scene.h), recorded once per visible object under that object's
// transform. Instances of a cage share its scheme instance, so they add no patches, no control
// points and no GPU buffers; moving an object changes only the view its draw gets.
#pragma once

#include <vector>

#include "line_pass.h"
#include "scene/planned_scene.h"
#include "scheme_host.h"

namespace qp {

// `world` (the camera's view) in the coordinates of an object placed by `transform`: the
// projection times the object's matrix, the eye brought into the object's space, and
// pixelsPerUnit scaled by the transform's largest scale (screen-adaptive factors stay as fine
// as the object looks), and DrawView::worldFromObject set to the matrix's linear part, with which
// the plans bring their world-fixed studio lights into the cage's coordinates.
DrawView objectView(const DrawView& world, const ObjectTransform& transform);

struct SceneSchemes {
    std::vector<PreparedScheme> cages;  // one per PlannedScene cage
    std::vector<Bounds> bounds;         // of each cage when prepared (which instance looks largest)
    double setupMs() const;
};

// prepareScheme for every cage, each with its owner's displacement (when set). Warnings in each
// cage's support.approximations name the object when the scene has several. On failure nothing
// is left on the GPU.
Result<SceneSchemes> prepareSceneSchemes(const PluginCatalog& catalog, const std::string& name, const Scene& scene,
                                         const PlannedScene& planned, const SchemeSettings& settings,
                                         const GpuContext& gpu, const std::string& source);

// Records every visible object (the first clearing target.area, as an empty scene does), the
// instances of a cage sharing the tessellation the largest-looking of them needs (sameFrame);
// statistics summed over the objects drawn.
Result<DrawStats> recordScene(VkCommandBuffer cmd, SceneSchemes& schemes, const Scene& scene, const PlannedScene& planned,
                              const RenderTarget& target, const DrawView& world);

Status destroySceneSchemes(SceneSchemes& schemes);

// The cages' lines (line_pass.h cageLines) in one buffer per cage, drawn once per visible object
// under its transform over what is there.
struct SceneCageLines {
    std::vector<Buffer> buffers;   // per cage
    std::vector<uint32_t> counts;  // vertices in each
};
Result<SceneCageLines> createSceneCageLines(const VulkanContext& context, const PlannedScene& planned);
void recordSceneCageLines(VkCommandBuffer cmd, const LinePass& pass, const RenderTarget& target, const SceneCageLines& lines,
                          const Scene& scene, const PlannedScene& planned, const DrawView& world);
void destroySceneCageLines(const VulkanContext& context, SceneCageLines& lines);

// timeSchemeFrames for a scene: every cage's update(), then recordScene, per frame.
Result<SchemeFrameTimes> timeSceneFrames(const VulkanContext& context, SceneSchemes& schemes, const Scene& scene,
                                         const PlannedScene& planned, const RenderTarget& target, const DrawView& view,
                                         const GpuTimer& timer, uint32_t repeats);

}  // namespace qp
