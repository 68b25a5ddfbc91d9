// The patching-scheme plugin interface: everything a scheme module implements and exports.
//
// A scheme is a shared module (plugins/<name>/, built by quadplan_add_scheme into
// <build>/plugins/quadplan-scheme-<name>.so) that the host loads at run time with dlopen
// (scheme_loader.h). It exports one C symbol, `quadplan_scheme_module`, returning a
// SchemeModule; QUADPLAN_EXPORT_SCHEME below writes it. plugins/README.md walks through
// wrapping a scheme.
//
// Life of a scheme instance, as the host drives it (every call may fail with a message; the
// host also catches exceptions, so a throwing scheme is reported, never fatal):
//   support(features)   can it draw this cage? what does it approximate or refuse? (no build)
//   build(planned)      topology-dependent work on the CPU: tables, patches, stencils
//   createGpu(gpu)      pipelines and buffers for targets of the given formats
//   update()            positions changed (and once after createGpu): CPU work that depends
//                       on positions, uploads; after it, evaluate() and record() see them
//   setDisplacement(d)  optional, after build: the scene's sculpted displacement (or none),
//                       drawn from the next update() on; displacementChanged(samples) after a
//                       brush dab changed samples in place (see "Displacement" below)
//   updateMoved(verts)  only these vertices moved since the last update (an interactive drag):
//                       a scheme may refresh just what depends on them; default: update()
//   updatePlans(change) a tag or topology edit changed the planned cage in place: a scheme may
//                       update just the sub-faces it re-planned; default: ask for a rebuild
//   record(cmd, ...)    clears target.area and draws the surface there; records only
//   evaluate(...)       the surface on the CPU, for error measurement (thread-safe, const)
//   destroyGpu()        before the Vulkan context goes away
//
// Parameter domain: every scheme evaluates in the plans' sub-face frame. Sub-faces are
// OpenSubdiv's Ptex faces (PlannedCage, core/plans/face_config.h): a quad is one sub-face with u from
// corner 0 to 1 and v from corner 0 to 3; an n-gon is n sub-faces, sub-face k having corners
// (vertex k, midpoint of edge k, centre, midpoint of edge k-1). The host compares a scheme
// with the exact limit surface (PlannedCage::evaluate) at the same (sub-face, u, v).
//
// Binary compatibility: modules pass C++ types (Cage, PlannedCage, VulkanContext, std::string)
// across the boundary, so they must come from the same build as the host: the loader checks
// kSchemeApiVersion, the compiler and standard-library tag and a layout fingerprint of the
// shared types, and refuses a module that differs, with a message saying to rebuild it.
// Bump kSchemeApiVersion on any change to this header.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

#include "culling/patch_cull_set.h"  // CullMethod, CullCounts
#include "displacement/displacement.h"
#include "mesh/cage.h"
#include "mesh/result.h"
#include "plans/plan_evaluator.h"  // SampleRequest
#include "plans/planned_cage.h"
#include "render_target.h"
#include "scene/shading.h"
#include "vk_context.h"

