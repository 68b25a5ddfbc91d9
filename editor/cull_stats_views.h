// What `quadplan cull-stats` measures in one view: every culling method drawn for real through
// the scheme (DrawView::cull), timed against the unculled frame, its picture compared with the
// unculled one pixel for pixel, and what it culled checked against an ID buffer of the scheme's
// own surface (render/id_pass.h): a culled part must own no pixel of it. The parts are the
// scheme's patches where it gives the triangles it draws per patch (Scheme::drawnPatches:
// osd-fas, whose Far patches are smaller than a sub-face next to an extraordinary vertex), else
// sub-faces (only those it culled whole are checked then).
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

// The ID mesh of one cage: the scheme's own surface, each part's vertices its own and carrying
// its number. Patches: the triangles the scheme draws (Scheme::drawnPatches). Sub-faces: the
// surface on the grid the scheme draws (at its factor; its displaced surface for an object with
// displacement).
struct PartIdMesh {
    IdMesh mesh;         // empty: no surface
    bool patches = false;  // the numbers are patches, not sub-faces
    uint32_t parts = 0;
};
// What the ID buffers and the timer need besides the headless scene.
struct CullStatsRig {
    IdPass pass;
    std::vector<PartIdMesh> meshes;  // per cage of the planned scene
    GpuTimer timer;
};
Result<CullStatsRig> createCullStatsRig(HeadlessScene& headless, const Scene& scene, const PlannedScene& planned,
                                        uint32_t tessFactor);
void destroyCullStatsRig(const VulkanContext& context, CullStatsRig& rig);

// A culled part that owns pixels of its object's ID buffer: a broken promise, named so it can be found.
struct VisibleCulled {
    uint32_t object = 0, part = 0;
    bool patch = false;   // `part` is a patch of the scheme, else a sub-face
    uint32_t pixels = 0;  // it owns in the ID buffer
};
struct MethodInView {
    DrawStats draw;                  // the last timed frame's (patches, triangles, cull counts)
    double frameMs = 0.0;            // median wall time of record + submit + wait
    double gpuMs = 0.0;              // median time between timestamps around the recorded commands
    uint64_t differingPixels = 0;    // against the unculled frame
    uint64_t culledParts = 0;        // the parts the scheme reported culled (all objects)
    std::vector<VisibleCulled> visibleCulledParts;  // of those, the ones owning a pixel of their object's ID buffer
};
struct ViewMeasurement {
    std::array<MethodInView, 1 + kMeasuredCullMethods.size()> methods;  // [0]: unculled
    uint64_t visibleParts = 0;  // owning a pixel of their object's ID buffer (all objects)
};

// Draws the scene from `view` unculled and with each method, `repeats` timed frames each after
// one warm-up (nothing moves between frames: the time is the draw's). The ID check draws each
// visible object alone, so a culled part counts as visible when its own object would show it,
// whatever other objects hide.
Result<ViewMeasurement> measureView(HeadlessScene& headless, CullStatsRig& rig, const Scene& scene,
                                    const PlannedScene& planned, const DrawView& view, uint32_t repeats);

}  // namespace qp::cli
