// `pn`: PN-triangles (Vlachos et al. 2001; pn.h, README.md) on the cage's triangles, its quads
// split along the shorter diagonal and its other polygons fanned: a cubic Bezier triangle and a
// quadratic normal patch per triangle, from the cage's positions and vertex normals only. It
// interpolates the cage instead of approximating the Catmull-Clark limit.
//
// Drawing: path=tess (default) draws one triangle patch per PN triangle through the
// tessellator (16 points in a storage buffer, pn.tese); path=cpu evaluates them on a sub-face
// grid on all cores and draws the triangles (grid_drawing.h). update() rebuilds the patches.
//
// Culling (DrawView::cull): per PN triangle on the tessellated path, per sub-face on the grid
// (the triangles covering it). A PN triangle is bounded by the box of its 10 points (a Bézier
// triangle lies in their hull) and by cubicTriangleNormalCone (patch_culling.h): its normals
// B_2 x B_3 are cross products of two derivatives, each a non-negative combination of the
// control points' differences in its direction, so Sederberg and Meyers' rule bounds them (the
// geometry's own normals decide what shows; PN's normal patch only shades). That cone serves
// tcone, ncone and pplane alike. Back-patch tests only on a closed, outward cage.
#include "grid_drawing.h"
#include "mesh/closed_surface.h"
#include "module_shader_code.h"
#include "pn.h"
#include "scheme_api.h"
#include "scheme_culling.h"
#include "tess_patch_pass.h"

