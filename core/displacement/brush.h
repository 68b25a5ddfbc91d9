// Sculpting brushes on displacement samples.
//
// A dab's centre is a point on the DISPLACED surface (what the user sees and picks): it changes
// every sited sample whose displaced position (limit position + D N, from the values before
// the dab) lies within the radius, whatever sub-face, crease or extraordinary vertex it belongs
// to: there is no per-face step, so strokes have no seams. Distances for the falloff are
// measured between the centre and those displaced positions. Its weight is
// w = strength * falloff(distance / radius) * (1 - mask), the mask being the sample's
// (Displacement::mask; 0 where there is none):
//   - raise / lower: d += / -= w * radius          (strength: height per dab, in radii)
//   - smooth:        d += w (mean of graph neighbours - d)   (strength in [0, 1])
//   - flatten:       d moves by w towards the plane through the dab's weighted mean displaced
//                    point, normal to its weighted mean limit normal   (strength in [0, 1])
//   - erase:         d -= w d                        (strength 1 with the constant falloff
//                    returns every sample in the radius to exactly 0)
//   - inflate:       d += w * radius * min(4, sqrt(1 + |grad D|^2)): the displaced surface moves
//                    w * radius along its own normal n_d, which for a height along N takes
//                    dD = w r / (n_d . N), n_d . N = 1 / sqrt(1 + |grad D|^2); grad D is the
//                    least-squares tangent gradient of the old D over the sample's graph
//                    neighbours (limit positions projected on the tangent plane of N). On flat
//                    D it is raise; on a bump's slopes it raises more, so the bump swells; the
//                    factor is capped at 4 (grazing slopes).   (strength as raise)
//   - crease:        a V-shaped cut with pinch. First the pinch: the sample takes the OLD D
//                    interpolated at c + (x - c)(1 + p), x its displaced position, c the
//                    centre, p = min(0.5, 4 strength) * falloff * (1 - mask): what lay a bit
//                    farther out moves in, so the sides of the cut close up (interpolated by
//                    inverse squared distance over the samples whose displaced positions lie
//                    within one sample spacing of that point; the value stays if there are
//                    none). Then the cut: d -= w * radius * (1 - distance / radius)^2; the
//                    squared cusp profile, multiplied into the falloff, has a nonzero slope at
//                    the centre, so the bottom of the cut is sharp. (strength: depth per dab,
//                    in radii)
//   - mask / unmask: m += / -= w, clamped to [0, 1] (w without the (1 - mask) factor); D does
//                    not change. The first mask dab creates the mask (zeros) if there is none.
//                    (strength in [0, 1])
// A sample whose mask is 1 keeps exactly its bits under every brush that changes D.
// With mirror symmetry a dab and its mirror image across the axis plane through the model
// centre act together on the values from before the dab (each sample reads old values only),
// so on a symmetric cage the result is symmetric whatever the brush (up to the rounding of
// sums over neighbours taken in another order: inflate's gradient, crease's interpolation).
// A stroke is a polyline sampled every `spacing` (dabs at the first point and then along the
// path); it returns a StrokeRecord (every changed sample once, sorted, with its value before
// and after the stroke) for the editor's undo/redo, and the sample ranges to upload. A stroke
// changes D or the mask, never both: its first dab decides (see Sculptor::dab).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "displacement/displacement.h"
#include "displacement/displacement_users.h"
#include "displacement/sculpt_samples.h"
#include "mesh/result.h"

