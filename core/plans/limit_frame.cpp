#include "plans/limit_frame.h"

#include <cmath>
#include <map>
#include <mutex>
#include <numbers>

namespace qp {

namespace {

glm::dvec3 at(const Cage& cage, uint32_t v) { return glm::dvec3(cage.positions[v]); }

bool isCorner(const Cage& cage, const QuadRing& ring) {
    return ring.boundary && ring.faceCount() == 1 && cage.options.boundary == BoundaryInterpolation::EdgesAndCorners;
}

// Cross-boundary limit tangent mask of a boundary vertex with k >= 2 faces, over the points
// (v, e_0 .. e_k, d_0 .. d_{k-1}): the left eigenvector of the local subdivision matrix for
// its largest eigenvalue among masks symmetric under e_x <-> e_{k-x} with weights summing to 0
// (the symmetric masks are the cross tangent's; the antisymmetric one is the boundary's).
// Power iteration started from the Biermann et al. / Loop-Schaefer mask, scaled so its vertex
// weight equals that mask's. Computed once per k.
std::vector<double> boundaryCrossMask(uint32_t k) {
    static std::mutex mutex;
    static std::map<uint32_t, std::vector<double>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(k); it != cache.end()) return it->second;

    const uint32_t size = 2 * k + 2, e0 = 1, d0 = k + 2;
    const double kk = double(k), c = std::cos(std::numbers::pi / kk), s = std::sin(std::numbers::pi / kk);
    const double denom = 3.0 * kk + c;
    std::vector<double> guess(size, 0.0);
    guess[0] = -4.0 * s / denom;
    guess[e0] = guess[e0 + k] = -(1.0 + 2.0 * c) * std::sqrt(1.0 + c) / (denom * std::sqrt(1.0 - c));
    for (uint32_t x = 1; x < k; ++x) guess[e0 + x] = 4.0 * std::sin(std::numbers::pi * x / kk) / denom;
    for (uint32_t x = 0; x < k; ++x)
        guess[d0 + x] = (std::sin(std::numbers::pi * x / kk) + std::sin(std::numbers::pi * (x + 1) / kk)) / denom;

    // Rows of the one-step matrix S (new point = row . old points), Catmull-Clark with boundary rules.
    std::vector<std::vector<double>> rows(size, std::vector<double>(size, 0.0));
    rows[0][0] = 6.0 / 8.0;
    rows[0][e0] = rows[0][e0 + k] = 1.0 / 8.0;
    auto facePoint = [&](uint32_t x) {  // face x = (v, e_x, d_x, e_{x+1})
        std::vector<double> r(size, 0.0);
        r[0] = r[e0 + x] = r[d0 + x] = r[e0 + x + 1] = 0.25;
        return r;
    };
    for (uint32_t x = 0; x < k; ++x) rows[d0 + x] = facePoint(x);
    rows[e0][0] = rows[e0][e0] = 0.5;
    rows[e0 + k][0] = rows[e0 + k][e0 + k] = 0.5;
    for (uint32_t x = 1; x < k; ++x) {
        std::vector<double> before = facePoint(x - 1), after = facePoint(x);
        for (uint32_t i = 0; i < size; ++i) rows[e0 + x][i] = 0.25 * (before[i] + after[i]);
        rows[e0 + x][0] += 0.25;
        rows[e0 + x][e0 + x] += 0.25;
    }

    std::vector<double> w = guess, next(size);
    for (int iteration = 0; iteration < 200000; ++iteration) {
        std::fill(next.begin(), next.end(), 0.0);
        for (uint32_t r = 0; r < size; ++r)
            for (uint32_t i = 0; i < size; ++i) next[i] += w[r] * rows[r][i];
        double scale = guess[0] / next[0], change = 0.0;
        for (uint32_t i = 0; i < size; ++i) {
            next[i] *= scale;
            change = std::max(change, std::abs(next[i] - w[i]));
        }
        w.swap(next);
        // Keep the mask in its subspace against round-off: symmetric, and free of the limit
        // position's component (whose eigenvalue 1 would otherwise take over).
        for (uint32_t x = 0; x <= k; ++x) w[e0 + x] = w[e0 + k - x] = 0.5 * (w[e0 + x] + w[e0 + k - x]);
        for (uint32_t x = 0; x < k; ++x) w[d0 + x] = w[d0 + k - 1 - x] = 0.5 * (w[d0 + x] + w[d0 + k - 1 - x]);
        double sum = 0.0;
        for (double x : w) sum += x;
        w[0] -= sum * 4.0 / 6.0;
        w[e0] -= sum / 6.0;
        w[e0 + k] -= sum / 6.0;
        if (change < 1e-15) break;
    }
    cache[k] = w;
    return w;
}

}  // namespace

