// `pn`: PN-triangles (Vlachos et al. 2001; pn.h, README.md) on the cage's triangles, its quads
// split along the shorter diagonal and its other polygons fanned: a cubic Bezier triangle and a
// quadratic normal patch per triangle, from the cage's positions and vertex normals only. It
// interpolates the cage instead of approximating the Catmull-Clark limit.
//
// Drawn one triangle patch per PN triangle through the tessellator (16 points in a storage
// buffer, pn.tese) or on the CPU grid: tess_patch_scheme.h. update() rebuilds the patches.
//
// Culling (DrawView::cull): per PN triangle on the tessellated path, per sub-face on the grid
// (the triangles covering it). A PN triangle is bounded by the box of its 10 points (a Bézier
// triangle lies in their hull) and by cubicTriangleNormalCone (patch_culling.h): its normals
// B_2 x B_3 are cross products of two derivatives, each a non-negative combination of the
// control points' differences in its direction, so Sederberg and Meyers' rule bounds them (the
// geometry's own normals decide what shows; PN's normal patch only shades). That cone serves
// tcone, ncone and pplane alike.
#include "pn.h"
#include "tess_patch_scheme.h"

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

struct PnTraits {
    static constexpr const char* kName = "pn";
    static constexpr const char* kTessControl = "pn.tesc";
    static constexpr const char* kTessEvaluation = "pn.tese";
    static constexpr const char* kApproximates =
        "pn interpolates the cage (its vertices and averaged vertex normals): it does not approximate the "
        "Catmull-Clark limit surface anywhere";
    static constexpr bool kTriangles = true;
    using Data = PnPatches;
    static std::span<const FeatureRule> rules() { return kRules; }
    static Result<Data> build(const Cage& cage) { return buildPn(cage, kName); }
    static uint32_t patchCount(const Data& data) { return data.stats.triangles; }
    static uint32_t controlPoints(const Data& data) { return data.stats.controlPoints; }
    // PN's triangles, 16 vec4 each: the 10 position points, then the 6 normal points.
    static std::vector<glm::vec4> packPatches(const Data& patches) {
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
    // A PN triangle's edges are cage edges (or spokes of a fan), each one quad sub-face edge long
    // or two n-gon sub-face edges: the full factor.
    static uint32_t edgeFactor(const Data&, uint32_t factor) { return factor; }

    // du, dv are PN's shading frame: the cubic geometry's derivatives projected onto the plane
    // of the normal patch's normal (as acc1 returns its tangent patches). The geometry is only
    // C0 (across the quads' split diagonals too), so its own derivatives would make a displaced
    // surface (displacePoint: (du + D_u N) x (dv + D_v N)) shade with the geometry's kinks
    // instead of PN's normal field, even where D is flat.
    static SurfacePoint evaluate(const Data& data, uint32_t subface, float u, float v) {
        const PnSample s = evaluatePn(data, subface, u, v);
        const glm::vec3 du = s.du - glm::dot(s.du, s.normal) * s.normal, dv = s.dv - glm::dot(s.dv, s.normal) * s.normal;
        return SurfacePoint{s.position, s.normal, du, dv, s.valid};
    }

    // Which sub-faces each triangle covers: a quad's one sub-face both its triangles, a triangle's
    // three sub-faces its one triangle, an n-gon's sub-face k its fan triangles k and k - 1 (pn.h).
    static PatchCover cover(const Data& patches) {
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
    static CullAdjacency adjacency(const Data& patches, const PlannedCage& planned) {
        const Topology& topology = planned.topology();
        std::vector<std::vector<uint32_t>> groups(planned.cage().vertexCount() + planned.cage().faceCount());
        auto addFace = [&](std::vector<uint32_t>& group, uint32_t face) {
            for (uint32_t t = patches.faceFirstTriangle[face]; t < patches.faceFirstTriangle[face + 1]; ++t) group.push_back(t);
        };
        for (uint32_t v = 0; v < planned.cage().vertexCount(); ++v)
            for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k)
                addFace(groups[v], topology.vertexFaces[k]);
        for (uint32_t f = 0; f < planned.cage().faceCount(); ++f) addFace(groups[planned.cage().vertexCount() + f], f);
        return adjacencyOfGroups(patches.stats.triangles, groups);
    }
    static glm::vec3 anchor(const Data& data, uint32_t t) { return data.positions[size_t(t) * PnPatches::kPositionPoints]; }
    static void addCullLeaves(const Data& data, uint32_t t, const glm::vec3& origin, PatchCullLeaves& leaves) {
        const glm::vec3* geometry = &data.positions[size_t(t) * PnPatches::kPositionPoints];  // CubicTrianglePoints' order
        addCubicTriangleLeaf(leaves, pointsRelativeTo<PnPatches::kPositionPoints>(geometry, origin));
    }
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("pn",
                       "PN-triangles (Vlachos et al. 2001) on the cage's triangles, split quads and fanned polygons: "
                       "interpolates the cage, drawn through the tessellator",
                       qp::TessPatchScheme<qp::PnTraits>)
