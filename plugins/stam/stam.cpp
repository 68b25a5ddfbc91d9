#include "stam.h"

#include <chrono>
#include <cmath>

#include "plans/corner_frame.h"
#include "stam_eigen.h"

namespace qp {

namespace {

// Uniform cubic B-spline basis and derivative, in double.
void bspline(double t, double b[4], double d[4]) {
    double s = 1.0 - t;
    b[0] = s * s * s / 6.0;
    b[1] = (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0;
    b[2] = (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0;
    b[3] = t * t * t / 6.0;
    d[0] = -s * s / 2.0;
    d[1] = (9.0 * t * t - 12.0 * t) / 6.0;
    d[2] = (-9.0 * t * t + 6.0 * t + 3.0) / 6.0;
    d[3] = t * t / 2.0;
}

uint32_t countBoundaryEdges(const Cage& cage) {
    Topology topology = buildTopology(cage);
    uint32_t boundary = 0;
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) boundary += topology.edgeFaceCount(e) == 1;
    return boundary;
}

// Steps until every face is a quad with at most one extraordinary corner.
uint32_t stepsToIsolate(const Cage& cage) {
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        if (cage.faceSize(f) != 4) return 2;
    Topology topology = buildTopology(cage);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        uint32_t extraordinary = 0;
        for (uint32_t k = 0; k < 4; ++k) extraordinary += topology.vertexFaceCount(cage.faceBegin(f)[k]) != 4;
        if (extraordinary > 1) return 1;
    }
    return 0;
}

}  // namespace

Result<StamPatches> buildStam(const Cage& cage, const std::string& source) {
    const auto start = std::chrono::steady_clock::now();
    if (Status valid = validateCage(cage, source); !valid) return valid.error();
    if (uint32_t boundary = countBoundaryEdges(cage))
        return Error{source + ": Stam's exact evaluation is defined for closed (interior-only) surfaces; this cage has " +
                     std::to_string(boundary) + " boundary edges"};
    auto prepared = prepareQuadPatchSource(cage, stepsToIsolate(cage), TangentRule::Exact, source);
    if (!prepared) return prepared.error();

    StamPatches out;
    out.source = std::move(prepared).value();
    const QuadPatchSource& src = out.source;
    const Cage& quads = src.quads;
    auto at = [&](uint32_t v) { return quads.positions[v]; };

    for (uint32_t patch = 0; patch < src.patchFace.size(); ++patch) {
        const uint32_t face = src.patchFace[patch];
        const uint32_t* corners = quads.faceBegin(face);
        uint32_t extraordinary = 0, rotation = 0;
        for (uint32_t k = 0; k < 4; ++k)
            if (src.rings[corners[k]].faceCount() != 4) {
                ++extraordinary;
                rotation = k;
            }
        if (extraordinary > 1)
            return Error{source + ": face " + std::to_string(face) + " of the refined cage has " +
                         std::to_string(extraordinary) + " extraordinary corners (not isolated)"};
        // Rings of the four corners, each starting at this face (corner `rotation` first).
        QuadRing ring[4];
        for (uint32_t k = 0; k < 4; ++k) ring[k] = gatherQuadRing(quads, src.topology, face, (rotation + k) % 4);
        out.pointOffset.push_back(uint32_t(out.controlPoints.size()));
        out.rotation.push_back(rotation);
        if (extraordinary == 0) {
            // The 4 x 4 grid, (col, row) with corner 0 at (1,1); see stam_eigen.h for the picture.
            uint32_t grid[4][4];
            const QuadRing& r0 = ring[0];
            grid[2][1] = r0.edges[0], grid[2][2] = r0.diagonals[0], grid[1][2] = r0.edges[1], grid[0][2] = r0.diagonals[1];
            grid[0][1] = r0.edges[2], grid[0][0] = r0.diagonals[2], grid[1][0] = r0.edges[3], grid[2][0] = r0.diagonals[3];
            grid[1][1] = r0.center;
            grid[3][0] = ring[1].diagonals[2], grid[3][1] = ring[1].edges[3], grid[3][2] = ring[1].diagonals[3];
            grid[3][3] = ring[2].diagonals[2], grid[2][3] = ring[2].edges[3], grid[1][3] = ring[2].diagonals[3];
            grid[0][3] = ring[3].diagonals[2];
            for (int row = 0; row < 4; ++row)
                for (int col = 0; col < 4; ++col) out.controlPoints.push_back(at(grid[col][row]));
            out.valence.push_back(4);
            ++out.stats.regularPatches;
        } else {
            const QuadRing& r0 = ring[0];
            const uint32_t n = r0.faceCount();
            out.controlPoints.push_back(at(r0.center));
            for (uint32_t i = 0; i < n; ++i) {
                out.controlPoints.push_back(at(r0.edges[i]));
                out.controlPoints.push_back(at(r0.diagonals[i]));
            }
            for (uint32_t v : {ring[1].diagonals[2], ring[1].edges[3], ring[1].diagonals[3], ring[2].diagonals[2],
                               ring[2].edges[3], ring[3].edges[2], ring[3].diagonals[2]})
                out.controlPoints.push_back(at(v));
            out.valence.push_back(n);
            ++out.stats.extraordinaryPatches;
            out.stats.maxValence = std::max(out.stats.maxValence, n);
        }
    }

    // Eigenspace projection of every extraordinary patch (parallel arrays to controlPoints).
    out.eigenCoefficients.assign(out.controlPoints.size(), glm::dvec3(0.0));
    for (uint32_t patch = 0; patch < out.valence.size(); ++patch) {
        if (out.valence[patch] == 4) continue;
        const StamEigenStructure& eigen = stamEigenStructure(out.valence[patch]);
        const uint32_t size = eigen.size, offset = out.pointOffset[patch];
        for (uint32_t r = 0; r < size; ++r) {
            glm::dvec3 sum(0.0);
            for (uint32_t c = 0; c < size; ++c)
                sum += eigen.inverseEigenvectors[size_t(r) * size + c] * glm::dvec3(out.controlPoints[offset + c]);
            out.eigenCoefficients[offset + r] = sum;
        }
    }

    countQuadPatches(out.stats, src, out.controlPoints.size(), start);
    return out;
}

StamSample evaluateStamPatch(const StamPatches& patches, uint32_t patch, double s, double t) {
    StamSample sample;
    const uint32_t offset = patches.pointOffset[patch], n = patches.valence[patch], rotation = patches.rotation[patch];
    double x, y;
    toCornerFrame(rotation, s, t, x, y);
    glm::dvec3 dx(0.0), dy(0.0);
    double bu[4], du[4], bv[4], dv[4];
    if (n == 4) {
        bspline(x, bu, du);
        bspline(y, bv, dv);
        for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col) {
                glm::dvec3 p(patches.controlPoints[offset + 4 * row + col]);
                sample.position += bu[col] * bv[row] * p;
                dx += du[col] * bv[row] * p;
                dy += bu[col] * dv[row] * p;
            }
    } else {
        // The limit point itself has no level: evaluate 2^-40 away (the error is ~2^-40 times
        // the patch size; the normal converges to the limit normal).
        const double tiny = std::ldexp(1.0, -40);
        if (std::max(x, y) < tiny) x = y = tiny;
        int m = int(std::floor(-std::log2(std::max(x, y)))) + 1;
        double scale = std::ldexp(1.0, m - 1);
        while (std::max(x, y) * scale > 1.0) scale = std::ldexp(1.0, --m - 1);
        while (std::max(x, y) * scale < 0.5) scale = std::ldexp(1.0, ++m - 1);
        double a = x * scale, b = y * scale;
        int k;
        if (a >= 0.5 && b < 0.5) k = 0, a = 2 * a - 1, b = 2 * b;
        else if (a >= 0.5) k = 1, a = 2 * a - 1, b = 2 * b - 1;
        else k = 2, a = 2 * a, b = 2 * b - 1;
        bspline(a, bu, du);
        bspline(b, bv, dv);
        const StamEigenStructure& eigen = stamEigenStructure(n);
        const uint32_t size = eigen.size;
        const double* phi = eigen.basis[k].data();
        const double chain = std::ldexp(1.0, m);  // d(a)/dx = 2^m
        for (uint32_t j = 0; j < size; ++j) {
            double c = 0.0, cu = 0.0, cv = 0.0;
            for (int row = 0; row < 4; ++row)
                for (int col = 0; col < 4; ++col) {
                    double w = phi[size_t(4 * row + col) * size + j];
                    c += bu[col] * bv[row] * w;
                    cu += du[col] * bv[row] * w;
                    cv += bu[col] * dv[row] * w;
                }
            double power = std::pow(eigen.eigenvalues[j], double(m - 1));
            const glm::dvec3& coefficient = patches.eigenCoefficients[offset + j];
            sample.position += power * c * coefficient;
            // Eigenvalue 1 belongs to the constant vector, whose derivatives vanish; its basis
            // derivatives are rounding noise that 2^m would amplify past the true ones.
            if (j == 0) continue;
            dx += power * cu * chain * coefficient;
            dy += power * cv * chain * coefficient;
        }

    }
    derivativesToFaceFrame(rotation, dx, dy);
    sample.du = dx;
    sample.dv = dy;
    sample.normal = patchNormal(dx, dy);
    sample.valid = true;
    return sample;
}

StamSample evaluateStam(const StamPatches& patches, uint32_t subface, double u, double v) {
    return evaluateOnQuads(patches.source, subface, u, v,
                           [&](uint32_t patch, double s, double t) { return evaluateStamPatch(patches, patch, s, t); });
}

const char* stamRestrictions() {
    return "Stam's direct evaluation is exact for the smooth Catmull-Clark rules, after one or two "
           "refinement steps that isolate extraordinary vertices (4x or 16x the patches). Not "
           "supported: boundaries (the cage must be closed) and non-manifold cages. Creases and "
           "corner tags act only within the refinement steps; beyond them the smooth rules are used, "
           "so tagged cages are not exact.";
}

}  // namespace qp
