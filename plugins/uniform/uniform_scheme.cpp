// `uniform`: table-driven uniform Catmull-Clark refinement (Loop 2010 §3) drawn as triangles
// (uniform_refinement.h). Every base quad becomes (2^L)^2 quads, two triangles each, with
// L = round(log2 of the tessellation factor), so the triangle density matches the plans' grid
// at the same factor. The refined vertices are not pushed to the limit: the surface is the
// refined mesh, and its error shrinks about fourfold per level.
//
// Options: level=L (1..8) overrides the level derived from the factor.
//
// Tag edits (sharpness, corners, holes) update in place: the refinement tables are rewritten
// around the re-planned faces from a local refinement (updateUniformTags), and the refined mesh
// is applied again as after a vertex move; topology edits rebuild.
//
// Displacement: the refined surface (sampleRefined, its own normals) on a grid of at least
// 2^L and at least the tiles' required factor, displaced and made watertight through
// a DisplacedDrawing (displaced_drawing.h: a dab re-displaces only what it reached).
//
// Culling (DrawView::cull) is per base face: its entry is the drawn triangles of its refined
// quads, each a flat leaf (patch_cull_set.h): the box of their points; for tcone and ncone the
// cone of their normals (the exact set of the face's normals: the surface drawn is these flat
// triangles); for pplane every triangle's own plane, so a face is culled exactly when every one
// of its triangles faces away. The indices are ordered by face, and a frame draws the ranges of
// the faces kept; a face facing away is culled only when no face around it is drawn
// (scheme_culling.h: at a fold a back-facing triangle can win the depth test along the edge it
// shares with a front-facing one). Displaced: per sub-face grid, frustum only, each box grown by
// its tile's largest |D|. Back-patch tests only on a closed, outward cage.
#include <algorithm>
#include <cmath>
#include <string>

#include "displaced_drawing.h"
#include "mesh/closed_surface.h"
#include "mesh_pass.h"
#include "scheme_api.h"
#include "scheme_culling.h"
#include "scheme_support.h"
#include "uniform_refinement.h"

namespace qp {
namespace {

constexpr FeatureRule kRules[] = {
    {CageFeature::SmoothTriangleRule, Handling::Approximated,
     "uniform refines triangles with the Catmark rule, not the smooth triangle rule"},
};

class UniformScheme final : public Scheme {
public:
    SupportReport support(const CageFeatures& features, const SchemeSettings& settings) const override {
        SupportReport report = assessSupport(kRules, features);
        if (settings.adaptivePixels > 0.0f)
            report.approximations.push_back("uniform has no screen-adaptive mode: it refines to level 4");
        for (const auto& [key, value] : settings.options) {
            if (key != "level") report.approximations.push_back("uniform ignores the unknown option '" + key + "'");
            else if (parseLevel(value) == 0) report.refusals.push_back("uniform: level must be 1..8, got '" + value + "'");
        }
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        uint32_t level = settings.adaptivePixels > 0.0f
                             ? 4u
                             : uint32_t(std::clamp(std::lround(std::log2(double(std::max(1u, settings.tessFactor)))), 1l, 8l));
        if (const std::string* text = settings.option("level")) level = parseLevel(*text);
        if (level == 0) return Error{"uniform: level must be 1..8"};
        Result<UniformRefinement> refinement = buildUniformRefinement(planned, level);
        if (!refinement) return refinement.error();
        refinement_ = std::move(*refinement);
        level_ = level;
        fillIndices();
        std::vector<std::pair<uint32_t, uint32_t>> pairs;  // each sub-face is covered by its face
        for (uint32_t f = 0; f < planned.cage().faceCount(); ++f)
            for (uint32_t s = planned.firstSubface(f); s < planned.firstSubface(f + 1); ++s) pairs.push_back({s, f});
        culling_ = PatchCulling{patchCover(planned.subfaceCount(), planned.cage().faceCount(), std::move(pairs)),
                                closedOutwardSurface(planned.cage(), planned.topology()),
                                adjacencyOfGroups(planned.cage().faceCount(), facesAroundVertices(planned)), {}};
        return success();
    }

    // Tag edits keep the refined topology: the tables are rewritten around the re-planned
    // sub-faces (updateUniformTags), then everything is applied again as after a move.
    Result<PlanUpdate> updatePlans(const PlanChange& change) override {
        if (change.topologyChanged) return PlanUpdate::Rebuild;
        if (Status s = updateUniformTags(refinement_, *planned_, change.subfaces); !s) return s.error();
        fillIndices();
        culling_.closed = closedOutwardSurface(planned_->cage(), planned_->topology());  // holes may have changed
        if (Status s = update(); !s) return s.error();
        return PlanUpdate::Updated;
    }
    bool updatesPlansInPlace() const override { return true; }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        return createSchemeMeshPass(pass_, gpu);
    }

    Status update() override {
        culling_.bounds.reset();
        applyUniformRefinement(refinement_, planned_->cage().positions, buffer_);
        const uint32_t first = refinement_.levelOffset[refinement_.levels];
        finest_ = std::span<const glm::vec3>(buffer_).subspan(first, refinement_.finestVertexCount());
        normals_ = refinedNormals(refinement_, finest_);
        if (!ctx_) return success();
        if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
        if (indices_.empty()) return success();
        if (displacement_) {
            const uint32_t factor = displacedGridFactor(*planned_, *displacement_, 1u << level_);
            return buildDisplacedDrawing(displaced_, *ctx_, *this, *planned_, *displacement_, factor);
        }
        destroyDisplacedDrawing(displaced_);
        return replaceMesh(*ctx_, mesh_, meshVertices(finest_, normals_), indices_);
    }

    Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        DrawStats stats;
        const PatchBounds bounds = faceBounds();
        if (displacement_) {
            const std::vector<uint32_t> culled = cullSubfacesForView(culling_, bounds, displacement_, view, stats);
            recordDisplacedParts(cmd, pass_, target, view, displaced_, culled, stats);
        } else {
            const std::vector<uint32_t> culled = cullPatchesForView(culling_, bounds, view, stats);
            const std::vector<IndexRange> parts = keptIndexRanges(faceFirstIndex_, culled);
            recordMeshParts(cmd, pass_, target, view, mesh_, culled.empty() ? nullptr : &parts, stats);
        }
        stats.patches = 0;  // uniform draws no patches, only triangles
        return stats;
    }

