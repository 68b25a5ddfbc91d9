// Shared by the tests of the approximate patching schemes (plugins/*/test_*.cpp) and of the
// core pieces they stand on: the exact limit surface of a cage (subdivision plans), and the
// error of a scheme against it at the same (sub-face, u, v).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "obj_io.h"
#include "planned_cage.h"
#include "test_support.h"

namespace qp::test {

// A cage with its exact limit surface. Heap-allocated so the plan database stays put.
struct ExactSurface {
    Cage cage;
    PlanDatabase database;
    std::unique_ptr<PlannedCage> planned;
    double diagonal = 1.0;
};

inline std::unique_ptr<ExactSurface> makeExactSurface(const Cage& cage, const std::string& name = "test cage") {
    auto surface = std::make_unique<ExactSurface>();
    surface->cage = cage;
    auto planned = PlannedCage::create(cage, surface->database, PlanOptions{}, name);
    EXPECT_TRUE(planned.ok()) << (planned.ok() ? "" : planned.error().message);
    if (!planned.ok()) return nullptr;
    surface->planned = std::make_unique<PlannedCage>(std::move(planned).value());
    surface->diagonal = std::max(double(computeBounds(cage).diagonal()), 1e-30);
    return surface;
}

// Loads ../shared/shapes/<name>.obj (callers skip when the shapes are missing).
inline Cage loadSharedShape(const std::string& name) {
    std::vector<std::string> warnings;
    auto cage = loadObj((sharedShapesDir() / (name + ".obj")).string(), &warnings);
    EXPECT_TRUE(cage.ok()) << name << ": " << (cage.ok() ? "" : cage.error().message);
    return cage.ok() ? std::move(cage).value() : Cage{};
}

// What a scheme returns at one (sub-face, u, v), in double.
struct SchemeSample {
    glm::dvec3 position{0.0}, normal{0.0};
};
using SchemeEvaluator = std::function<SchemeSample(uint32_t subface, double u, double v)>;
// Which sub-faces to measure (all with a surface when empty).
using SubfaceFilter = std::function<bool(uint32_t subface)>;

struct SchemeError {
    double maxRelative = 0.0, rmsRelative = 0.0;  // position distance / bounding-box diagonal
    double maxNormalDegrees = 0.0, rmsNormalDegrees = 0.0;
    uint64_t samples = 0;
    uint32_t worstSubface = 0, worstNormalSubface = 0;
};

inline double angleDegrees(glm::dvec3 a, glm::dvec3 b) {
    double la = glm::length(a), lb = glm::length(b);
    if (la == 0.0 || lb == 0.0) return 180.0;
    double c = std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0);
    // acos loses precision near 0; atan2 of |a x b| and a.b does not.
    return std::atan2(glm::length(glm::cross(a, b)) / (la * lb), c) * 180.0 / std::numbers::pi;
}

// Samples an n x n grid (u, v = i / (n-1)) on every measured sub-face. The exact normal is the
// normalised cross product of the plans' derivatives.
inline SchemeError measureScheme(const ExactSurface& exact, const SchemeEvaluator& scheme, uint32_t n = 9,
                                 const SubfaceFilter& filter = {}) {
    SchemeError error;
    double sumSquares = 0.0, sumNormalSquares = 0.0;
    uint64_t normalSamples = 0;
    for (uint32_t s = 0; s < exact.planned->subfaceCount(); ++s) {
        if (!exact.planned->hasSurface(s) || (filter && !filter(s))) continue;
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                double u = double(i) / double(n - 1), v = double(j) / double(n - 1);
                LimitSample ref = exact.planned->evaluate(s, float(u), float(v));
                SchemeSample ours = scheme(s, u, v);
                double d = glm::length(ours.position - glm::dvec3(ref.position)) / exact.diagonal;
                sumSquares += d * d;
                ++error.samples;
                if (d > error.maxRelative) {
                    error.maxRelative = d;
                    error.worstSubface = s;
                }
                glm::dvec3 refNormal = glm::cross(glm::dvec3(ref.du), glm::dvec3(ref.dv));
                if (glm::length(refNormal) == 0.0) continue;  // degenerate reference (collapsed corner)
                double a = angleDegrees(ours.normal, refNormal);
                sumNormalSquares += a * a;
                ++normalSamples;
                if (a > error.maxNormalDegrees) {
                    error.maxNormalDegrees = a;
                    error.worstNormalSubface = s;
                }
            }
    }
    if (error.samples) error.rmsRelative = std::sqrt(sumSquares / double(error.samples));
    if (normalSamples) error.rmsNormalDegrees = std::sqrt(sumNormalSquares / double(normalSamples));
    return error;
}

inline void printSchemeError(const std::string& scheme, const std::string& cage, const SchemeError& e) {
    std::printf("| %-8s | %-22s | %10.3e | %10.3e | %8.3f | %8.3f |\n", scheme.c_str(), cage.c_str(), e.maxRelative,
                e.rmsRelative, e.maxNormalDegrees, e.rmsNormalDegrees);
}

}  // namespace qp::test
