#include "osd_fas_patches.h"

#include <algorithm>
#include <cassert>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include "plans/osd_refiner.h"
#include "plans/patch_basis.h"

namespace qp {

using namespace OpenSubdiv;

namespace {

// Basis of a single-crease patch: Far marks the crease edge with its PatchParam boundary bit
// (edge 0: v=0, 1: u=1, 2: v=1, 3: u=0) and gives the sharpness separately; EvaluateBasis would
// treat that edge as a boundary (an infinitely sharp crease). Along the crease the cubic
// B-spline, across it the semi-sharp crease basis of core/plans/patch_basis.h, which is exact for the
// uniform crease rule, fractional sharpness included.
void singleCreaseBasis(const Far::PatchParam& param, float sharpness, float u, float v, float w[16], float wu[16],
                       float wv[16]) {
    param.Normalize(u, v);
    assert(__builtin_popcount(param.GetBoundary()) == 1 && "a single-crease patch marks exactly its crease edge");
    const int edge = __builtin_ctz(param.GetBoundary());
    const Basis1D bu = edge == 3 ? creaseBasis1D(u, sharpness) : edge == 1 ? creaseBasis1DFar(u, sharpness) : bsplineBasis1D(u);
    const Basis1D bv = edge == 0 ? creaseBasis1D(v, sharpness) : edge == 2 ? creaseBasis1DFar(v, sharpness) : bsplineBasis1D(v);
    const float scale = float(1 << param.GetDepth());  // patch-local derivatives to the face's, as EvaluateBasis
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            w[4 * row + col] = bu.b[col] * bv.b[row];
            wu[4 * row + col] = scale * bu.d[col] * bv.b[row];
            wv[4 * row + col] = scale * bu.b[col] * bv.d[row];
        }
}

// Summed in double relative to the patch's first control point: deep patches' derivatives are
// differences of points 2^-depth of a face apart times 2^depth, which float in the model's
// absolute coordinates cannot hold (the plans keep their control points relative for the same
// reason, core/plans/planned_cage.h).
FasSample evaluatePatch(const FasPatches& patches, const Far::PatchTable::PatchHandle& handle, float u, float v) {
    double w[20], wu[20], wv[20];
    const Far::PatchParam param = patches.table->GetPatchParam(handle);
    const float sharpness = patches.table->GetSingleCreasePatchSharpnessValue(handle);
    if (sharpness > 0.0f && patches.table->GetPatchArrayDescriptor(handle.arrayIndex).GetType() == Far::PatchDescriptor::REGULAR) {
        float fw[16], fu[16], fv[16];
        singleCreaseBasis(param, sharpness, u, v, fw, fu, fv);
        std::copy(fw, fw + 16, w);
        std::copy(fu, fu + 16, wu);
        std::copy(fv, fv + 16, wv);
    } else {
        patches.table->EvaluateBasis(handle, double(u), double(v), w, wu, wv);
    }
    const Far::ConstIndexArray cvs = patches.table->GetPatchVertices(handle);
    const glm::dvec3 origin = patches.points[size_t(cvs[0])];
    glm::dvec3 position(0.0), du(0.0), dv(0.0);
    for (int k = 0; k < cvs.size(); ++k) {
        const glm::dvec3 c = patches.points[size_t(cvs[k])] - origin;
        position += w[k] * c;
        du += wu[k] * c;
        dv += wv[k] * c;
    }
    FasSample s{glm::vec3(origin + position), glm::vec3(du), glm::vec3(dv)};
    // EvaluateBasis differentiates an n-gon's sub-face in the parent's parameterisation, where
    // it spans 1/2 (core/plans/limit_reference.cpp): back to the sub-face's own frame.
    if (param.NonQuadRoot()) {
        s.du *= 0.5f;
        s.dv *= 0.5f;
    }
    return s;
}

// Domain points and triangles of one patch.
void layoutPatch(FasPatches& patches, const FasPatchLayout& p) {
    glm::vec2* domain = &patches.domain[p.firstVertex];
    uint32_t* index = &patches.indices[p.firstIndex];
    const uint32_t base = p.firstVertex;
    if (!p.transitions) {
        const uint32_t n = p.factor, side = n + 1;
        for (uint32_t y = 0; y <= n; ++y)
            for (uint32_t x = 0; x <= n; ++x) *domain++ = {float(x) / float(n), float(y) / float(n)};
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const uint32_t a = base + y * side + x, b = a + 1, c = a + side + 1, d = a + side;
                for (uint32_t i : {a, b, c, a, c, d}) *index++ = i;
            }
        return;
    }
    // One cell: a fan around the centre over the corners and the midpoints of transition edges,
    // counter-clockwise. Edge e runs from corner e to corner e + 1.
    static const glm::vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    domain[0] = {0.5f, 0.5f};
    uint32_t ring[8], count = 0, next = 1;
    for (uint32_t e = 0; e < 4; ++e) {
        domain[next] = corners[e];
        ring[count++] = base + next++;
        if (p.transitions & (1u << e)) {
            domain[next] = 0.5f * (corners[e] + corners[(e + 1) % 4]);
            ring[count++] = base + next++;
        }
    }
    for (uint32_t i = 0; i < count; ++i)
        for (uint32_t k : {base, ring[i], ring[(i + 1) % count]}) *index++ = k;
}