namespace qp {

inline constexpr uint32_t kSchemeApiVersion = 12;

// ---- What a cage asks of a scheme ---------------------------------------------------------

enum class CageFeature : uint32_t {
    NonQuadFaces,              // faces with 3 or more than 4 vertices
    Triangles,                 // faces with 3 vertices
    Boundaries,                // edges with one face
    Holes,                     // faces tagged as holes
    InfinitelySharpCreases,    // edges with sharpness >= 10
    SemiSharpCreases,          // edges with 0 < sharpness < 10
    InfinitelySharpCorners,    // vertices with sharpness >= 10
    SemiSharpCorners,          // vertices with 0 < sharpness < 10
    NonManifold,               // non-manifold edges or vertices
    ExtraordinaryVertices,     // interior valence != 4, boundary valence != 3
    AdjacentExtraordinary,     // faces with more than one extraordinary vertex
    ChaikinCreases,            // semi-sharp creases under the Chaikin crease method
    SmoothTriangleRule,        // triangles under the "smooth" triangle subdivision option
    NoBoundaryInterpolation,   // boundaries under the rule "none" (no surface along them)
    EdgeOnlyBoundaries,        // boundaries under "edges only" (smooth boundary corners)
};
inline constexpr uint32_t kCageFeatureCount = 15;
const char* cageFeatureName(CageFeature feature);  // "semi-sharp creases", ...

// How many elements (faces, edges or vertices) of a cage have each feature.
struct CageFeatures {
    std::array<uint32_t, kCageFeatureCount> count{};
    uint32_t maxValence = 0;
    bool has(CageFeature f) const { return count[uint32_t(f)] > 0; }
    uint32_t operator[](CageFeature f) const { return count[uint32_t(f)]; }
};
CageFeatures analyzeCage(const Cage& cage, const Topology& topology);

// What a scheme does with a feature. Features a scheme does not list are handled exactly.
enum class Handling : uint8_t {
    Exact,         // represented like the limit surface
    Approximated,  // drawn, but not as the limit surface would be: the text says how
    Unsupported,   // the scheme cannot draw such a cage at all: the text says why
};
struct FeatureRule {
    CageFeature feature;
    Handling handling;
    const char* text;  // for the user, e.g. "semi-sharp creases are drawn smooth"
};

struct SupportReport {
    std::vector<std::string> approximations;  // shown as warnings; the scheme still draws
    std::vector<std::string> refusals;        // non-empty: the scheme is skipped with these
    bool usable() const { return refusals.empty(); }
};
// The usual support(): each listed feature the cage has adds its text (with the element count).
SupportReport assessSupport(std::span<const FeatureRule> rules, const CageFeatures& features);

// ---- Settings, views, statistics ------------------------------------------------------------

struct SchemeSettings {
    uint32_t tessFactor = 8;        // segments along a quad sub-face edge (n-gon sub-faces: half)
    float adaptivePixels = 0.0f;    // > 0: screen-adaptive, target pixels per segment (if supported)
    uint32_t planDepth = 6;         // depth of the reference plans; exact schemes isolate to it
    // Scheme-specific `--option key=value` pairs; a scheme warns about keys it does not know.
    std::vector<std::pair<std::string, std::string>> options;
    const std::string* option(const std::string& key) const {
        for (const auto& [k, v] : options)
            if (k == key) return &v;
        return nullptr;
    }
};

struct GpuContext {
    const VulkanContext* vulkan = nullptr;
    VkPipelineCache cache = VK_NULL_HANDLE;  // may be null
    VkFormat colorFormat = VK_FORMAT_R8G8B8A8_UNORM;
    VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;
};

// A scheme draws in its cage's own coordinates. A scene's objects place cages by transforms: the
// host then passes each object's view in that object's space (objectView in scheme_host.h:
// viewProjection times the object's matrix, the eye brought into object space, pixelsPerUnit
// scaled with it), `clear` false for every object after the first and `sameFrame` true for the
// later objects of a cage.
struct DrawView {
    glm::mat4 viewProjection{1.0f};  // Vulkan clip space (render/camera.h), from the cage's coordinates
    glm::vec3 eye{0.0f};             // in the cage's coordinates
    glm::vec3 background{0.9f, 0.92f, 0.95f};  // linear; record() clears target.area to it
    bool clear = true;                // false: record() draws over what target.area holds
    // The linear part of the object's matrix (identity for a cage drawn alone): a scheme that
    // lights in world space brings its lights into the cage's coordinates with its inverse.
    glm::mat3 worldFromObject{1.0f};
    // True for the second and later objects drawing this scheme instance in one frame (instances
    // of one cage): draw the surface the previous record() laid out and evaluated, under this
    // view's matrix, instead of laying it out for this view (host-side data written now would
    // also change what the earlier draws of the same command buffer read).
    bool sameFrame = false;
    float pixelsPerUnit = 1.0f;       // for screen-adaptive factors (render/plan_pass.h)
    bool wireframe = false;           // tessellation wireframe over the surface, if supported
    std::string colorBy = "shading";  // one of Scheme::colorModes()
    Shading shading = Shading::Studio;  // how "shading" (and every colour mode) is lit
    // Sub-faces the editor hides (its hidden faces' sub-faces; sorted, each once): not drawn.
    // Empty: draw everything. The span is valid during record() only.
    std::span<const uint32_t> hiddenSubfaces;
    // Patches that cannot show a pixel in this view are skipped (docs/culling.md): outside the
    // frustum, and with a back-patch method (each with the frustum test) facing away on a
    // closed, outward surface seen from outside. Conservative: the picture is the unculled one,
    // pixel for pixel. A scheme that does not cull draws everything and leaves DrawStats::cull zero.
    CullMethod cull = CullMethod::None;
    // When set, record() writes here the sub-faces it culled whole this frame (sorted; a
    // sub-face drawn as several patches counts when all of them were culled): `quadplan
    // cull-stats` checks them against an ID buffer of the unculled frame.
    std::vector<uint32_t>* culledSubfacesOut = nullptr;
    // When set for a scheme whose Scheme::drawnPatches() gives triangles, record() writes here
    // the patches it culled this frame (sorted, in that numbering): `quadplan cull-stats` checks
    // each against an ID buffer of those triangles.
    std::vector<uint32_t>* culledPatchesOut = nullptr;
    // A scheme that writes its triangles on the host may leave out those that cover no pixel
    // centre of target.area (plans' CPU grid: render/sample_culling.h). The picture is the same;
    // false draws every triangle (benchmarks compare the two).
    bool sampleCulling = true;
    // The camera is moving (the editor's orbit, pan or zoom): a scheme whose factors follow the
    // view may keep those it chose for an earlier view, drawing them under this view's matrix
    // (progressive refinement: a cheaper frame now, full quality in the first frame without it).
    bool navigating = false;
};

// What the last record() submitted.
// How a draw reached the rasteriser.
enum class DrawnBy : uint32_t {
    Unknown,
    Tessellator,  // one patch primitive per patch through the tessellation stages
    GpuGrid,      // triangles over vertices a compute shader evaluated
    CpuMesh,      // triangles over vertices evaluated on the CPU
};
inline const char* drawnByName(DrawnBy by) {
    switch (by) {
    case DrawnBy::Tessellator: return "tess";
    case DrawnBy::GpuGrid: return "grid";
    case DrawnBy::CpuMesh: return "cpu";
    case DrawnBy::Unknown: break;
    }
    return "?";
}

struct DrawStats {
    uint64_t patches = 0;    // primitives through the tessellator, or patches drawn as grids
    uint64_t triangles = 0;  // 0 when unknown (screen-adaptive tessellation)
    // Of `triangles`, those the draw left out because they cover no pixel centre (plans' CPU
    // grid, render/sample_culling.h): the density is `triangles`, the rasteriser saw the rest.
    uint64_t sampleCulledTriangles = 0;
    // Of `triangles`, those left out as facing away behind the surface's front side (plans' CPU
    // grid under a back-patch cull method, render/sample_culling.h); not in sampleCulledTriangles.
    uint64_t facingAwayTriangles = 0;
    DrawnBy drawnBy = DrawnBy::Unknown;
    // DrawView::cull: what the tests culled (patches and triangles above leave the culled ones
    // out) and the CPU time they took this frame (bounds built after an update included).
    CullCounts cull;
    double cullMilliseconds = 0.0;
    // What the draw submitted: patch primitives through the tessellator, else triangles.
    uint64_t primitives() const { return drawnBy == DrawnBy::Tessellator ? patches : triangles; }
};

struct SchemeStats {
    uint64_t patches = 0;        // patches built (0: the scheme draws no patches)
    uint64_t controlPoints = 0;  // points computed per update (stencils applied, refined vertices)
    uint64_t gpuBytes = 0;       // buffers it keeps on the device
    uint64_t singleCreasePatches = 0;  // OpenSubdiv single-crease patches among `patches` (osd-fas)
};

// A point of a scheme's surface. `normal` is what the scheme shades with (a separate normal
// field for schemes that have one, else the unit normal of du x dv).
struct SurfacePoint {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};
    glm::vec3 du{0.0f}, dv{0.0f};  // zero when hasDerivatives is false
    bool hasDerivatives = false;
};

