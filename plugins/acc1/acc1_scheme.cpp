// `acc1`: Loop and Schaefer 2008 (acc1.h, README.md): per quad of the (once refined, for
// non-quad cages) cage a bicubic Bezier geometry patch and two tangent patches whose cross
// product is the shading normal, 40 control points.
//
// Drawn through the tessellator (acc1.tesc, acc1.tese) or on the CPU grid: tess_patch_scheme.h.
// Culling bounds a patch by its bicubic Bézier geometry patch, the surface drawn (box, tcone,
// ncone, pplane); the tangent patches only shade.
#include "acc1.h"
#include "tess_patch_scheme.h"

namespace qp {
namespace {

constexpr FeatureRule kRules[] = {
    {CageFeature::ExtraordinaryVertices, Handling::Approximated,
     "acc1 approximates the surface next to extraordinary vertices (bicubic patches, only C0 across their "
     "edges there, shaded with separate tangent patches; exact on regular quads)"},
    {CageFeature::SemiSharpCreases, Handling::Approximated, "acc1 draws semi-sharp creases smooth"},
    {CageFeature::InfinitelySharpCreases, Handling::Approximated, "acc1 draws infinitely sharp creases smooth"},
    {CageFeature::SemiSharpCorners, Handling::Approximated, "acc1 draws sharp corners smooth"},
    {CageFeature::InfinitelySharpCorners, Handling::Approximated, "acc1 draws sharp corners smooth"},
    {CageFeature::NonQuadFaces, Handling::Approximated,
     "acc1 refines cages with non-quad faces once first (tags act in that step only; 4 patches per quad)"},
    {CageFeature::NonManifold, Handling::Unsupported, "acc1 needs a manifold cage (a fan of quads around every vertex)"},
};

struct Acc1Traits : QuadPatchTraits<Acc1Patches> {
    static constexpr const char* kName = "acc1";
    static constexpr const char* kTessControl = "acc1.tesc";
    static constexpr const char* kTessEvaluation = "acc1.tese";
    static std::span<const FeatureRule> rules() { return kRules; }
    static Result<Data> build(const Cage& cage) { return buildAcc1(cage, {}, kName); }
    static SurfacePoint evaluate(const Data& data, uint32_t subface, float u, float v) {
        return surfacePointOf(evaluateAcc1(data, subface, u, v));
    }
    static void addCullLeaves(const Data& data, uint32_t patch, const glm::vec3& origin, PatchCullLeaves& leaves) {
        // The geometry patch, b(i, j) at 4 j + i: BicubicPoints' order.
        const glm::vec3* geometry = &data.controlPoints[size_t(patch) * Acc1Patches::kControlPointsPerPatch];
        addBezierLeaf(leaves, pointsRelativeTo<Acc1Patches::kGeometryPoints>(geometry, origin), false);
    }
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("acc1",
                       "Loop-Schaefer 2008 bicubic patches with tangent patches (ACC-1): 40 control points per quad, "
                       "drawn through the tessellator",
                       qp::TessPatchScheme<qp::Acc1Traits>)