namespace qp {

enum class BrushKind : uint8_t { Raise, Lower, Smooth, Flatten, Erase, Inflate, Crease, Mask, Unmask };

// Mask and unmask paint the mask; every other kind changes D.
inline bool isMaskBrush(BrushKind kind) { return kind == BrushKind::Mask || kind == BrushKind::Unmask; }
enum class Falloff : uint8_t { Smooth, Linear, Constant, Sphere };
enum class MirrorAxis : uint8_t { None, X, Y, Z };

struct Brush {
    BrushKind kind = BrushKind::Raise;
    float radius = 0.1f;    // world units
    float strength = 0.1f;  // see the table above
    Falloff falloff = Falloff::Smooth;
};

struct StrokeOptions {
    Brush brush;
    MirrorAxis mirror = MirrorAxis::None;
    float spacing = 0.0f;  // between dabs along the path; 0: a quarter of the radius
};

// Names as the command line and the stroke files spell them ("raise", "smooth", "x", ...).
std::optional<BrushKind> brushKindFromName(std::string_view name);
std::optional<Falloff> falloffFromName(std::string_view name);
std::optional<MirrorAxis> mirrorAxisFromName(std::string_view name);  // "none", "x", "y", "z"
const char* brushKindName(BrushKind kind);
const char* falloffName(Falloff falloff);

// falloff(x) for x = distance / radius in [0, 1]: 1 at the centre, 0 at the rim (except
// Constant, which is 1 throughout). Inline: a big dab weighs a hundred thousand samples.
inline float falloffWeight(Falloff falloff, float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    switch (falloff) {
    case Falloff::Smooth: return 1.0f - x * x * (3.0f - 2.0f * x);
    case Falloff::Linear: return 1.0f - x;
    case Falloff::Constant: return 1.0f;
    case Falloff::Sphere: return std::sqrt(1.0f - x * x);
    }
    return 0.0f;
}

// Radii above this are refused whatever the model (callers that know the model's size check
// against it too: checkBrushRadiusForModel).
inline constexpr float kMaxBrushRadius = 1e30f;
// Height brushes (raise, lower, inflate, crease) move at most this many radii per dab.
inline constexpr float kMaxHeightStrength = 10.0f;

// Checks 0 < radius <= kMaxBrushRadius, finite values and the strength range of the brush kind:
// [0, 1] for smooth, flatten, erase, mask and unmask, [0, kMaxHeightStrength] for the others.
Status validateBrush(const Brush& brush);
// Refuses a radius over a million times the model's bounding-box diagonal (a typo, or a unit
// mix-up, that would reach every sample at every dab).
Status checkBrushRadiusForModel(float radius, float diagonal);
// validateBrush, a spacing that is finite and >= 0, and a path of finite points (the error
// names the first bad point, counting from 1, and its coordinates).
Status validateStroke(const StrokeOptions& options, std::span<const glm::vec3> path);

// What masking needs: a displacement to hold the mask. The error says what to do.
Status checkMaskable(const Displacement& displacement);

struct SampleChange {
    uint32_t sample;
    float before, after;
};

struct StrokeRecord {
    std::vector<SampleChange> changes;  // sorted by sample, each sample once
    uint32_t dabs = 0;
    bool mask = false;  // true: `changes` are mask values (a mask stroke, invert, clear), not D
};

// Sets every changed sample back to `before` (undo) or to `after` (redo), in D or (record.mask)
// in the mask, which is created (zeros) if it is empty. The record must come from the same
// layout (resolution changes and topology edits make new layouts).
void undoStroke(Displacement& displacement, const StrokeRecord& record);
void redoStroke(Displacement& displacement, const StrokeRecord& record);

// m -> 1 - m on every sample (with no mask yet: everything becomes masked), and every mask
// value to 0 (the mask vector stays, all zeros). The records undo exactly through
// DisplacementEdit(target, record, listener). Both fail, changing nothing, on an empty
// displacement (checkMaskable).
Result<StrokeRecord> invertMask(Displacement& displacement);
Result<StrokeRecord> clearMask(Displacement& displacement);

// The copy regions a GPU copy of the samples needs after these changes: the blocks of `block`
// samples (`block` divides 64) that hold one, consecutive blocks merged, sorted, the last one
// clipped after the last changed sample.
struct SampleRange {
    uint32_t first, count;
};
std::vector<SampleRange> uploadRanges(const SampleBits& samples, uint32_t block = 16);

// Applies dabs and remembers, per sample, its value before the first one. One Sculptor serves
// one stroke at a time; the samples cache must be built for the displacement's layout.
class Sculptor {
public:
    Sculptor(Displacement& displacement, const SculptSamples& samples);

    // The mirror plane passes through `centre` (by default the samples' bounding-box centre).
    void setMirrorCentre(const glm::vec3& centre) { mirrorCentre_ = centre; }