namespace qp {
namespace {

constexpr FeatureRule kRules[] = {
    {CageFeature::SemiSharpCreases, Handling::Approximated, "pn ignores creases (it sees no neighbours)"},
    {CageFeature::InfinitelySharpCreases, Handling::Approximated, "pn ignores creases (it sees no neighbours)"},
    {CageFeature::SemiSharpCorners, Handling::Approximated, "pn ignores corner tags"},
    {CageFeature::InfinitelySharpCorners, Handling::Approximated, "pn ignores corner tags"},
    {CageFeature::Boundaries, Handling::Approximated,
     "pn interpolates the boundary polygon instead of the limit boundary curve"},
    {CageFeature::NoBoundaryInterpolation, Handling::Approximated,
     "pn also draws the faces along the boundary that the rule 'none' leaves without surface"},
    {CageFeature::NonQuadFaces, Handling::Approximated, "pn fans polygons with more than four sides around their centroid"},
    {CageFeature::NonManifold, Handling::Approximated, "pn averages vertex normals over every face at a non-manifold vertex"},
};

// PN's triangles, 16 vec4 each: the 10 position points, then the 6 normal points.
std::vector<glm::vec4> packTriangles(const PnPatches& patches) {
    std::vector<glm::vec4> points;
    points.reserve(size_t(patches.stats.triangles) * 16);
    for (uint32_t t = 0; t < patches.stats.triangles; ++t) {
        for (uint32_t i = 0; i < PnPatches::kPositionPoints; ++i)
            points.push_back(glm::vec4(patches.positions[size_t(t) * PnPatches::kPositionPoints + i], 1.0f));
        for (uint32_t i = 0; i < PnPatches::kNormalPoints; ++i)
            points.push_back(glm::vec4(patches.normals[size_t(t) * PnPatches::kNormalPoints + i], 0.0f));
    }
    return points;
}

// Which sub-faces each triangle covers: a quad's one sub-face both its triangles, a triangle's
// three sub-faces its one triangle, an n-gon's sub-face k its fan triangles k and k - 1 (pn.h).
PatchCover pnCover(const PnPatches& patches) {
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    for (uint32_t f = 0; f + 1 < patches.faceFirstTriangle.size(); ++f) {
        const uint32_t t0 = patches.faceFirstTriangle[f], triangles = patches.faceFirstTriangle[f + 1] - t0;
        const uint32_t n = patches.faceSize[f], s0 = patches.faceFirstSubface[f];
        if (triangles == 0) continue;  // a hole
        for (uint32_t k = 0; k < patches.faceFirstSubface[f + 1] - s0; ++k) {
            if (n == 3) pairs.push_back({s0 + k, t0});
            if (n == 4) pairs.insert(pairs.end(), {{s0, t0}, {s0, t0 + 1}});
            if (n > 4) pairs.insert(pairs.end(), {{s0 + k, t0 + k}, {s0 + k, t0 + (k + n - 1) % n}});
        }
    }
    return patchCover(patches.faceFirstSubface.back(), patches.stats.triangles, std::move(pairs));
}

// Triangles that may share a point: those of faces around a cage vertex, and of one face.
CullAdjacency pnAdjacency(const PnPatches& patches, const PlannedCage& planned) {
    const Topology& topology = planned.topology();
    std::vector<std::vector<uint32_t>> groups(planned.cage().vertexCount() + planned.cage().faceCount());
    auto addFace = [&](std::vector<uint32_t>& group, uint32_t face) {
        for (uint32_t t = patches.faceFirstTriangle[face]; t < patches.faceFirstTriangle[face + 1]; ++t) group.push_back(t);
    };
    for (uint32_t v = 0; v < planned.cage().vertexCount(); ++v)
        for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k) addFace(groups[v], topology.vertexFaces[k]);
    for (uint32_t f = 0; f < planned.cage().faceCount(); ++f) addFace(groups[planned.cage().vertexCount() + f], f);
    return adjacencyOfGroups(patches.stats.triangles, groups);
}

class PnScheme final : public Scheme {
public:
    SupportReport support(const CageFeatures& features, const SchemeSettings& settings) const override {
        SupportReport report;
        report.approximations.push_back(
            "pn interpolates the cage (its vertices and averaged vertex normals): it does not approximate the "
            "Catmull-Clark limit surface anywhere");
        SupportReport rules = assessSupport(kRules, features);
        report.approximations.insert(report.approximations.end(), rules.approximations.begin(), rules.approximations.end());
        checkPatchOptions(report, settings, "pn");
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        settings_ = settings;
        Result<PatchPath> path = patchPathOption(settings, "pn");
        if (!path) return path.error();
        path_ = *path;
        if (Status built = rebuild(); !built) return built;
        prepareGridDrawing(grid_, planned, settings.adaptivePixels > 0.0f ? 16u : settings.tessFactor);
        culling_ = PatchCulling{pnCover(patches_), closedOutwardSurface(planned.cage(), planned.topology()),
                                pnAdjacency(patches_, planned), subfaceAdjacency(planned)};
        return success();
    }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        // The grid draws the CPU path, and the tessellated path while displaced.
        if (Status grid = createGridDrawing(grid_, gpu); !grid) return grid;
        if (path_ == PatchPath::Cpu) return success();
        Result<TessPatchPass> pass =
            createTessPatchPass(*ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat,
                                {moduleShaderCode("tess_patch.vert"), moduleShaderCode("pn.tesc"), moduleShaderCode("pn.tese"), {}});
        if (!pass) return Error{"pn: " + pass.error().message + " (use --option path=cpu)"};
        pass_ = *pass;
        havePass_ = true;
        return success();
    }

