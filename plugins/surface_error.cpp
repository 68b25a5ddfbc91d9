#include "surface_error.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include "plans/tangent_plane.h"
#include "scheme_support.h"

namespace qp {

std::string ExactReference::description() const {
    if (kind == ReferenceKind::Plans) return "subdivision plans, depth " + std::to_string(depth) + " (float)";
    return "OpenSubdiv Far adaptive patches, depth " + std::to_string(depth) + ", double precision";
}

double ExactReference::errorBound() const {
    // Far at depth 10 against Stam within 1/32 of every extraordinary vertex of four closed
    // cages (valence 3 to 20): 1.8e-8 of the diagonal (Stam.MatchesFarDepth10NearExtraordinaryVertices);
    // elsewhere B-spline, boundary and crease patches, exact up to round-off.
    if (kind == ReferenceKind::Far && depth >= 10) return 2e-8;
    return -1.0;
}

Result<ExactReference> evaluateReference(ReferenceKind kind, uint32_t depth, const PlannedCage& planned,
                                         std::span<const SampleRequest> samples, const std::string& source) {
    ExactReference reference;
    reference.kind = kind;
    reference.depth = depth;
    reference.samples.resize(samples.size());
    Result<std::vector<SubfaceCorner>> noPlane = cornersWithoutTangentPlane(planned.cage(), source);
    if (!noPlane) return noPlane.error();
    reference.withoutTangentPlane.assign(samples.size(), 0);
    for (size_t i = 0; i < samples.size(); ++i)
        if (const int corner = domainCorner(samples[i].u, samples[i].v); corner >= 0)
            reference.withoutTangentPlane[i] =
                std::binary_search(noPlane->begin(), noPlane->end(), SubfaceCorner{samples[i].subface, uint32_t(corner)});
    if (kind == ReferenceKind::Plans) {
        reference.depth = planned.options().maxDepth;
        std::vector<LimitSample> exact(samples.size());
        evaluateBatch(planned, samples, exact);
        for (size_t i = 0; i < samples.size(); ++i)
            reference.samples[i] = {glm::dvec3(exact[i].position), glm::dvec3(exact[i].du), glm::dvec3(exact[i].dv)};
        return reference;
    }
    Result<LimitReference> far = LimitReference::create(planned.cage(), depth, source);
    if (!far) return far.error();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, samples.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i < range.end(); ++i)
            reference.samples[i] = far->evaluate(samples[i].subface, samples[i].u, samples[i].v);
    });
    return reference;
}

SurfaceError measureSurfaceError(const ExactReference& reference, std::span<const SurfacePoint> points, double diagonal) {
    const std::vector<double> diagonals(points.size(), diagonal);
    return measureSurfaceError(reference, points, diagonals);
}

SurfaceError measureSurfaceError(const ExactReference& reference, std::span<const SurfacePoint> points,
                                 std::span<const double> diagonalOfSample) {
    assert(diagonalOfSample.size() == points.size());
    SurfaceError error;
    error.relError.resize(points.size());
    double sumSquares = 0.0;
    ErrorStats& s = error.stats;
    std::vector<double> angles;
    angles.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const ReferenceSample& exact = reference.samples[i];
        const double distance = glm::length(glm::dvec3(points[i].position) - exact.position);
        const double rel = distance / diagonalOfSample[i];
        error.relError[i] = float(rel);
        s.maxRelError = std::max(s.maxRelError, rel);
        sumSquares += rel * rel;
        // Where the exact surface's derivatives are (nearly) parallel, or one has vanished, its
        // normal is not defined by them (folds of degenerate cages): no normal comparison there.
        const glm::dvec3 cross = glm::cross(exact.du, exact.dv);
        const double lu = glm::length(exact.du), lv = glm::length(exact.dv);
        const double sine = glm::length(cross) / std::max(lu * lv, 1e-300);
        const bool vanishing = !(std::min(lu, lv) > kMinDerivativeRatio * std::max(lu, lv));
        const float schemeLength = glm::length(points[i].normal);
        if (i < reference.withoutTangentPlane.size() && reference.withoutTangentPlane[i]) {
            ++s.normalSamplesExcluded;
            ++s.normalSamplesWithoutTangentPlane;
            continue;
        }
        if (!(sine > kMinNormalSine) || vanishing || !(schemeLength > 0.0f)) {
            ++s.normalSamplesExcluded;
            continue;
        }
        // atan2 of sine and cosine: acos loses everything below ~0.03 degrees in float.
        const glm::dvec3 a = cross / glm::length(cross), b(glm::dvec3(points[i].normal) / double(schemeLength));
        const double angle = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
        s.maxNormalDegrees = std::max(s.maxNormalDegrees, angle * 180.0 / M_PI);
        angles.push_back(angle * 180.0 / M_PI);
        ++s.normalSamples;
    }
    if (!angles.empty()) {
        const size_t k = std::min(angles.size() - 1, size_t(std::ceil(0.99 * double(angles.size()))) - 1);
        std::nth_element(angles.begin(), angles.begin() + k, angles.end());
        s.p99NormalDegrees = angles[k];
    }
    s.samples = points.size();
    s.rmsRelError = points.empty() ? 0.0 : std::sqrt(sumSquares / double(points.size()));
    return error;
}

SurfaceError measureSurfaceError(const PlannedCage& exact, std::span<const SampleRequest> samples,
                                 std::span<const SurfacePoint> points, double diagonal) {
    Result<ExactReference> reference = evaluateReference(ReferenceKind::Plans, 0, exact, samples, "");
    return measureSurfaceError(*reference, points, diagonal);
}

namespace {

// One colour per decade, kHeatLow .. kHeatHigh (sRGB).
constexpr glm::vec3 kDecadeColors[] = {
    {0.10f, 0.10f, 0.45f},  // 1e-7 and below
    {0.15f, 0.35f, 0.95f},  // 1e-6
    {0.10f, 0.80f, 0.90f},  // 1e-5
    {0.20f, 0.80f, 0.25f},  // 1e-4
    {0.98f, 0.90f, 0.15f},  // 1e-3
    {0.98f, 0.50f, 0.05f},  // 1e-2
    {0.85f, 0.05f, 0.05f},  // 1e-1 and above
};

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

}  // namespace

glm::vec3 heatColorSrgb(double relError) {
    const double decades = std::log10(kHeatHigh / kHeatLow);
    double t = relError > 0.0 ? std::log10(relError / kHeatLow) : 0.0;
    t = std::clamp(t, 0.0, decades);
    const size_t i = std::min(size_t(t), std::size(kDecadeColors) - 2);
    const float f = float(t - double(i));
    return kDecadeColors[i] * (1.0f - f) + kDecadeColors[i + 1] * f;
}

glm::vec3 heatColorLinear(double relError) {
    const glm::vec3 c = heatColorSrgb(relError);
    return {srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b)};
}

}  // namespace qp
