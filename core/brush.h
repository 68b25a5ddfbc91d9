// Sculpting brushes on displacement samples.
//
// A dab at a world-space centre changes every sited sample whose LIMIT position (not the
// displaced one) lies within the radius, whatever sub-face, crease or extraordinary vertex it
// belongs to: there is no per-face step, so strokes have no seams. Its weight is
// w = strength * falloff(distance / radius):
//   - raise / lower: d += / -= w * radius          (strength: height per dab, in radii)
//   - smooth:        d += w (mean of graph neighbours - d)   (strength in [0, 1])
//   - flatten:       d moves by w towards the plane through the dab's weighted mean displaced
//                    point, normal to its weighted mean limit normal   (strength in [0, 1])
//   - erase:         d -= w d                        (strength 1 with the constant falloff
//                    returns every sample in the radius to exactly 0)
// With mirror symmetry a dab and its mirror image across the axis plane through the model
// centre act together on the values from before the dab (each sample reads old values only),
// so on a symmetric cage the result is symmetric whatever the brush.
// A stroke is a polyline sampled every `spacing` (dabs at the first point and then along the
// path); it returns a StrokeRecord (every changed sample once, sorted, with its value before
// and after the stroke) for the editor's undo/redo, and the sample ranges to upload.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "displacement.h"
#include "result.h"
#include "sculpt_samples.h"

namespace qp {

enum class BrushKind : uint8_t { Raise, Lower, Smooth, Flatten, Erase };
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
// Constant, which is 1 throughout).
float falloffWeight(Falloff falloff, float x);

// Checks radius > 0, finite values and the strength range of the brush kind.
Status validateBrush(const Brush& brush);

struct SampleChange {
    uint32_t sample;
    float before, after;
};

struct StrokeRecord {
    std::vector<SampleChange> changes;  // sorted by sample, each sample once
    uint32_t dabs = 0;
};

// Sets every changed sample back to `before` (undo) or to `after` (redo). The record must come
// from the same layout (resolution changes and topology edits make new layouts).
void undoStroke(Displacement& displacement, const StrokeRecord& record);
void redoStroke(Displacement& displacement, const StrokeRecord& record);

// The copy regions a GPU copy of the samples needs after these changes (in any order): the
// blocks of `block` samples that hold one, consecutive blocks merged, sorted.
struct SampleRange {
    uint32_t first, count;
};
std::vector<SampleRange> uploadRanges(const StrokeRecord& record, uint32_t block = 16);
std::vector<SampleRange> uploadRanges(std::span<const uint32_t> samples, uint32_t block = 16);

// Applies dabs and remembers, per sample, its value before the first one. One Sculptor serves
// one stroke at a time; the samples cache must be built for the displacement's layout.
class Sculptor {
public:
    Sculptor(Displacement& displacement, const SculptSamples& samples);

    // The mirror plane passes through `centre` (by default the samples' bounding-box centre).
    void setMirrorCentre(const glm::vec3& centre) { mirrorCentre_ = centre; }

    // One dab (and its mirror image). Returns the number of samples it changed.
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
    Displacement& displacement_;
    const SculptSamples& samples_;
    glm::vec3 mirrorCentre_;
    uint32_t dabs_ = 0;
    std::optional<glm::vec3> strokePoint_;  // dabTo's previous point in this stroke
    double untilNext_ = 0.0;                // and the distance from it to the next dab

    // Per sample: the stroke serial when first touched, and the value before it.
    std::vector<uint32_t> touchedInStroke_;
    std::vector<float> before_;
    std::vector<uint32_t> touched_;
    uint32_t stroke_ = 1;

    // Scratch reused between dabs; dabStamp_ tells the mirror image's samples from the dab's.
    std::vector<uint32_t> affected_, indexed_, dabStamp_;
    uint32_t dabSerial_ = 0;
    std::vector<float> weights_, newValues_;
    std::vector<uint32_t> firstTouches_, chunkCounts_;
};

// One whole stroke: begin, dabs along the path, end.
StrokeRecord applyStroke(Displacement& displacement, const SculptSamples& samples, const StrokeOptions& options,
                         std::span<const glm::vec3> path);

}  // namespace qp