    Status update() override {
        culling_.bounds.reset();
        if (Status built = rebuild(); !built) return built;
        if (onGrid()) return updateGridDrawing(grid_, *this);
        if (!havePass_) return success();
        const std::vector<glm::vec4> points = packTriangles(patches_);
        return uploadTessPatches(*ctx_, pass_, points.data(), points.size() * sizeof(glm::vec4), patches_.stats.triangles);
    }

    Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        DrawStats stats;
        const PatchBounds bounds = triangleBounds();
        if (onGrid()) {
            const std::vector<uint32_t> culled = cullSubfacesForView(culling_, bounds, grid_.displacement, view, stats);
            return recordGridDrawing(cmd, grid_, target, view, stats, culled);
        }
        const std::vector<uint32_t> culled = cullPatchesForView(culling_, bounds, view, stats);
        // A PN triangle's edges are cage edges (or spokes of a fan), each one quad sub-face edge
        // long or two n-gon sub-face edges: the full factor.
        const uint32_t factor = settings_.adaptivePixels > 0.0f ? 0u : settings_.tessFactor;
        recordTessPatches(cmd, pass_, target, view, {factor, settings_.adaptivePixels, false}, culled);
        stats.patches = patches_.stats.triangles - culled.size();
        stats.triangles = factor ? stats.patches * tessTriangles(factor, true) : 0;
        stats.drawnBy = DrawnBy::Tessellator;
        return stats;
    }

    // Sculpted displacement: this scheme's own surface moved along its own normal, drawn on the
    // CPU grid (grid_drawing.h) whichever path was chosen; evaluate() stays undisplaced.
    Status setDisplacement(const Displacement* displacement) override {
        culling_.bounds.reset();
        return setGridDisplacement(grid_, displacement);
    }
    Status displacementChanged(std::span<const uint32_t> samples) override {
        culling_.bounds.reset();  // the margins follow |D|
        return gridDisplacementChanged(grid_, samples);
    }

    // du, dv are PN's shading frame: the cubic geometry's derivatives projected onto the plane
    // of the normal patch's normal (as acc1 returns its tangent patches). The geometry is only
    // C0 (across the quads' split diagonals too), so its own derivatives would make a displaced
    // surface (displacePoint: (du + D_u N) x (dv + D_v N)) shade with the geometry's kinks
    // instead of PN's normal field, even where D is flat.
    void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const override {
        for (size_t i = 0; i < requests.size(); ++i) {
            const PnSample s = evaluatePn(patches_, requests[i].subface, requests[i].u, requests[i].v);
            const glm::vec3 du = s.du - glm::dot(s.du, s.normal) * s.normal, dv = s.dv - glm::dot(s.dv, s.normal) * s.normal;
            out[i] = SurfacePoint{s.position, s.normal, du, dv, s.valid};
        }
    }

    SchemeStats stats() const override {
        return SchemeStats{patches_.stats.triangles, patches_.stats.controlPoints,
                           onGrid() ? gridDrawingBytes(grid_) : pass_.patchData.size};
    }

    void destroyGpu() override {
        if (!ctx_) return;
        destroyGridDrawing(grid_);
        if (havePass_) destroyTessPatchPass(*ctx_, pass_);
        havePass_ = false;
        ctx_ = nullptr;
    }

private:
    bool onGrid() const { return path_ == PatchPath::Cpu || grid_.displacement; }

    // The geometry of each PN triangle as a culling leaf.
    PatchBounds triangleBounds() const {
        const glm::vec3* positions = patches_.positions.data();
        return PatchBounds{patches_.stats.triangles,
                           [positions](uint32_t t) { return positions[size_t(t) * PnPatches::kPositionPoints]; },
                           [positions](uint32_t t, const glm::vec3& origin, PatchCullLeaves& leaves) {
                               CubicTrianglePoints points;  // pn.h's order is CubicTrianglePoints'
                               for (uint32_t k = 0; k < PnPatches::kPositionPoints; ++k)
                                   points[k] = positions[size_t(t) * PnPatches::kPositionPoints + k] - origin;
                               addCubicTriangleLeaf(leaves, points);
                           }};
    }

    Status rebuild() {
        Result<PnPatches> patches = buildPn(planned_->cage(), "pn");
        if (!patches) return patches.error();
        patches_ = std::move(*patches);
        return success();
    }

    const PlannedCage* planned_ = nullptr;
    SchemeSettings settings_;
    PatchPath path_ = PatchPath::Tessellated;
    PnPatches patches_;
    const VulkanContext* ctx_ = nullptr;
    TessPatchPass pass_;
    bool havePass_ = false;
    GridDrawing grid_;
    PatchCulling culling_;
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("pn",
                       "PN-triangles (Vlachos et al. 2001) on the cage's triangles, split quads and fanned polygons: "
                       "interpolates the cage, drawn through the tessellator",
                       qp::PnScheme)
