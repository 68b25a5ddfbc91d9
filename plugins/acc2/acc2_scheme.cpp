// `acc2`: Loop, Schaefer, Ni, Castano 2009 Gregory patches (acc2.h, README.md), one bicubic
// Gregory patch of 20 control points per quad of the (once refined, for non-quad cages) cage.
//
// Drawn through the tessellator (acc2.tesc, acc2.tese) or on the CPU grid: tess_patch_scheme.h.
// Culling bounds a patch as a Gregory leaf (patch_cull_set.h: the box of its 20 points and a
// cone bounding its true normals; its points are already in patch_basis.h's order).
#include "acc2.h"
#include "tess_patch_scheme.h"

namespace qp {
namespace {

constexpr FeatureRule kRules[] = {
    {CageFeature::ExtraordinaryVertices, Handling::Approximated,
     "acc2 approximates the surface next to extraordinary vertices (Gregory patches: limit position at "
     "patch corners, G1 across edges; exact on regular quads)"},
    {CageFeature::SemiSharpCreases, Handling::Approximated, "acc2 draws semi-sharp creases smooth"},
    {CageFeature::InfinitelySharpCreases, Handling::Approximated, "acc2 draws infinitely sharp creases smooth"},
    {CageFeature::SemiSharpCorners, Handling::Approximated, "acc2 draws sharp corners smooth"},
    {CageFeature::InfinitelySharpCorners, Handling::Approximated, "acc2 draws sharp corners smooth"},
    {CageFeature::NonQuadFaces, Handling::Approximated,
     "acc2 refines cages with non-quad faces once first (tags act in that step only; 4 patches per quad)"},
    {CageFeature::NonManifold, Handling::Unsupported, "acc2 needs a manifold cage (a fan of quads around every vertex)"},
};

struct Acc2Traits : QuadPatchTraits<Acc2Patches> {
    static constexpr const char* kName = "acc2";
    static constexpr const char* kTessControl = "acc2.tesc";
    static constexpr const char* kTessEvaluation = "acc2.tese";
    static std::span<const FeatureRule> rules() { return kRules; }
    static Result<Data> build(const Cage& cage) { return buildAcc2(cage, {}, kName); }
    static SurfacePoint evaluate(const Data& data, uint32_t subface, float u, float v) {
        return surfacePointOf(evaluateAcc2(data, subface, u, v));
    }
    static void addCullLeaves(const Data& data, uint32_t patch, const glm::vec3& origin, PatchCullLeaves& leaves) {
        const glm::vec3* gregory = &data.controlPoints[size_t(patch) * Acc2Patches::kControlPointsPerPatch];
        addGregoryLeaf(leaves, pointsRelativeTo<Acc2Patches::kControlPointsPerPatch>(gregory, origin), false);
    }
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("acc2",
                       "Loop et al. 2009 Gregory patches (ACC-2): 20 control points per quad, rational interior blend, "
                       "drawn through the tessellator",
                       qp::TessPatchScheme<qp::Acc2Traits>)
