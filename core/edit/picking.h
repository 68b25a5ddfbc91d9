// Picking: which cage vertex, edge or face, or which point of the limit surface, lies under a
// pixel; and box selection. Plain glm; no renderer needed.
//
// Conventions (those of render/camera.h and Vulkan): `viewProjection` maps world space to
// Vulkan clip space (depth 0..1, Y flipped by the projection); pixel coordinates have (0, 0) at
// the top-left corner of the viewport, x right, y down, and a point's pixel is
// (ndc.xy + 1) / 2 * viewport size. Distances along rays are in world units.
//
// Visibility ("select only what you can see"): an Occluder answers "does a surface cross this
// ray more than its tolerance before the given distance?"; a point is visible when none does.
// cageOccluder tests against the cage faces, limitOccluder against the limit surface.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "edit/bvh.h"
#include "edit/selection.h"
#include "mesh/cage.h"
#include "mesh/topology.h"
#include "plans/planned_cage.h"

namespace qp {

inline constexpr uint32_t kNoHit = UINT32_MAX;
inline constexpr float kNoDistance = std::numeric_limits<float>::infinity();

struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  // unit length
};

struct PickView {
    glm::mat4 viewProjection{1.0f};
    glm::vec2 size{1.0f};  // viewport width, height in pixels

    // The ray through a pixel, from the near plane (origin) away from the camera.
    Ray rayThrough(const glm::vec2& pixel) const;

    struct Projected {
        glm::vec2 pixel{0.0f};
        float depth = 0.0f;    // Vulkan depth, 0 at the near plane
        bool inFront = false;  // in front of the near plane (and the camera)
    };
    Projected project(const glm::vec3& point) const;
};

// Cage faces as a BVH of triangle fans around each face's centroid (holes included: they are
// cage faces a user may pick). Rebuild after any edit that moves or changes faces.
class CageRaycaster {
public:
    CageRaycaster() = default;
    explicit CageRaycaster(const Cage& cage);

    struct Hit {
        uint32_t face = kNoHit;
        float distance = kNoDistance;
        glm::vec3 position{0.0f};
    };
    Hit intersect(const Ray& ray, float maxDistance = kNoDistance) const;

private:
    BoxBvh bvh_;
    std::vector<uint32_t> fanOffsets_;     // per face, into fanPoints_: centroid, then corners
    std::vector<glm::vec3> fanPoints_;
};

// The limit surface sampled on a (resolution + 1)^2 grid per sub-face with a surface, in a BVH
// of sub-face boxes; a ray hit on the sampled triangles is refined by Newton's method on
// PlannedCage::evaluate to the exact limit surface (`refined` says whether it converged inside
// the sub-face; otherwise the triangle hit is returned).
class LimitPicker {
public:
    LimitPicker() = default;
    explicit LimitPicker(const PlannedCage& planned, uint32_t resolution = 8);

    // The resolution that keeps the samples of `subfaces` sub-faces near 16 M points (192 MiB):
    // 8 up to about 200k sub-faces, 3 at a million; Newton's refinement makes the
    // hits exact either way, the samples only find them.
    static uint32_t resolutionFor(uint32_t subfaces);

    // After an edit: re-samples the sub-faces the report lists; after a topology edit the kept
    // sub-faces (EditReport::previousSubfaceOf) keep their samples and only new ones are added.
    // A report without the maps (topology changed) re-samples everything. Re-sampling alone
    // (no sub-face gains or loses its surface) refits the BVH instead of building it again.
    void update(const PlannedCage& planned, const EditReport& report);

