#include "plans/refine_once.h"

#include <algorithm>

#include <opensubdiv/far/primvarRefiner.h>

#include "plans/face_config.h"
#include "plans/osd_refiner.h"

namespace qp {

using namespace OpenSubdiv;

namespace {

struct Point3 {
    double x = 0, y = 0, z = 0;
    void Clear() { x = y = z = 0; }
    void AddWithWeight(const Point3& p, float w) {
        x += double(w) * p.x;
        y += double(w) * p.y;
        z += double(w) * p.z;
    }
};

}  // namespace

Result<RefinedCage> refineOnce(const Cage& cage, const std::string& source) {
    auto created = createRefiner(cage, source);
    if (!created) return created.error();
    Far::TopologyRefiner& refiner = **created;
    Far::TopologyRefiner::UniformOptions uniform(1);
    uniform.fullTopologyInLastLevel = true;  // level-1 edges carry the decayed sharpness
    refiner.RefineUniform(uniform);
    const Far::TopologyLevel& parent = refiner.GetLevel(0);
    const Far::TopologyLevel& child = refiner.GetLevel(1);

    RefinedCage out;
    out.cage.options = cage.options;

    std::vector<Point3> coarse(cage.vertexCount()), fine(size_t(child.GetNumVertices()));
    for (uint32_t v = 0; v < cage.vertexCount(); ++v)
        coarse[v] = {double(cage.positions[v].x), double(cage.positions[v].y), double(cage.positions[v].z)};
    Point3* src = coarse.data();
    Point3* dst = fine.data();
    Far::PrimvarRefiner(refiner).Interpolate(1, src, dst);
    out.cage.positions.resize(fine.size());
    for (size_t v = 0; v < fine.size(); ++v) out.cage.positions[v] = glm::vec3(float(fine[v].x), float(fine[v].y), float(fine[v].z));

    out.firstChild.assign(cage.faceCount() + 1, 0);
    out.parentFirstSubface.assign(cage.faceCount() + 1, 0);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t n = cage.faceSize(f);
        out.firstChild[f + 1] = out.firstChild[f] + n;
        out.parentFirstSubface[f + 1] = out.parentFirstSubface[f] + subfaceCount(n);
        Far::ConstIndexArray edges = parent.GetFaceEdges(Far::Index(f));
        const uint32_t* corners = cage.faceBegin(f);
        const uint32_t facePoint = uint32_t(parent.GetFaceChildVertex(Far::Index(f)));
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t quad[4] = {uint32_t(parent.GetVertexChildVertex(Far::Index(corners[k]))),
                                uint32_t(parent.GetEdgeChildVertex(edges[int(k)])), facePoint,
                                uint32_t(parent.GetEdgeChildVertex(edges[int((k + n - 1) % n)]))};
            out.cage.addFace(quad, 4);
        }
        if (cage.isHole(f))
            for (uint32_t k = 0; k < n; ++k) out.cage.holes.push_back(out.firstChild[f] + k);
    }

    for (int e = 0; e < child.GetNumEdges(); ++e) {
        float sharpness = child.GetEdgeSharpness(e);
        if (sharpness <= 0.0f) continue;
        Far::ConstIndexArray ends = child.GetEdgeVertices(e);
        uint32_t a = uint32_t(ends[0]), b = uint32_t(ends[1]);
        out.cage.creases.push_back({std::min(a, b), std::max(a, b), std::min(sharpness, kInfiniteSharpness)});
    }
    for (int v = 0; v < child.GetNumVertices(); ++v) {
        float sharpness = child.GetVertexSharpness(v);
        if (sharpness > 0.0f) out.cage.corners.push_back({uint32_t(v), std::min(sharpness, kInfiniteSharpness)});
    }
    normalizeTags(out.cage);
    if (Status valid = validateCage(out.cage, source + " (refined once)"); !valid) return valid.error();
    return out;
}

RefinedLocation locateInRefined(const RefinedCage& refined, uint32_t subface, double u, double v) {
    const auto& first = refined.parentFirstSubface;
    const uint32_t face = uint32_t(std::upper_bound(first.begin(), first.end(), subface) - first.begin()) - 1;
    const uint32_t children = refined.firstChild[face + 1] - refined.firstChild[face];
    RefinedLocation at;
    if (children != 4) {  // n-gon: sub-face k is child k, same frame
        at.face = refined.firstChild[face] + (subface - first[face]);
        at.s = u;
        at.t = v;
        return at;
    }
    const bool right = u > 0.5, top = v > 0.5;
    const uint32_t k = right ? (top ? 2 : 1) : (top ? 3 : 0);
    at.face = refined.firstChild[face] + k;
    switch (k) {
    case 0: at.s = 2 * u; at.t = 2 * v; at.dsdu = 2; at.dsdv = 0; at.dtdu = 0; at.dtdv = 2; break;
    case 1: at.s = 2 * v; at.t = 2 * (1 - u); at.dsdu = 0; at.dsdv = 2; at.dtdu = -2; at.dtdv = 0; break;
    case 2: at.s = 2 * (1 - u); at.t = 2 * (1 - v); at.dsdu = -2; at.dsdv = 0; at.dtdu = 0; at.dtdv = -2; break;
    default: at.s = 2 * (1 - v); at.t = 2 * u; at.dsdu = 0; at.dsdv = -2; at.dtdu = 2; at.dtdv = 0; break;
    }
    return at;
}

RefinedLocation locateInRefined(const RefinedCage& refined, const RefinedLocation& outer) {
    RefinedLocation inner = locateInRefined(refined, outer.face, outer.s, outer.t);
    RefinedLocation chained = inner;
    // d/du = dsdu_o d/ds_o + dtdu_o d/dt_o, and d/ds_o = dsds_i d/ds_i + dtds_i d/dt_i.
    chained.dsdu = inner.dsdu * outer.dsdu + inner.dsdv * outer.dtdu;
    chained.dsdv = inner.dsdu * outer.dsdv + inner.dsdv * outer.dtdv;
    chained.dtdu = inner.dtdu * outer.dsdu + inner.dtdv * outer.dtdu;
    chained.dtdv = inner.dtdu * outer.dsdv + inner.dtdv * outer.dtdv;
    return chained;
}

}  // namespace qp