    // One dab (and its mirror image) at a point on the displaced surface. Returns the number of
    // samples it changed (D values, or mask values for mask brushes). A stroke changes one
    // array: its first dab decides, and a later dab of the other kind (a mask brush in a D
    // stroke or the reverse) changes nothing and returns 0; so does a dab with a brush that
    // fails validateBrush or a non-finite centre.
    uint32_t dab(const Brush& brush, MirrorAxis mirror, const glm::vec3& centre);

    // Continues the stroke to `point`: the stroke's first call dabs at the point; later calls
    // dab every `spacing` along the straight segment from the previous point, carrying the
    // distance left over to the next call, so a path given in pieces (an editor stroke: one
    // cursor position per frame) dabs exactly where the whole polyline would. `reached`, when
    // given, collects every dab's lastDabSamples() (what to upload).
    uint32_t dabTo(const StrokeOptions& options, const glm::vec3& point, std::vector<uint32_t>* reached = nullptr);
    // dabTo for each point of a polyline.
    uint32_t dabsAlong(const StrokeOptions& options, std::span<const glm::vec3> path);

    // Samples changed since the stroke began (sorted).
    std::vector<uint32_t> changedSamples() const;

    // Samples the last dab reached (unordered; a superset of those it changed): what to
    // upload after each dab (uploadRanges).
    std::span<const uint32_t> lastDabSamples() const { return affected_; }

    void beginStroke();
    StrokeRecord endStroke();
    uint32_t dabCount() const { return dabs_; }  // in the stroke so far

private:
    // The array this stroke changes: D, or the mask.
    std::vector<float>& strokeValues() { return strokeMask_ ? displacement_.mask : displacement_.samples; }
    const std::vector<float>& strokeValues() const { return strokeMask_ ? displacement_.mask : displacement_.samples; }
    // The dab's samples (and its mirror image's) into affected_, their places in the spatial
    // index (where their displaced positions are kept) into indexed_.
    void gatherDab(const glm::vec3* centres, uint32_t centreCount, float radius);
    // After a dab changed D: the displaced cells' boxes take in the new positions.
    void growDisplacedCells();
    // Crease's pinch: the old D interpolated at the point (on the displaced surface) near
    // sample k of the dab; `fallback` when no sample lies within `spacing` of it.
    float interpolateOldD(const glm::vec3& point, float spacing, float fallback) const;
    // Inflate's factor 1 / (n_d . N) at a sample, capped at 4.
    float inflateFactor(uint32_t sample) const;
    // Crease's sample spacing at a sample: the largest distance to its graph neighbours.
    float sampleSpacing(uint32_t sample) const;

    Displacement& displacement_;
    const SculptSamples& samples_;
    glm::vec3 mirrorCentre_;
    uint32_t dabs_ = 0;
    std::optional<glm::vec3> strokePoint_;  // dabTo's previous point in this stroke
    double untilNext_ = 0.0;                // and the distance from it to the next dab

    // Per sample: the stroke serial when first touched, and the value before it (side by side:
    // a dab's writes reach them in spatial order, one cache miss for both).
    struct FirstValue {
        uint32_t stroke = 0;
        float value = 0.0f;
    };
    std::vector<FirstValue> firstValues_;
    std::vector<uint32_t> touched_;
    uint32_t stroke_ = 1;

    // Scratch reused between dabs; dabStamp_ tells the mirror image's samples from the dab's.
    std::vector<uint32_t> affected_, indexed_, dabStamp_;
    uint32_t dabSerial_ = 0;
    std::vector<float> weights_, newValues_;
    DisplacedCells cells_;              // where displaced positions lie, for queries
    bool strokeMask_ = false;           // this stroke paints the mask
    bool cellsStale_ = true;            // D may have changed since cells_ was built
    std::vector<uint32_t> firstTouches_, chunkCounts_;
};

// One whole stroke: begin, dabs along the path, end. Call validateStroke first: a stroke that
// fails it changes nothing and returns an empty record.
StrokeRecord applyStroke(Displacement& displacement, const SculptSamples& samples, const StrokeOptions& options,
                         std::span<const glm::vec3> path);

}  // namespace qp