// The triangles record() draws for the unculled frame, each vertex numbered by the patch
// (culling entry) it belongs to; no vertex is shared between patches, so every triangle has one
// number. For the ID buffer of `quadplan cull-stats` (render/id_pass.h).
struct PatchTriangles {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> patchOfVertex;  // parallel to positions
    std::vector<uint32_t> indices;        // three per triangle
    uint32_t patchCount = 0;
};

// What a tag or topology edit did to the planned cage a scheme was built for (PlannedCage is
// edited in place: core/plans/planned_cage.h EditReport).
struct PlanChange {
    std::span<const uint32_t> subfaces;  // sorted: sub-faces whose plan, rotation or control
                                         // points changed (the numbering after the edit)
    bool topologyChanged = false;        // faces or vertices were renumbered (a topology edit)
    // Topology edits: per sub-face now, its number before the edit, or UINT32_MAX for a new one.
    // A sub-face that maps and is not in `subfaces` is the same surface as before (its 1-ring
    // may be renumbered); the cage's vertices, edges and faces may all have new numbers.
    std::span<const uint32_t> previousSubfaceOf;
};
enum class PlanUpdate : uint8_t {
    Updated,  // record() and evaluate() now show the edited cage
    Rebuild,  // the host must make a new instance (build, createGpu, update)
};