    Status setDisplacement(const Displacement* displacement) override {
        culling_.bounds.reset();
        displacement_ = displacementToDraw(displacement);
        return success();
    }

    Status displacementChanged(std::span<const uint32_t> samples) override {
        culling_.bounds.reset();  // the margins follow |D|
        return updateDisplacedDrawing(displaced_, samples);
    }

    void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const override {
        for (size_t i = 0; i < requests.size(); ++i) {
            const RefinedSample s = sampleRefined(refinement_, finest_, normals_, requests[i].subface, requests[i].u, requests[i].v);
            out[i] = SurfacePoint{s.position, s.normal, s.du, s.dv, true};
        }
    }

    SchemeStats stats() const override {
        SchemeStats stats;
        stats.controlPoints = refinement_.levelOffset.empty() ? 0 : refinement_.levelOffset.back() - refinement_.levelOffset[1];
        stats.gpuBytes = mesh_.vertices.size + mesh_.indices.size + displaced_.gpu.vertices.size + displaced_.gpu.indices.size;
        return stats;
    }

    void destroyGpu() override {
        if (!ctx_) return;
        if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
        destroyDisplacedDrawing(displaced_);
        destroyMeshPass(*ctx_, pass_);
        ctx_ = nullptr;
    }

private:
    // Two triangles per drawn quad, the quads ordered by sub-face (so by face: Far refines in that
    // order already, the sort only makes sure), and where each face's indices begin.
    void fillIndices() {
        faceQuads_ = refinement_.drawnQuads;
        const std::vector<RefinedQuad>& quads = refinement_.quads;
        std::stable_sort(faceQuads_.begin(), faceQuads_.end(),
                         [&quads](uint32_t a, uint32_t b) { return quads[a].subface < quads[b].subface; });
        const uint32_t faces = planned_->cage().faceCount();
        faceFirstQuad_.assign(faces + 1, 0);
        for (uint32_t i : faceQuads_) ++faceFirstQuad_[faceOfSubface(*planned_, quads[i].subface) + 1];
        for (uint32_t f = 0; f < faces; ++f) faceFirstQuad_[f + 1] += faceFirstQuad_[f];
        faceFirstIndex_.resize(faces + 1);
        for (uint32_t f = 0; f <= faces; ++f) faceFirstIndex_[f] = 6 * faceFirstQuad_[f];
        indices_.clear();
        indices_.reserve(6 * faceQuads_.size());
        for (uint32_t i : faceQuads_) {
            const uint32_t* v = quads[i].vertices;
            indices_.insert(indices_.end(), {v[0], v[1], v[2], v[0], v[2], v[3]});
        }
    }

    // Each face's drawn triangles as flat culling leaves.
    PatchBounds faceBounds() const {
        return PatchBounds{planned_->cage().faceCount(),
                           [this](uint32_t f) {
                               return faceFirstQuad_[f] == faceFirstQuad_[f + 1]
                                          ? glm::vec3(0.0f)
                                          : finest_[refinement_.quads[faceQuads_[faceFirstQuad_[f]]].vertices[0]];
                           },
                           [this](uint32_t f, const glm::vec3& origin, PatchCullLeaves& leaves) {
                               for (uint32_t k = faceFirstQuad_[f]; k < faceFirstQuad_[f + 1]; ++k) {
                                   const uint32_t* v = refinement_.quads[faceQuads_[k]].vertices;
                                   const glm::vec3 p0 = finest_[v[0]] - origin, p1 = finest_[v[1]] - origin,
                                                   p2 = finest_[v[2]] - origin, p3 = finest_[v[3]] - origin;
                                   addFlatTriangle(leaves, p0, p1, p2);
                                   addFlatTriangle(leaves, p0, p2, p3);
                               }
                           }};
    }

    static uint32_t parseLevel(const std::string& text) {
        char* end = nullptr;
        const long level = std::strtol(text.c_str(), &end, 10);
        return (!text.empty() && *end == '\0' && level >= 1 && level <= 8) ? uint32_t(level) : 0u;
    }

    const PlannedCage* planned_ = nullptr;
    UniformRefinement refinement_;
    uint32_t level_ = 1;
    std::vector<uint32_t> indices_;
    std::vector<uint32_t> faceQuads_;       // the drawn quads in index order (by face)
    std::vector<uint32_t> faceFirstQuad_;   // per face: its quads in faceQuads_ (faces + 1)
    std::vector<uint32_t> faceFirstIndex_;  // per face: its first index (faces + 1)
    PatchCulling culling_;
    const Displacement* displacement_ = nullptr;
    std::vector<glm::vec3> buffer_, normals_;
    std::span<const glm::vec3> finest_;

    const VulkanContext* ctx_ = nullptr;
    MeshPass pass_;
    GpuMesh mesh_;                // undisplaced
    DisplacedDrawing displaced_;  // with a displacement
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("uniform",
                       "table-driven uniform Catmull-Clark refinement (Loop 2010 section 3) drawn as triangles",
                       qp::UniformScheme)
