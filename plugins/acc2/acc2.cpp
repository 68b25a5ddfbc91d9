#include "acc2.h"

#include "plans/patch_basis.h"

namespace qp {

namespace {

glm::dvec3 at(const Cage& cage, uint32_t v) { return glm::dvec3(cage.positions[v]); }

// Corner k of a patch face: its limit frame and the two tangent-plane edge points.
struct Corner {
    const QuadRing* ring = nullptr;
    uint32_t face = 0;  // index of the patch face in the ring
    glm::dvec3 P{0.0}, Ep{0.0}, Em{0.0};
    double cosine = 0.0;
    bool nextEdgeOnBoundary = false, prevEdgeOnBoundary = false;
};

Corner makeCorner(const QuadPatchSource& src, uint32_t face, uint32_t k) {
    Corner c;
    const uint32_t v = src.quads.faceBegin(face)[k];
    c.ring = &src.rings[v];
    c.face = src.ringFace(face, k);
    const VertexLimit& limit = src.limits[v];
    const uint32_t n = uint32_t(limit.tangents.size());
    c.P = limit.position;
    c.Ep = c.P + limit.tangents[c.face];
    c.Em = c.P + limit.tangents[(c.face + 1) % n];
    c.cosine = limit.cosine;
    c.nextEdgeOnBoundary = c.ring->boundary && c.face == 0;
    c.prevEdgeOnBoundary = c.ring->boundary && c.face + 1 == c.ring->faceCount();
    return c;
}

// Half the difference of the regular interior points on either side of ring edge i, pointing
// into face i: (e_{i+1} - e_{i-1}) / 3 + (d_i - d_{i-1}) / 6.
glm::dvec3 crossDifference(const Cage& cage, const QuadRing& ring, int i) {
    return (at(cage, ring.edge(i + 1)) - at(cage, ring.edge(i - 1))) / 3.0 +
           (at(cage, ring.diagonal(i)) - at(cage, ring.diagonal(i - 1))) / 6.0;
}

// The 20 points of the patch of `face` (acc2.h's order).
void buildPatch(const QuadPatchSource& src, uint32_t face, glm::vec3* cp) {
    const Cage& quads = src.quads;
    Corner corners[4];
    for (uint32_t k = 0; k < 4; ++k) corners[k] = makeCorner(src, face, k);
    for (uint32_t k = 0; k < 4; ++k) {
        const Corner& c = corners[k];
        const Corner& next = corners[(k + 1) % 4];
        const Corner& prev = corners[(k + 3) % 4];
        const int i = int(c.face);
        glm::dvec3 Fp = c.nextEdgeOnBoundary
                            ? interiorBezierPoint(quads, *c.ring, c.face)
                            : c.Ep + (2.0 * c.cosine * (next.Em - c.Ep) - next.cosine * (c.Ep - c.P) +
                                      crossDifference(quads, *c.ring, i)) /
                                         3.0;
        glm::dvec3 Fm = c.prevEdgeOnBoundary
                            ? interiorBezierPoint(quads, *c.ring, c.face)
                            : c.Em + (2.0 * c.cosine * (prev.Ep - c.Em) - prev.cosine * (c.Em - c.P) -
                                      crossDifference(quads, *c.ring, i + 1)) /
                                         3.0;
        cp[5 * k + 0] = glm::vec3(c.P);
        cp[5 * k + 1] = glm::vec3(c.Ep);
        cp[5 * k + 2] = glm::vec3(c.Em);
        cp[5 * k + 3] = glm::vec3(Fp);
        cp[5 * k + 4] = glm::vec3(Fm);
    }
}

}  // namespace

Result<Acc2Patches> buildAcc2(const Cage& cage, const Acc2Settings& settings, const std::string& source) {
    Result<Acc2Patches> out = buildQuadPatches<Acc2Patches>(cage, settings.tangents, source, buildPatch);
    if (out) out->settings = settings;
    return out;
}

Acc2Sample evaluateAcc2Patch(const Acc2Patches& patches, uint32_t patch, float s, float t) {
    Acc2Sample sample;
    BasisWeights w;
    gregoryWeights(s, t, w, patches.settings.surfaceDerivatives);
    const glm::vec3* cp = &patches.controlPoints[size_t(patch) * Acc2Patches::kControlPointsPerPatch];
    for (uint32_t i = 0; i < Acc2Patches::kControlPointsPerPatch; ++i) {
        sample.position += w.w[i] * cp[i];
        sample.du += w.du[i] * cp[i];
        sample.dv += w.dv[i] * cp[i];
    }
    sample.normal = patchNormal(sample.du, sample.dv);
    sample.valid = true;
    return sample;
}

Acc2Sample evaluateAcc2(const Acc2Patches& patches, uint32_t subface, float u, float v) {
    return evaluateOnQuads(patches.source, subface, u, v, [&](uint32_t patch, double s, double t) {
        return evaluateAcc2Patch(patches, patch, float(s), float(t));
    });
}

const char* acc2Restrictions() {
    return "ACC-2 (Gregory patches) approximates the Catmull-Clark limit: exact on regular quads, "
           "limit position at every patch corner, G1 elsewhere. Cages with "
           "non-quad faces are refined once first (4x the patches of their quads). Semi-sharp and "
           "infinitely sharp creases and corner tags are ignored (smooth rules); boundaries follow "
           "Catmull-Clark boundary limits at the corners (edges-only valence-2 boundary vertices "
           "approximately). Non-manifold cages are rejected.";
}

}  // namespace qp
