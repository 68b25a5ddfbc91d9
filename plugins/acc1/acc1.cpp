#include "acc1.h"

namespace qp {

namespace {

// Corner k of a patch face, with everything its edges need.
struct Corner {
    const QuadRing* ring = nullptr;
    const VertexLimit* limit = nullptr;
    uint32_t face = 0;  // index of the patch face in the ring
    glm::dvec3 P{0.0};
    glm::dvec3 tNext{0.0}, tPrev{0.0};  // limit tangents towards the next / previous corner
    glm::dvec3 interior{0.0};           // this face's interior point at the corner
    glm::dvec3 edgeNext{0.0}, edgePrev{0.0};  // geometry edge points
    glm::dvec3 interiorAcrossNext{0.0}, interiorAcrossPrev{0.0};  // neighbours' interior points
    bool nextOnBoundary = false, prevOnBoundary = false;
};

Corner makeCorner(const QuadPatchSource& src, uint32_t face, uint32_t k) {
    Corner c;
    const uint32_t v = src.quads.faceBegin(face)[k];
    c.ring = &src.rings[v];
    c.limit = &src.limits[v];
    c.face = src.ringFace(face, k);
    const uint32_t n = uint32_t(c.limit->tangents.size());
    c.P = c.limit->position;
    c.tNext = c.limit->tangents[c.face];
    c.tPrev = c.limit->tangents[(c.face + 1) % n];
    c.nextOnBoundary = c.ring->boundary && c.face == 0;
    c.prevOnBoundary = c.ring->boundary && c.face + 1 == c.ring->faceCount();
    const uint32_t faces = c.ring->faceCount();
    c.interior = interiorBezierPoint(src.quads, *c.ring, c.face);
    if (!c.nextOnBoundary) {
        c.interiorAcrossNext = interiorBezierPoint(src.quads, *c.ring, (c.face + faces - 1) % faces);
        c.edgeNext = 0.5 * (c.interior + c.interiorAcrossNext);
    } else {
        c.edgeNext = c.P + c.tNext;
    }
    if (!c.prevOnBoundary) {
        c.interiorAcrossPrev = interiorBezierPoint(src.quads, *c.ring, (c.face + 1) % faces);
        c.edgePrev = 0.5 * (c.interior + c.interiorAcrossPrev);
    } else {
        c.edgePrev = c.P + c.tPrev;
    }
    return c;
}

// Along-edge derivative T (3 Bernstein coefficients) and cross derivative into the patch L (4)
// of the edge from corner a to corner b (b = a's next corner).
struct EdgeDerivatives {
    glm::dvec3 T[3], L[4];
};

EdgeDerivatives edgeDerivatives(const Corner& a, const Corner& b) {
    EdgeDerivatives d;
    d.T[0] = 3.0 * a.tNext;
    d.T[1] = 3.0 * (b.edgePrev - a.edgeNext);
    d.T[2] = -3.0 * b.tPrev;
    d.L[0] = 3.0 * a.tPrev;
    d.L[3] = 3.0 * b.tNext;
    if (a.nextOnBoundary) {  // no neighbour: the geometry patch's own cross derivative
        d.L[1] = 3.0 * (a.interior - a.edgeNext);
        d.L[2] = 3.0 * (b.interior - b.edgePrev);
        return d;
    }
    const double l0 = 2.0 * a.limit->cosine, l1 = -2.0 * b.limit->cosine;
    const glm::dvec3 lambdaT1 = (2.0 * l0 * d.T[1] + l1 * d.T[0]) / 3.0;
    const glm::dvec3 lambdaT2 = (l0 * d.T[2] + 2.0 * l1 * d.T[1]) / 3.0;
    d.L[1] = 0.5 * lambdaT1 + 1.5 * (a.interior - a.interiorAcrossNext);
    d.L[2] = 0.5 * lambdaT2 + 1.5 * (b.interior - b.interiorAcrossPrev);
    return d;
}

void bernstein3(float x, float b[4], float d[4]) {
    float y = 1.0f - x;
    b[0] = y * y * y;
    b[1] = 3.0f * x * y * y;
    b[2] = 3.0f * x * x * y;
    b[3] = x * x * x;
    d[0] = -3.0f * y * y;
    d[1] = 3.0f * y * y - 6.0f * x * y;
    d[2] = 6.0f * x * y - 3.0f * x * x;
    d[3] = 3.0f * x * x;
}

void bernstein2(float x, float b[3]) {
    float y = 1.0f - x;
    b[0] = y * y;
    b[1] = 2.0f * x * y;
    b[2] = x * x;
}

// The 40 points of the patch of `face` (acc1.h's order).
void buildPatch(const QuadPatchSource& src, uint32_t face, glm::vec3* cp) {
    Corner c[4];
    for (uint32_t k = 0; k < 4; ++k) c[k] = makeCorner(src, face, k);

    glm::dvec3 b[4][4];  // b[i][j], i along u, j along v
    b[0][0] = c[0].P, b[3][0] = c[1].P, b[3][3] = c[2].P, b[0][3] = c[3].P;
    b[1][1] = c[0].interior, b[2][1] = c[1].interior, b[2][2] = c[2].interior, b[1][2] = c[3].interior;
    b[1][0] = c[0].edgeNext, b[0][1] = c[0].edgePrev;
    b[3][1] = c[1].edgeNext, b[2][0] = c[1].edgePrev;
    b[2][3] = c[2].edgeNext, b[3][2] = c[2].edgePrev;
    b[0][2] = c[3].edgeNext, b[1][3] = c[3].edgePrev;

    EdgeDerivatives e[4];
    for (uint32_t k = 0; k < 4; ++k) e[k] = edgeDerivatives(c[k], c[(k + 1) % 4]);
    glm::dvec3 U[3][4], V[4][3];  // U[i][j]: d/du, i along u (degree 2); V[i][j]: d/dv, j degree 2
    for (int i = 0; i < 3; ++i) {
        U[i][0] = e[0].T[i];           // edge 0 runs along +u at v = 0
        U[i][3] = -e[2].T[2 - i];      // edge 2 runs along -u at v = 1
    }
    for (int j = 1; j < 3; ++j) {
        U[0][j] = e[3].L[3 - j];       // edge 3 (u = 0, t = 1 - v): cross = +d/du
        U[2][j] = -e[1].L[j];          // edge 1 (u = 1, t = v): cross = -d/du
    }
    U[1][1] = 3.0 * (b[2][1] - b[1][1]);
    U[1][2] = 3.0 * (b[2][2] - b[1][2]);
    for (int j = 0; j < 3; ++j) {
        V[3][j] = e[1].T[j];           // edge 1 runs along +v at u = 1
        V[0][j] = -e[3].T[2 - j];      // edge 3 runs along -v at u = 0
    }
    for (int i = 1; i < 3; ++i) {
        V[i][0] = e[0].L[i];           // edge 0 (v = 0, t = u): cross = +d/dv
        V[i][2] = -e[2].L[3 - i];      // edge 2 (v = 1, t = 1 - u): cross = -d/dv
    }
    V[1][1] = 3.0 * (b[1][2] - b[1][1]);
    V[2][1] = 3.0 * (b[2][2] - b[2][1]);

    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) cp[4 * j + i] = glm::vec3(b[i][j]);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 3; ++i) cp[16 + 3 * j + i] = glm::vec3(U[i][j]);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) cp[28 + 4 * j + i] = glm::vec3(V[i][j]);
}

}  // namespace