// ---- The scheme ----------------------------------------------------------------------------

class Scheme {
public:
    virtual ~Scheme() = default;

    virtual SupportReport support(const CageFeatures& features, const SchemeSettings& settings) const = 0;
    // `planned` (cage, topology, tags, positions, plans) outlives the scheme instance, and its
    // positions may change between update() calls; its topology does not (a new topology gets
    // a new instance).
    virtual Status build(const PlannedCage& planned, const SchemeSettings& settings) = 0;
    virtual Status createGpu(const GpuContext& gpu) = 0;
    virtual Status update() = 0;
    // Like update(), when only `vertices` (sorted, unique) moved since the last update or
    // updateMoved. The limit over a sub-face depends on its 1-ring only, so a scheme can
    // refresh just the sub-faces whose 1-ring holds a moved vertex. The host calls it while
    // the device is not using the scheme's buffers, as for update().
    virtual Status updateMoved(std::span<const uint32_t> vertices) {
        (void)vertices;
        return update();
    }
    // The planned cage given to build() was edited in place (tags re-planned some sub-faces, or
    // a topology edit renumbered it). A scheme that can update what it keeps for just
    // `change.subfaces` does so and returns Updated; Rebuild (the default) or a failure makes the
    // host build a new instance instead (a failure is reported, the picture never goes stale).
    // Called while the device is not using the scheme's buffers, as update() is. A displacement
    // set before stays set and must still match the sub-faces.
    virtual Result<PlanUpdate> updatePlans(const PlanChange& change) {
        (void)change;
        return PlanUpdate::Rebuild;
    }
    // True when updatePlans can update in place (at least for some edits): `quadplan schemes`
    // and the editor say which schemes rebuild after an edit.
    virtual bool updatesPlansInPlace() const { return false; }
    // True when topology edits (PlanChange::topologyChanged) are among them.
    virtual bool updatesTopologyInPlace() const { return false; }
    // True when record() leaves out DrawView::hiddenSubfaces; the editor warns in the viewports of
    // schemes that draw them anyway.
    virtual bool hidesSubfaces() const { return false; }
    // Fails, saying why, when the frame cannot be made (a buffer larger than the device makes);
    // target.area is cleared all the same.
    virtual Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) = 0;
    // out[i] = the surface at requests[i]; requests name sub-faces with a surface only. Called
    // concurrently from several threads on disjoint spans.
    virtual void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const = 0;
    virtual SchemeStats stats() const = 0;
    // A scheme whose culling leaves out patches smaller than a sub-face (osd-fas' Far patches
    // next to an extraordinary vertex) gives the triangles it draws, numbered by patch, so that
    // every culled patch can be checked against an ID buffer of them (DrawView::culledPatchesOut).
    // On a tessellator path: the same patches tessellated on the host as close to the
    // tessellator as it can. None (the default): the ID buffer numbers sub-faces, and only the
    // sub-faces a scheme culls whole are checked against it.
    virtual Result<PatchTriangles> drawnPatches() const { return PatchTriangles{}; }
    // Colour modes record() understands; the first is the default ("shading").
    virtual std::vector<std::string> colorModes() const { return {"shading"}; }
    virtual void destroyGpu() = 0;

    // ---- Displacement (docs/displacement.md; optional) ----
    // Sculpted displacement: every scheme draws s + D N, where s, its derivatives and the unit
    // normal N are the SCHEME'S OWN at (sub-face, u, v) and D = evaluateDisplacement(*d, sub-face,
    // u, v) (core/displacement/displacement.h); the shading normal is displacePoint's (it includes D's
    // derivatives). Shared boundary vertices must stay bit-identical: evaluate them through one
    // owner, as buildDisplacedMesh (core/displacement/displaced_mesh.h) does. The tessellation factor must
    // follow the tile resolutions (at least requiredMeshFactor / requiredTessellationFactor).
    // evaluate() keeps returning the surface WITHOUT displacement (the host compares it with the
    // undisplaced limit surface).
    //
    // setDisplacement: after build(); nullptr (or an empty one) removes it. `*displacement` must
    // match the planned cage's sub-faces and outlive the instance or the next call; the scheme
    // reads it, never writes it. It is drawn from the next update() on. The default refuses a
    // displacement, so that a scheme that cannot draw it says so rather than drawing without it.
    virtual Status setDisplacement(const Displacement* displacement) {
        if (!displacement || displacement->empty()) return success();
        return Error{"this scheme does not draw sculpted displacement"};
    }
    // `samples` (indices into Displacement::samples, any order, repeats allowed: e.g.
    // Sculptor::lastDabSamples() after a dab, core/displacement/brush.h) changed in place; the layout is the
    // one given to setDisplacement. Bring what record() draws up to date, ideally only around
    // them (uploadRanges gives the buffer regions). Default: a full update().
    virtual Status displacementChanged(std::span<const uint32_t> samples) {
        (void)samples;
        return update();
    }
};