double subdominantEigenvalue(uint32_t valence) {
    const double n = double(valence), c = std::cos(2.0 * std::numbers::pi / n);
    return (5.0 + c + std::cos(std::numbers::pi / n) * std::sqrt(18.0 + 2.0 * c)) / 16.0;
}

VertexLimit computeVertexLimit(const Cage& cage, const QuadRing& ring, TangentRule rule) {
    VertexLimit limit;
    const glm::dvec3 v = at(cage, ring.center);
    const uint32_t faces = ring.faceCount();
    limit.tangents.resize(ring.edges.size());

    if (!ring.boundary) {
        const double n = double(faces), theta = 2.0 * std::numbers::pi / n, c = std::cos(theta);
        const double lambda = subdominantEigenvalue(faces);
        glm::dvec3 sum = n * n * v;
        for (uint32_t i = 0; i < faces; ++i) sum += 4.0 * at(cage, ring.edges[i]) + at(cage, ring.diagonals[i]);
        limit.position = sum / (n * (n + 5.0));
        const double modeWeight = 2.0 + 2.0 * c, exactWeight = 8.0 * lambda - 2.0;
        const double a = rule == TangentRule::AccEdgeMode ? modeWeight : exactWeight;
        // On the characteristic configuration (the ring an eigenvector for lambda: d-ring =
        // (1 + w) / (4 lambda - 1) times the e-ring in Fourier terms) both rules give the same
        // vector when the exact one is divided by this ratio.
        // (Valence 2 has no tangent plane -- every weight is 0 -- and no ratio.)
        const double dTerm = faces > 2 ? (1.0 + c) / (4.0 * lambda - 1.0) : 0.0;
        const double ratio = rule == TangentRule::Exact && faces > 2 ? (exactWeight + dTerm) / (modeWeight + dTerm) : 1.0;
        double scale = 1.0 / (n * lambda * (n + 5.0) * ratio);
        // Loop and Schaefer's length: face weight beta cos((2 pi i + pi) / n) / 3 with
        // beta = 1 / (n sqrt(4 + cos^2(pi / n))); our face weight is scale cos(pi / n) times it.
        if (rule == TangentRule::LoopSchaefer && faces > 2) {
            const double cp = std::cos(std::numbers::pi / n);
            scale = 1.0 / (3.0 * n * std::sqrt(4.0 + cp * cp) * cp);
        }
        for (uint32_t j = 0; j < faces; ++j) {
            glm::dvec3 t(0.0);
            for (uint32_t i = 0; i < faces; ++i) {
                double ci = std::cos(theta * (double(i) - double(j)));
                double ci1 = std::cos(theta * (double(i) + 1.0 - double(j)));
                t += a * ci * (at(cage, ring.edges[i]) - v) + 0.5 * (ci + ci1) * (at(cage, ring.diagonals[i]) - v);
            }
            limit.tangents[j] = scale * t;
        }
        limit.cosine = c;
        return limit;
    }

    const uint32_t k = faces;
    const glm::dvec3 e0 = at(cage, ring.edges.front()), ek = at(cage, ring.edges.back());
    if (k == 1) {
        limit.corner = isCorner(cage, ring);
        limit.position = limit.corner ? v : (e0 + 4.0 * v + ek) / 6.0;
        for (size_t j = 0; j < ring.edges.size(); ++j) limit.tangents[j] = (at(cage, ring.edges[j]) - v) / 3.0;
        limit.cosine = 0.0;
        return limit;
    }
    limit.position = (e0 + 4.0 * v + ek) / 6.0;
    const double kk = double(k), c = std::cos(std::numbers::pi / kk);
    const std::vector<double> mask = boundaryCrossMask(k);
    glm::dvec3 cross(0.0);
    for (uint32_t x = 0; x <= k; ++x) cross += mask[1 + x] * (at(cage, ring.edges[x]) - v);
    for (uint32_t x = 0; x < k; ++x) cross += mask[k + 2 + x] * (at(cage, ring.diagonals[x]) - v);
    cross /= 3.0;
    const glm::dvec3 along = (e0 - ek) / 6.0;
    for (uint32_t j = 0; j <= k; ++j)
        limit.tangents[j] = std::cos(std::numbers::pi * j / kk) * along + std::sin(std::numbers::pi * j / kk) * cross;
    limit.cosine = c;
    return limit;
}

glm::dvec3 interiorBezierPoint(const Cage& cage, const QuadRing& ring, uint32_t face) {
    const double n = ring.faceCount() == 1 && ring.boundary ? 4.0 : double(ring.effectiveValence());
    return (n * at(cage, ring.center) + 2.0 * at(cage, ring.edge(int(face))) + 2.0 * at(cage, ring.edge(int(face) + 1)) +
            at(cage, ring.diagonals[face])) /
           (n + 5.0);
}

}  // namespace qp
