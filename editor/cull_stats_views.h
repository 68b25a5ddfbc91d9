// What `quadplan cull-stats` measures in one view: every culling method drawn for real through
// the scheme (DrawView::cull), timed against the unculled frame, its picture compared with the
// unculled one pixel for pixel, and the sub-faces it culled checked against an ID buffer of the
// scheme's own surface (render/id_pass.h): a culled sub-face must own no pixel of it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "camera.h"
#include "gpu_timer.h"
#include "headless_scene.h"
#include "id_pass.h"

namespace qp::cli {

// The methods cull-stats reports, in order; index 0 of a ViewMeasurement is the unculled frame.
inline constexpr std::array<CullMethod, 4> kMeasuredCullMethods = {CullMethod::Frustum, CullMethod::TCone, CullMethod::NCone,
                                                                   CullMethod::PPlane};

// `count` cameras on a Fibonacci sphere around `bounds`, each framing all of it (render/camera.h's
// distance and depth range, turned to its direction), for images of `aspect`.
std::vector<RenderCamera> sphereCameras(const Bounds& bounds, uint32_t count, float aspect);

// What the ID buffers and the timer need besides the headless scene: per cage an ID mesh of the
// scheme's own surface, drawn at the factor the scheme draws with (its displaced surface for an
// object with displacement), each sub-face's vertices its own and carrying its number.
struct CullStatsRig {
    IdPass pass;
    std::vector<IdMesh> meshes;  // per cage of the planned scene (empty: no surface)
    GpuTimer timer;
};
Result<CullStatsRig> createCullStatsRig(HeadlessScene& headless, const Scene& scene, const PlannedScene& planned,
                                        uint32_t tessFactor);
void destroyCullStatsRig(const VulkanContext& context, CullStatsRig& rig);

// A culled sub-face that owns pixels of its object's ID buffer: a broken promise, named so it can be found.
struct VisibleCulled {
    uint32_t object = 0, subface = 0;
    uint32_t pixels = 0;  // it owns in the ID buffer
};
struct MethodInView {
    DrawStats draw;                  // the last timed frame's (patches, triangles, cull counts)
    double frameMs = 0.0;            // median wall time of record + submit + wait
    double gpuMs = 0.0;              // median time between timestamps around the recorded commands
    uint64_t differingPixels = 0;    // against the unculled frame
    uint64_t culledSubfaces = 0;     // the sub-faces the scheme reported culled whole (all objects)
    std::vector<VisibleCulled> visibleCulledSubfaces;  // of those, the ones owning a pixel of their object's ID buffer
};
struct ViewMeasurement {
    std::array<MethodInView, 1 + kMeasuredCullMethods.size()> methods;  // [0]: unculled
    uint64_t visibleSubfaces = 0;  // owning a pixel of their object's ID buffer (all objects)
};

// Draws the scene from `view` unculled and with each method, `repeats` timed frames each after
// one warm-up (nothing moves between frames: the time is the draw's). The ID check draws each
// visible object alone, so a culled sub-face counts as visible when its own object would show it,
// whatever other objects hide.
Result<ViewMeasurement> measureView(HeadlessScene& headless, CullStatsRig& rig, const Scene& scene,
                                    const PlannedScene& planned, const DrawView& view, uint32_t repeats);

}  // namespace qp::cli