// ---- The module entry point ----------------------------------------------------------------

// Compiler and standard library the module was built with (must equal the host's).
#define QUADPLAN_SCHEME_ABI_TAG "gcc-compatible " __VERSION__ " libstdc++ cxx11-abi " QP_STRINGIFY(_GLIBCXX_USE_CXX11_ABI)
#define QP_STRINGIFY_(x) #x
#define QP_STRINGIFY(x) QP_STRINGIFY_(x)

// Sizes of the types that cross the boundary: a module built against different core or
// render headers (without an API bump) differs here and is refused.
inline constexpr uint64_t kSchemeLayoutFingerprint =
    (((((uint64_t(sizeof(Cage)) * 1009 + sizeof(PlannedCage)) * 1009 + sizeof(Topology)) * 1009 +
       sizeof(VulkanContext)) * 1009 + sizeof(RenderTarget)) * 1009 + sizeof(SchemeSettings)) * 1009 +
    sizeof(DrawView) * 31 + sizeof(SurfacePoint) * 7 + sizeof(SampleRequest) + sizeof(Displacement) * 3;

struct SchemeModule {
    uint32_t apiVersion;  // kSchemeApiVersion; stays the first member in every version
    const char* abiTag;   // QUADPLAN_SCHEME_ABI_TAG; stays the second
    uint64_t layoutFingerprint;
    const char* name;     // what --schemes names: lower case, digits and '-'
    const char* summary;  // one line for `quadplan schemes`
    Scheme* (*create)();  // a new instance, or nullptr; the host deletes it
};

// The C symbol the loader looks up.
#define QUADPLAN_SCHEME_ENTRY "quadplan_scheme_module"
using SchemeEntryFunction = const SchemeModule* (*)();

// In exactly one .cpp of a module: QUADPLAN_EXPORT_SCHEME("acc1", "one-line summary", Acc1Scheme)
#define QUADPLAN_EXPORT_SCHEME(NAME, SUMMARY, CLASS)                                                 \
    extern "C" __attribute__((visibility("default"))) const ::qp::SchemeModule* quadplan_scheme_module() { \
        static const ::qp::SchemeModule module{::qp::kSchemeApiVersion, QUADPLAN_SCHEME_ABI_TAG,     \
                                               ::qp::kSchemeLayoutFingerprint, NAME, SUMMARY,        \
                                               []() -> ::qp::Scheme* { return new CLASS(); }};       \
        return &module;                                                                              \
    }

}  // namespace qp