// Where a ptex face (a Far patch's face id) comes from: the base face and, for an n-gon, which
// of its corners' sub-faces (-1 for a quad).
struct PtexOrigin {
    Far::Index face;
    int corner;
};

std::vector<PtexOrigin> ptexOrigins(const Far::TopologyRefiner& r) {
    const Far::TopologyLevel& base = r.GetLevel(0);
    std::vector<PtexOrigin> origins;
    for (Far::Index f = 0; f < base.GetNumFaces(); ++f) {
        const int n = base.GetFaceVertices(f).size();
        if (n == 4) origins.push_back({f, -1});
        else
            for (int k = 0; k < n; ++k) origins.push_back({f, k});
    }
    return origins;
}

// A refined face with its corners in the patch frame's order: (0,0), (1,0), (1,1), (0,1).
struct FramedFace {
    int level;
    Far::Index face;
    Far::Index corners[4];
};

Far::Index edgeChild(const Far::TopologyLevel& level, Far::Index a, Far::Index b) {
    return level.GetEdgeChildVertex(level.FindEdge(a, b));
}

// The child of `f` in frame quadrant m (0: (0,0), 1: (1,0), 2: (1,1), 3: (0,1)), its corners
// framed the same way: the quadrant's corner vertex, the midpoints of its two edges, the centre.
FramedFace childInQuadrant(const Far::TopologyRefiner& r, const FramedFace& f, int m) {
    const Far::TopologyLevel& level = r.GetLevel(f.level);
    const Far::ConstIndexArray vertices = level.GetFaceVertices(f.face);
    int k = 0;
    while (vertices[k] != f.corners[m]) ++k;
    FramedFace child{f.level + 1, level.GetFaceChildFaces(f.face)[k], {}};
    const Far::Index prev = f.corners[(m + 3) % 4], corner = f.corners[m], next = f.corners[(m + 1) % 4];
    child.corners[m] = level.GetVertexChildVertex(corner);
    child.corners[(m + 1) % 4] = edgeChild(level, corner, next);
    child.corners[(m + 2) % 4] = level.GetFaceChildVertex(f.face);
    child.corners[(m + 3) % 4] = edgeChild(level, prev, corner);
    return child;
}