    struct Hit {
        uint32_t subface = kNoHit;
        float u = 0.0f, v = 0.0f;  // in the sub-face's frame (PlannedCage::evaluate)
        glm::vec3 position{0.0f};
        float distance = kNoDistance;
        bool refined = false;
    };
    // `planned` must be the PlannedCage the picker was built or last updated from.
    Hit intersect(const PlannedCage& planned, const Ray& ray, float maxDistance = kNoDistance) const;
    // Whether the limit surface crosses the ray before `distance`: what intersect would say
    // (its hit nearer than `distance`), without Newton's refinement where the sampled hit's
    // refinement window lies wholly before or after `distance`, and looking no farther.
    bool hides(const PlannedCage& planned, const Ray& ray, float distance) const;

private:
    void sample(const PlannedCage& planned, uint32_t subface);
    void rebuildBvh();
    Hit sampledHit(const Ray& ray, float maxDistance) const;  // the nearest sampled triangle's
    Hit refined(const PlannedCage& planned, const Ray& ray, Hit hit) const;
    uint32_t stride() const { return (resolution_ + 1) * (resolution_ + 1); }
    // Grids of 4 x 4 cells or more keep a box per quadrant: a ray through a sub-face's box
    // passes through one or two of them, and only their cells are tested.
    bool hasQuadrants() const { return resolution_ >= 4; }

    uint32_t resolution_ = 8;
    float largestSubface_ = 0.0f;    // at least the largest sub-face box's diagonal
    std::vector<glm::vec3> samples_;  // stride() per sub-face; unused where its box is empty
    std::vector<Box> boxes_;          // empty: the sub-face has no surface
    std::vector<std::array<Box, 4>> quadrantBoxes_;  // per sub-face where hasQuadrants()
    BoxBvh bvh_;
};

struct Occluder {
    // Whether a surface crosses the ray more than the tolerance before `distance` (world units).
    // Safe to call from several threads at once.
    std::function<bool(const Ray& ray, float distance)> hides;
};
// `tolerance` in world units (e.g. 1e-4 x the cage's diagonal). These keep references: the
// raycaster, picker and planned cage must outlive the occluder.
Occluder cageOccluder(const CageRaycaster& raycaster, float tolerance);
Occluder limitOccluder(const LimitPicker& picker, const PlannedCage& planned, float tolerance);

// Whether the point is in front of the camera and not hidden by the occluder.
bool isVisible(const PickView& view, const glm::vec3& point, const Occluder* occluder);

struct VertexPick {
    uint32_t vertex = kNoHit;
    float pixelDistance = kNoDistance;
    float depth = 0.0f;
};
// The vertex whose projection is nearest the pixel, within tolerancePixels; among equally near
// ones (within half a pixel) the one nearest the camera. Hidden vertices are skipped when an
// occluder is given.
VertexPick pickVertex(const Cage& cage, const PickView& view, const glm::vec2& pixel, float tolerancePixels,
                      const Occluder* occluder = nullptr);

struct EdgePick {
    EdgeKey edge;
    bool hit = false;
    float pixelDistance = kNoDistance;
    float t = 0.0f;  // where along edge v0 -> v1 the pick ray passes closest (for loop cuts)
};
// The edge whose projection passes nearest the pixel, within tolerancePixels (edges crossing
// the near plane are clipped to it); ties as for vertices. The visibility test uses the point
// of the edge nearest the pick ray.
EdgePick pickEdge(const Cage& cage, const Topology& topology, const PickView& view, const glm::vec2& pixel,
                  float tolerancePixels, const Occluder* occluder = nullptr);

// The face under the pixel (the nearest along the ray).
CageRaycaster::Hit pickFace(const CageRaycaster& raycaster, const PickView& view, const glm::vec2& pixel);

// Elements whose projections fall inside the rectangle between two pixel corners (any order):
// vertices by their position, edges when both ends are inside, faces by their centroid. With an
// occluder only visible ones (edges by their midpoint), tested on every core. Returns a
// selection of `mode`, in increasing element order.
Selection boxSelect(const Cage& cage, const Topology& topology, SelectionMode mode, const PickView& view,
                    const glm::vec2& cornerA, const glm::vec2& cornerB, const Occluder* occluder = nullptr);

}  // namespace qp
