// DisplacedPicker: ray picking on the DISPLACED limit surface f = s + D N (the surface a sculptor
// sees and brushes; docs/displacement.md), where LimitPicker (picking.h) picks s alone.
//
// Each sub-face with a surface is sampled on an (n + 1)^2 grid, n = its displacement tile's
// cells (at least `minResolution`, at most kMaxPickResolution), so that every knot of the tile
// is a grid point and the sampled triangles follow the detail the user painted; the BVH holds the sub-faces' boxes of the displaced grid points. A ray hit on the
// sampled triangles is refined by Newton's method on f(u, v) = origin + t direction with
// f_u ~ s_u + D_u N (Blinn's approximation, as the renderers' normals: the Jacobian errs by
// the factor 1 + D kappa, which slows the iteration where the surface is curved but does not
// move its root); only a hit that converges inside a sub-face is `refined` (the sub-face of the
// triangle hit, or one next to it when the crossing lies across their edge).
//
// The grid keeps each point's limit position and unit normal beside its displaced position, so
// a brush dab that changed samples in place costs no limit evaluation: updateSamples() maps
// the samples to the sub-faces reading them (displacement_users.h) and re-displaces those.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "displacement/displacement.h"
#include "displacement/displacement_users.h"
#include "edit/bvh.h"
#include "edit/picking.h"
#include "plans/planned_cage.h"

namespace qp {

// Grids finer than this would cost (n + 1)^2 x 36 bytes per sub-face (300 MB for 2,000 sub-faces
// at 64) for detail Newton's refinement reaches anyway from a coarser triangle hit.
inline constexpr uint32_t kMaxPickResolution = 32;

class DisplacedPicker {
public:
    DisplacedPicker() = default;
    // `displacement` may be empty (then f = s); its layout must belong to planned's cage.
    DisplacedPicker(const PlannedCage& planned, const Displacement& displacement, uint32_t minResolution = 8);
    // Only these sub-faces (any order, each once) are sampled and hit: a local picker for work
    // near an edit (displacement_transfer.h), which would not pay for sampling the whole cage.
    DisplacedPicker(const PlannedCage& planned, const Displacement& displacement, std::span<const uint32_t> subfaces,
                    uint32_t minResolution = 8);

    // The limit surface changed on these sub-faces (vertex moves, re-planned tags; same
    // numbering and layout): re-evaluates them whole.
    void updateSubfaces(const PlannedCage& planned, const Displacement& displacement, std::span<const uint32_t> subfaces);
    // Samples changed in place (a dab, a stroke undone; same layout): re-displaces the sub-faces
    // whose D reads one of them, from the limit points the grid holds.
    void updateSamples(const PlannedCage& planned, const Displacement& displacement, std::span<const uint32_t> samples);

    struct Hit {
        uint32_t subface = kNoHit;
        float u = 0.0f, v = 0.0f;      // in the sub-face's frame (PlannedCage::evaluate)
        glm::vec3 position{0.0f};      // on the displaced surface: s + D N
        glm::vec3 normal{0.0f, 0.0f, 1.0f};  // the displaced surface's unit normal, normalize(f_u x f_v)
        glm::vec3 limit{0.0f};         // s(u, v), the undisplaced limit point
        float distance = kNoDistance;
        bool refined = false;
    };
    // `planned` and `displacement` must be those the picker was built or last updated from.
    Hit intersect(const PlannedCage& planned, const Displacement& displacement, const Ray& ray,
                  float maxDistance = kNoDistance) const;

    uint32_t subfaceCount() const { return uint32_t(grids_.size()); }
    uint32_t gridResolution(uint32_t subface) const { return grids_[subface].n; }
    // The sub-faces the last update re-sampled (for measurements and tests).
    const std::vector<uint32_t>& lastUpdated() const { return lastUpdated_; }

private:
    struct Grid {
        uint32_t n = 0;                      // intervals per side; 0: no surface
        std::vector<glm::vec3> limit, normal, displaced;  // (n + 1)^2 each, row-major, u fastest
    };
    uint32_t wantedResolution(const Displacement& displacement, uint32_t subface) const;
    void sampleLimit(const PlannedCage& planned, const Displacement& displacement, uint32_t subface);
    void displace(const Displacement& displacement, uint32_t subface);
    void resample(const PlannedCage& planned, const Displacement& displacement, std::span<const uint32_t> subfaces,
                  bool limitToo);
    Hit triangleHit(const Ray& ray, float maxDistance) const;
    bool newton(const PlannedCage& planned, const Displacement& displacement, const Ray& ray, uint32_t subface,
                glm::vec2 uv, Hit& hit) const;
    void refine(const PlannedCage& planned, const Displacement& displacement, const Ray& ray, Hit& hit) const;

    uint32_t minResolution_ = 8;
    std::vector<Grid> grids_;  // per sub-face
    std::vector<Box> boxes_;
    BoxBvh bvh_;
    DisplacementUsers users_;  // of the layout the picker was built for (empty without one)
    std::vector<uint32_t> lastUpdated_;
};

// The displaced point f = s + D N of (sub-face, u, v) and its unit normal (Blinn), as the
// picker and the renderers compute them; D = 0 without a displacement.
DisplacedPoint displacedSurfacePoint(const PlannedCage& planned, const Displacement& displacement, uint32_t subface,
                                     float u, float v);

}  // namespace qp
