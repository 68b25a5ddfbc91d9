#include "plans/quad_patch_source.h"

#include <algorithm>

#include "plans/face_config.h"

namespace qp {

uint32_t QuadPatchSource::ringFace(uint32_t face, uint32_t corner) const {
    const QuadRing& ring = rings[quads.faceBegin(face)[corner]];
    for (uint32_t i = 0; i < ring.faceCount(); ++i)
        if (ring.faces[i] == face) return i;
    return UINT32_MAX;
}

bool regularQuad(const QuadPatchSource& source, uint32_t face) {
    for (uint32_t k = 0; k < 4; ++k) {
        const QuadRing& ring = source.rings[source.quads.faceBegin(face)[k]];
        if (ring.boundary || ring.faceCount() != 4) return false;
    }
    return true;
}

bool boundaryQuad(const QuadPatchSource& source, uint32_t face) {
    for (uint32_t k = 0; k < 4; ++k)
        if (source.rings[source.quads.faceBegin(face)[k]].boundary) return true;
    return false;
}

uint32_t stepsToAllQuads(const Cage& cage) {
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        if (cage.faceSize(f) != 4) return 1;
    return 0;
}

Result<QuadPatchSource> prepareQuadPatchSource(const Cage& cage, uint32_t steps, TangentRule rule,
                                               const std::string& source) {
    if (Status valid = validateCage(cage, source); !valid) return valid.error();
    QuadPatchSource out;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) out.originalSubfaces += subfaceCount(cage.faceSize(f));
    out.quads = cage;
    for (uint32_t step = 0; step < steps; ++step) {
        auto refined = refineOnce(out.quads, source);
        if (!refined) return refined.error();
        out.quads = std::move(refined->cage);
        refined->cage = Cage{};
        out.steps.push_back(std::move(refined).value());
    }
    out.topology = buildTopology(out.quads);
    if (Status manifold = checkQuadManifold(out.quads, out.topology, source); !manifold) return manifold.error();

    const Cage& quads = out.quads;
    out.rings.resize(quads.vertexCount());
    out.limits.resize(quads.vertexCount());
    for (uint32_t v = 0; v < quads.vertexCount(); ++v) {
        if (out.topology.vertexFaceCount(v) == 0) continue;
        uint32_t face = out.topology.vertexFaces[out.topology.vertexFaceOffsets[v]];
        const uint32_t* corners = quads.faceBegin(face);
        uint32_t corner = uint32_t(std::find(corners, corners + 4, v) - corners);
        out.rings[v] = gatherQuadRing(quads, out.topology, face, corner);
        out.limits[v] = computeVertexLimit(quads, out.rings[v], rule);
    }

    const bool noBoundarySurface = quads.options.boundary == BoundaryInterpolation::None;
    out.facePatch.assign(quads.faceCount(), kNoPatch);
    for (uint32_t f = 0; f < quads.faceCount(); ++f) {
        if (quads.isHole(f)) continue;
        if (noBoundarySurface) {
            bool touches = false;
            for (uint32_t k = 0; k < 4; ++k) touches |= out.rings[quads.faceBegin(f)[k]].boundary;
            if (touches) continue;
        }
        out.facePatch[f] = uint32_t(out.patchFace.size());
        out.patchFace.push_back(f);
    }

    for (const EdgeCrease& c : quads.creases) {
        uint32_t e = out.topology.findEdge(c.v0, c.v1);
        if (e != UINT32_MAX && out.topology.edgeFaceCount(e) > 1) ++out.ignoredCreases;
    }
    for (const VertexCorner& c : quads.corners)
        if (!(out.rings[c.vertex].boundary && out.rings[c.vertex].faceCount() == 1)) ++out.ignoredCorners;
    return out;
}

RefinedLocation locateOnQuads(const QuadPatchSource& source, uint32_t subface, double u, double v) {
    if (source.steps.empty()) {
        RefinedLocation at;
        at.face = subface;  // all quads: sub-face = face
        at.s = u;
        at.t = v;
        return at;
    }
    RefinedLocation at = locateInRefined(source.steps[0], subface, u, v);
    for (size_t i = 1; i < source.steps.size(); ++i) at = locateInRefined(source.steps[i], at);
    return at;
}

}  // namespace qp
