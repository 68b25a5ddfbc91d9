// Exporting a whole scene: one limit mesh per cage (instances share their cage's), each optimised
// for the GPU, written as one file (glTF keeps a node per visible object; the other formats merge
// them in the world) or one file per object (`split`: NAME_OBJECT.EXT). What `quadplan export`,
// the editor's File > Export and Python's scene.export() all call, so they write the same bytes.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "camera.h"
#include "limit_mesh.h"
#include "mesh_files.h"
#include "mesh_order.h"
#include "scene/planned_scene.h"
#include "scene/scene.h"

namespace qp {

// Screen-adaptive density: each cage's grid cut as the grid path cuts it for this camera
// (world space; each object's transform is applied), `pixelsPerSegment` pixels per segment.
struct AdaptiveExport {
    glm::mat4 viewProjection{1.0f};
    float pixelsPerUnit = 1.0f;  // render/plan_pass.h pixelsPerUnit() for the view's height
    float pixelsPerSegment = 8.0f;
};

// The adaptive density for what `camera` sees in a viewport `viewportHeight` pixels tall.
AdaptiveExport adaptiveExport(const RenderCamera& camera, uint32_t viewportHeight, float pixelsPerSegment);

struct ExportOptions {
    uint32_t factor = 8;     // uniform tessellation factor (segments per sub-face edge)
    std::optional<AdaptiveExport> adaptive;  // instead of `factor`
    bool displaced = false;  // apply each cage's sculpted displacement (the exact surface only)
    bool optimize = true;    // meshoptimizer's vertex cache and fetch order
    bool split = false;      // one file per visible object
    UvMode uv = UvMode::None;  // the cages' texture coordinates (cage_uvs.h)
};

struct ExportReport {
    std::vector<std::string> files;
    uint64_t vertices = 0, triangles = 0;  // in the files (glTF: each mesh once)
    uint32_t objects = 0, meshes = 0;
    MeshClosure closure;                   // summed over the meshes
    OrderReport order;                     // triangle-weighted over the meshes (zeros without optimize)
    std::vector<std::string> notes;        // e.g. a cage without displacement under `displaced`
    double ms = 0.0;
};

// The planned cages of a scene's objects, wherever they are kept (a PlannedScene, the editor's
// document): per cage its owning object, per object the cage it draws.
struct SceneCages {
    std::vector<const PlannedCage*> cages;
    std::vector<uint32_t> cageOfObject, objectOfCage;
};
SceneCages sceneCages(const PlannedScene& planned);

// Where `split` writes object `object` of an export to `out`: NAME_OBJECT.EXT beside it.
std::string splitExportPath(const std::string& out, const std::string& object);

// How finely cage `c` of `planned` is meshed under `options`.
MeshDensity exportDensity(const Scene& scene, const SceneCages& planned, uint32_t c, const ExportOptions& options);

// Where a long export or bake is (the editor's progress bar): what it does now and the fraction
// of the whole done. Called from the exporting thread; returning false cancels the job, which
// then fails with "cancelled" having written nothing (it is asked before the first file).
using ExportProgress = std::function<bool(const std::string& stage, float fraction)>;

// Makes cage `c`'s mesh; the default is exactLimitMesh (with the owner's displacement when asked).
using CageMesher = std::function<Result<LimitMesh>(const PlannedCage& cage, uint32_t c, const std::string& source)>;

// `scene`'s objects (names, transforms, visibility, displacement) drawing `planned`'s cages.
// `source` names the scene in messages. Nothing is written when any cage fails.
Result<ExportReport> exportScene(const Scene& scene, const SceneCages& planned, const std::string& path,
                                 const ExportOptions& options, const std::string& source,
                                 const CageMesher& mesher = nullptr, const ExportProgress& progress = nullptr);

}  // namespace qp
