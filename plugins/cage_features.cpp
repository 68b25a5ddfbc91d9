// analyzeCage and assessSupport (scheme_api.h).
#include <string>

#include "scheme_api.h"

namespace qp {

const char* cageFeatureName(CageFeature feature) {
    switch (feature) {
        case CageFeature::NonQuadFaces: return "non-quad faces";
        case CageFeature::Triangles: return "triangles";
        case CageFeature::Boundaries: return "boundary edges";
        case CageFeature::Holes: return "holes";
        case CageFeature::InfinitelySharpCreases: return "infinitely sharp creases";
        case CageFeature::SemiSharpCreases: return "semi-sharp creases";
        case CageFeature::InfinitelySharpCorners: return "infinitely sharp corners";
        case CageFeature::SemiSharpCorners: return "semi-sharp corners";
        case CageFeature::NonManifold: return "non-manifold edges or vertices";
        case CageFeature::ExtraordinaryVertices: return "extraordinary vertices";
        case CageFeature::AdjacentExtraordinary: return "faces with several extraordinary vertices";
        case CageFeature::ChaikinCreases: return "Chaikin semi-sharp creases";
        case CageFeature::SmoothTriangleRule: return "triangles under the smooth triangle rule";
        case CageFeature::NoBoundaryInterpolation: return "boundaries without interpolation";
        case CageFeature::EdgeOnlyBoundaries: return "edge-only boundaries";
    }
    return "unknown feature";
}

CageFeatures analyzeCage(const Cage& cage, const Topology& topology) {
    CageFeatures features;
    auto add = [&](CageFeature f, uint32_t n = 1) { features.count[uint32_t(f)] += n; };
    const CageStats stats = computeStats(cage, topology);

    for (const EdgeCrease& c : cage.creases)
        add(c.sharpness >= kInfiniteSharpness ? CageFeature::InfinitelySharpCreases : CageFeature::SemiSharpCreases);
    for (const VertexCorner& c : cage.corners)
        add(c.sharpness >= kInfiniteSharpness ? CageFeature::InfinitelySharpCorners : CageFeature::SemiSharpCorners);
    add(CageFeature::Holes, uint32_t(cage.holes.size()));
    add(CageFeature::NonManifold, stats.nonManifoldEdges + stats.nonManifoldVertices);
    add(CageFeature::Boundaries, stats.boundaryEdges);
    add(CageFeature::ExtraordinaryVertices, stats.extraordinaryVertices);
    if (cage.options.creaseMethod == CreaseMethod::Chaikin) add(CageFeature::ChaikinCreases, features[CageFeature::SemiSharpCreases]);
    if (stats.boundaryEdges > 0 && cage.options.boundary == BoundaryInterpolation::None)
        add(CageFeature::NoBoundaryInterpolation, stats.boundaryEdges);
    if (stats.boundaryEdges > 0 && cage.options.boundary == BoundaryInterpolation::EdgesOnly)
        add(CageFeature::EdgeOnlyBoundaries, stats.boundaryEdges);

    // Extraordinary vertices as computeStats counts them: interior valence != 4, boundary != 3.
    std::vector<bool> boundaryVertex(cage.vertexCount(), false), extraordinary(cage.vertexCount(), false);
    for (uint32_t e = 0; e < topology.edgeCount(); ++e)
        if (topology.edgeFaceCount(e) == 1)
            boundaryVertex[topology.edgeVertices[2 * e]] = boundaryVertex[topology.edgeVertices[2 * e + 1]] = true;
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        const uint32_t valence = topology.vertexEdgeCount(v);
        features.maxValence = std::max(features.maxValence, valence);
        extraordinary[v] = valence > 0 && valence != (boundaryVertex[v] ? 3u : 4u);
    }
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t n = cage.faceSize(f);
        if (n != 4) add(CageFeature::NonQuadFaces);
        if (n == 3) add(CageFeature::Triangles);
        if (n == 3 && cage.options.triangleSubdivision == TriangleSubdivision::Smooth) add(CageFeature::SmoothTriangleRule);
        uint32_t evs = 0;
        for (uint32_t i = 0; i < n; ++i) evs += extraordinary[cage.faceBegin(f)[i]];
        if (evs > 1) add(CageFeature::AdjacentExtraordinary);
    }
    return features;
}

SupportReport assessSupport(std::span<const FeatureRule> rules, const CageFeatures& features) {
    SupportReport report;
    for (const FeatureRule& rule : rules) {
        if (rule.handling == Handling::Exact || !features.has(rule.feature)) continue;
        std::string text = std::string(rule.text) + " (the cage has " + std::to_string(features[rule.feature]) + " " +
                           cageFeatureName(rule.feature) + ")";
        (rule.handling == Handling::Unsupported ? report.refusals : report.approximations).push_back(std::move(text));
    }
    return report;
}

}  // namespace qp
