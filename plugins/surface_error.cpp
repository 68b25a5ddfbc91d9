#include "surface_error.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "scheme_support.h"

namespace qp {

namespace {
constexpr double kMinNormalSine = 1e-3;
}  // namespace

SurfaceError measureSurfaceError(const PlannedCage& exact, std::span<const SampleRequest> samples,
                                 std::span<const SurfacePoint> points, double diagonal) {
    std::vector<LimitSample> reference(samples.size());
    evaluateBatch(exact, samples, reference);
    SurfaceError error;
    error.relError.resize(samples.size());
    double sumSquares = 0.0;
    ErrorStats& s = error.stats;
    for (size_t i = 0; i < samples.size(); ++i) {
        const double distance = glm::length(glm::dvec3(points[i].position) - glm::dvec3(reference[i].position));
        const double rel = distance / diagonal;
        error.relError[i] = float(rel);
        s.maxRelError = std::max(s.maxRelError, rel);
        sumSquares += rel * rel;
        // Where the exact surface's derivatives are (nearly) parallel its normal is not defined
        // by them (folds of degenerate cages): no normal comparison there.
        const glm::dvec3 du(reference[i].du), dv(reference[i].dv);
        const double sine = glm::length(glm::cross(du, dv)) / std::max(glm::length(du) * glm::length(dv), 1e-300);
        const glm::vec3 exactNormal = normalOf(reference[i].du, reference[i].dv);
        const float schemeLength = glm::length(points[i].normal);
        if (!(sine > kMinNormalSine) || !(schemeLength > 0.0f)) continue;
        // atan2 of sine and cosine: acos loses everything below ~0.03 degrees in float.
        const glm::dvec3 a(exactNormal), b(glm::dvec3(points[i].normal) / double(schemeLength));
        const double angle = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
        s.maxNormalDegrees = std::max(s.maxNormalDegrees, angle * 180.0 / M_PI);
        ++s.normalSamples;
    }
    s.samples = samples.size();
    s.rmsRelError = samples.empty() ? 0.0 : std::sqrt(sumSquares / double(samples.size()));
    return error;
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