// The refined face a patch covers, found by walking down from its base face along the
// PatchParam's (u, v) bits.
FramedFace patchFace(const Far::TopologyRefiner& r, std::span<const PtexOrigin> origins, const Far::PatchParam& param) {
    const PtexOrigin origin = origins[size_t(param.GetFaceId())];
    const Far::TopologyLevel& base = r.GetLevel(0);
    const Far::ConstIndexArray vertices = base.GetFaceVertices(origin.face);
    FramedFace face{0, origin.face, {}};
    if (origin.corner < 0) {
        std::copy(vertices.begin(), vertices.end(), face.corners);
    } else {
        // An n-gon's sub-face k: from its corner k towards the midpoint of the edge after it.
        const int n = vertices.size(), k = origin.corner;
        face = {1, base.GetFaceChildFaces(origin.face)[k],
                {base.GetVertexChildVertex(vertices[k]), edgeChild(base, vertices[k], vertices[(k + 1) % n]),
                 base.GetFaceChildVertex(origin.face), edgeChild(base, vertices[(k + n - 1) % n], vertices[k])}};
    }
    const int steps = param.GetDepth() - (param.NonQuadRoot() ? 1 : 0);
    for (int bit = steps - 1; bit >= 0; --bit) {
        const bool highU = (param.GetU() >> bit) & 1, highV = (param.GetV() >> bit) & 1;
        face = childInQuadrant(r, face, highV ? (highU ? 2 : 3) : (highU ? 1 : 0));
    }
    return face;
}

// FasPatchLayout::edgePoints of one patch, as indices into the all-levels vertex numbering the
// stencil table and the patch table share.
void setEdgePoints(const Far::TopologyRefiner& r, std::span<const int> levelOffsets, const FramedFace& face,
                   uint32_t transitions, FasPatchLayout& p) {
    const Far::TopologyLevel& level = r.GetLevel(face.level);
    auto global = [&](int atLevel, Far::Index v) { return uint32_t(levelOffsets[size_t(atLevel)] + v); };
    for (int e = 0; e < 4; ++e) {
        const Far::Index a = face.corners[e], b = face.corners[(e + 1) % 4];
        if (transitions & (1u << e)) {
            p.edgePoints[e][0] = global(face.level + 1, level.GetVertexChildVertex(a));
            p.edgePoints[e][1] = global(face.level + 1, edgeChild(level, a, b));
            p.edgePoints[e][2] = global(face.level + 1, level.GetVertexChildVertex(b));
        } else {
            p.edgePoints[e][0] = global(face.level, a);
            p.edgePoints[e][1] = kNoEdgeMidpoint;
            p.edgePoints[e][2] = global(face.level, b);
        }
    }
}

}  // namespace

Result<FasPatches> buildFasPatches(const Cage& cage, uint32_t depth, uint32_t tessFactor) {
    FasPatches patches;
    while (patches.factor * 2 <= std::max(1u, tessFactor)) patches.factor *= 2;

    auto refiner = createRefiner(cage, "osd-fas");
    if (!refiner) return refiner.error();
    Far::TopologyRefiner& r = **refiner;
    Far::PatchTableFactory::Options options{depth};
    options.useInfSharpPatch = true;
    options.useSingleCreasePatch = true;
    options.generateLegacySharpCornerPatches = false;
    options.generateVaryingTables = false;
    options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    options.SetPatchPrecision<double>();  // the end caps' local points (FasPatches::stencils)
    r.RefineAdaptive(options.GetRefineAdaptiveOptions());
    patches.table.reset(Far::PatchTableFactory::Create(r, options));
    patches.map = std::make_unique<Far::PatchMap>(*patches.table);

    using StencilFactory = Far::StencilTableFactoryReal<double>;
    StencilFactory::Options stencilOptions;
    stencilOptions.generateIntermediateLevels = true;
    stencilOptions.generateControlVerts = true;
    stencilOptions.generateOffsets = true;
    patches.stencils.reset(StencilFactory::Create(r, stencilOptions));
    if (const auto* local = patches.table->GetLocalPointStencilTable<double>(); local && local->GetNumStencils() > 0)
        patches.stencils.reset(StencilFactory::AppendLocalPointStencilTable(r, patches.stencils.get(), local, true));

    const std::vector<PtexOrigin> origins = ptexOrigins(r);
    std::vector<int> levelOffsets(size_t(r.GetNumLevels()), 0);
    for (int level = 1; level < r.GetNumLevels(); ++level)
        levelOffsets[size_t(level)] = levelOffsets[size_t(level - 1)] + r.GetLevel(level - 1).GetNumVertices();

    uint32_t vertices = 0, indices = 0;
    int patchIndex = 0;
    for (int array = 0; array < patches.table->GetNumPatchArrays(); ++array) {
        const int cvsPerPatch = patches.table->GetPatchArrayDescriptor(array).GetNumControlVertices();
        for (int patch = 0; patch < patches.table->GetNumPatches(array); ++patch, ++patchIndex) {
            const Far::PatchParam param = patches.table->GetPatchParam(array, patch);
            FasPatchLayout p;
            p.handle.arrayIndex = array;
            p.handle.patchIndex = patchIndex;
            p.handle.vertIndex = patch * cvsPerPatch;  // relative to the array's first control vertex
            p.factor = std::max(1u, patches.factor >> param.GetDepth());
            patches.singleCreasePatches += patches.table->GetSingleCreasePatchSharpnessValue(array, patch) > 0.0f;
            p.transitions = p.factor == 1 ? param.GetTransition() : 0u;
            setEdgePoints(r, levelOffsets, patchFace(r, origins, param), param.GetTransition(), p);
            const uint32_t midpoints = uint32_t(__builtin_popcount(p.transitions));
            p.firstVertex = vertices;
            p.firstIndex = indices;
            p.vertexCount = p.transitions ? 5 + midpoints : (p.factor + 1) * (p.factor + 1);
            p.indexCount = p.transitions ? 3 * (4 + midpoints) : 6 * p.factor * p.factor;
            vertices += p.vertexCount;
            indices += p.indexCount;
            patches.layout.push_back(p);
        }
    }
    patches.indices.assign(indices, 0);
    patches.domain.resize(vertices);
    tbb::parallel_for(size_t(0), patches.layout.size(), [&](size_t i) { layoutPatch(patches, patches.layout[i]); });
    return patches;
}