Result<Acc1Patches> buildAcc1(const Cage& cage, const Acc1Settings& settings, const std::string& source) {
    return buildQuadPatches<Acc1Patches>(cage, settings.tangents, source, buildPatch);
}

Acc1Sample evaluateAcc1Patch(const Acc1Patches& patches, uint32_t patch, float s, float t) {
    Acc1Sample sample;
    const glm::vec3* cp = &patches.controlPoints[size_t(patch) * Acc1Patches::kControlPointsPerPatch];
    float bs[4], ds[4], bt[4], dt[4], qs[3], qt[3];
    bernstein3(s, bs, ds);
    bernstein3(t, bt, dt);
    bernstein2(s, qs);
    bernstein2(t, qt);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) sample.position += bs[i] * bt[j] * cp[4 * j + i];
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 3; ++i) sample.du += qs[i] * bt[j] * cp[16 + 3 * j + i];
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) sample.dv += bs[i] * qt[j] * cp[28 + 4 * j + i];
    sample.normal = patchNormal(sample.du, sample.dv);
    sample.valid = true;
    return sample;
}

Acc1Sample evaluateAcc1(const Acc1Patches& patches, uint32_t subface, float u, float v) {
    return evaluateOnQuads(patches.source, subface, u, v, [&](uint32_t patch, double s, double t) {
        return evaluateAcc1Patch(patches, patch, float(s), float(t));
    });
}

const char* acc1Restrictions() {
    return "ACC-1 (bicubic geometry + tangent patches) approximates the Catmull-Clark limit: exact on "
           "regular quads; at extraordinary vertices the geometry is only C0 across edges and shading "
           "uses the separate tangent patches (exact limit normal at patch corners, continuous "
           "normals). Cages with non-quad faces are refined once first (4x the patches of their "
           "quads). Semi-sharp and infinitely sharp creases and corner tags are ignored (smooth "
           "rules); boundaries follow Catmull-Clark boundary limits at the corners. Non-manifold "
           "cages are rejected.";
}

}  // namespace qp
