// How far a scheme's surface is from the exact limit surface, and the heat-map colours.
//
// Error at a sample = |scheme(sub-face, u, v) - exact(sub-face, u, v)| / bounding-box diagonal
// of the cage. `exact` is an ExactReference: by default OpenSubdiv's Far adaptive patches at
// depth 10 with double-precision points (LimitReference), whose own error is ~2e-8 of the
// diagonal next to extraordinary vertices (measured against Stam's exact evaluation) and
// round-off elsewhere; or the plans at their depth, which are exact except within 2^-depth of
// an extraordinary vertex (docs/plan-engine.md). It is a parametric distance: a scheme whose surface is right but
// parameterised differently (uniform refinement) is charged for that too. Normal deviation is
// the angle between the scheme's shading normal and du x dv of the exact surface, left out
// where the exact du and dv are within 0.06 degrees of parallel (folds of degenerate cages,
// where no normal is defined) and at the face corners where the limit surface has no tangent
// plane (core/plans/tangent_plane.h).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "plans/limit_reference.h"
#include "scheme_api.h"

namespace qp {

struct ErrorStats {
    double maxRelError = 0.0;
    double rmsRelError = 0.0;
    double maxNormalDegrees = 0.0;
    double p99NormalDegrees = 0.0;  // 99th percentile of the normal samples' deviation
    uint64_t samples = 0;
    uint64_t normalSamples = 0;  // samples where both normals are defined
    // Samples left out of the normal comparison, where the exact surface's derivatives define no
    // tangent plane: they are (nearly) parallel, |du x dv| <= kMinNormalSine |du| |dv|, or one
    // of them vanishes against the other, min(|du|, |dv|) <= kMinDerivativeRatio max(|du|, |dv|)
    // (its direction is then round-off: the folded edge of back-to-back faces, coincident
    // vertices); samples at a face corner where the limit surface has no tangent plane
    // (core/plans/tangent_plane.h: corners of sectors of two or more faces at a corner-rule vertex,
    // counted also in normalSamplesWithoutTangentPlane); and samples where the scheme gives no
    // normal.
    uint64_t normalSamplesExcluded = 0;
    uint64_t normalSamplesWithoutTangentPlane = 0;
};

// The bounds of ErrorStats::normalSamplesExcluded. The ratio is far above double round-off
// (1e-16, what a vanished derivative of the Far reference measures) and far below any face a
// cage would be modelled with.
inline constexpr double kMinNormalSine = 1e-3;
inline constexpr double kMinDerivativeRatio = 1e-8;

struct SurfaceError {
    std::vector<float> relError;  // per sample
    ErrorStats stats;
};

// The exact surface at a set of samples, and what it is.
enum class ReferenceKind { Far, Plans };
struct ExactReference {
    ReferenceKind kind = ReferenceKind::Far;
    uint32_t depth = 10;
    std::vector<ReferenceSample> samples;  // at the sample points, in order
    std::vector<uint8_t> withoutTangentPlane;  // per sample: 1 at a corner without a tangent plane
    std::string description() const;      // "OpenSubdiv Far adaptive patches, depth 10, double precision"
    // Its own distance from the limit surface over the diagonal, as measured (docs/schemes.md),
    // or a negative value where no bound was measured.
    double errorBound() const;
};
// Far: LimitReference::create(planned.cage(), depth) evaluated at the samples (in parallel);
// Plans: PlannedCage::evaluate, at the plans' own depth (`depth` is ignored). Either way the
// samples at corners without a tangent plane are marked (cornersWithoutTangentPlane).
Result<ExactReference> evaluateReference(ReferenceKind kind, uint32_t depth, const PlannedCage& planned,
                                         std::span<const SampleRequest> samples, const std::string& source);

// `points` are the scheme's values at the reference's samples; `diagonal` is the scale (> 0).
SurfaceError measureSurfaceError(const ExactReference& reference, std::span<const SurfacePoint> points, double diagonal);
// The same with a scale per sample: a scene's samples, each cage's relative to its own diagonal.
SurfaceError measureSurfaceError(const ExactReference& reference, std::span<const SurfacePoint> points,
                                 std::span<const double> diagonalOfSample);
// Against the plans (ReferenceKind::Plans).
SurfaceError measureSurfaceError(const PlannedCage& exact, std::span<const SampleRequest> samples,
                                 std::span<const SurfacePoint> points, double diagonal);

// The heat map's one fixed scale, logarithmic, so tiles and runs compare at a glance: one hue
// per decade from kHeatLow (dark blue) to kHeatHigh (red); below and above clamp.
inline constexpr double kHeatLow = 1e-7;
inline constexpr double kHeatHigh = 1e-1;
// Colour of a relative error, sRGB-encoded components in [0, 1] (for the legend on the image).
glm::vec3 heatColorSrgb(double relError);
// The same colour as linear components (what the shaders take).
glm::vec3 heatColorLinear(double relError);

}  // namespace qp