void updateFasPoints(FasPatches& patches, std::span<const glm::vec3> cagePositions) {
    patches.points.resize(size_t(patches.stencils->GetNumStencils()));
    // In double, relative to the stencil's first cage vertex: weights sum to 1 only up to
    // round-off, which against absolute coordinates would move nearby points apart.
    tbb::parallel_for(size_t(0), patches.points.size(), [&](size_t i) {
        const Far::StencilReal<double> s = patches.stencils->GetStencil(Far::Index(i));
        if (s.GetSize() == 0) {
            patches.points[i] = glm::dvec3(0.0);
            return;
        }
        const glm::dvec3 first(cagePositions[size_t(s.GetVertexIndices()[0])]);
        glm::dvec3 p(0.0);
        for (int k = 0; k < s.GetSize(); ++k)
            p += s.GetWeights()[k] * (glm::dvec3(cagePositions[size_t(s.GetVertexIndices()[k])]) - first);
        patches.points[i] = first + p;
    });
}

FasSample evaluateFas(const FasPatches& patches, uint32_t subface, float u, float v) {
    const Far::PatchTable::PatchHandle* handle = patches.map->FindPatch(int(subface), u, v);
    return handle ? evaluatePatch(patches, *handle, u, v) : FasSample{};
}

FasSample evaluateFasPatch(const FasPatches& patches, uint32_t patch, float u, float v) {
    const Far::PatchTable::PatchHandle& handle = patches.layout[patch].handle;
    patches.table->GetPatchParam(handle).Unnormalize(u, v);
    return evaluatePatch(patches, handle, u, v);
}

void tessellateFas(const FasPatches& patches, std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals) {
    positions.resize(patches.domain.size());
    normals.resize(patches.domain.size());
    tbb::parallel_for(size_t(0), patches.layout.size(), [&](size_t i) {
        const FasPatchLayout& p = patches.layout[i];
        const Far::PatchParam param = patches.table->GetPatchParam(p.handle);
        for (uint32_t k = p.firstVertex; k < p.firstVertex + p.vertexCount; ++k) {
            float u = patches.domain[k].x, v = patches.domain[k].y;
            param.Unnormalize(u, v);  // patch-local -> the sub-face's frame
            const FasSample s = evaluatePatch(patches, p.handle, u, v);
            positions[k] = s.position;
            const glm::vec3 n = glm::cross(s.du, s.dv);
            normals[k] = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f);
        }
    });
}

}  // namespace qp
