#include "stam_eigen.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>

#include <Eigen/Dense>

namespace qp {

namespace {

using Row = std::vector<double>;  // weights over the 2n+8 template points

// The template mesh: the 2n+8 points and the faces that make v, e_0, d_0 and e_1 interior.
struct Template {
    uint32_t n = 0, size = 0;
    std::vector<std::array<uint32_t, 4>> faces;

    uint32_t e(int i) const { return 1 + 2 * uint32_t(((i % int(n)) + int(n)) % int(n)); }
    uint32_t d(int i) const { return 2 + 2 * uint32_t(((i % int(n)) + int(n)) % int(n)); }
    uint32_t extra(uint32_t j) const { return 2 * n + 1 + j; }  // p30 p31 p32 p33 p23 p13 p03

    explicit Template(uint32_t valence) : n(valence), size(2 * valence + 8) {
        for (int i = 0; i < int(n); ++i) faces.push_back({0, e(i), d(i), e(i + 1)});
        faces.push_back({e(0), d(-1), extra(0), extra(1)});  // below e_0 .. d_0, beyond
        faces.push_back({e(0), extra(1), extra(2), d(0)});
        faces.push_back({d(0), extra(2), extra(3), extra(4)});
        faces.push_back({e(1), d(0), extra(4), extra(5)});
        faces.push_back({e(1), extra(5), extra(6), d(1)});
    }

    // Level-0 grid position (col, row) of the patch's B-spline picture -> template point.
    // (0,0) is never needed; (0,1), (1,0), (0,2), (2,0) are e_2, e_{n-1}, d_1, d_{n-1}.
    uint32_t grid(int x, int y) const {
        static const int extras[4][4] = {{-1, -1, -1, 6}, {-1, -1, -1, 5}, {-1, -1, -1, 4}, {0, 1, 2, 3}};
        if (x == 1 && y == 1) return 0;
        if (x == 2 && y == 1) return e(0);
        if (x == 2 && y == 2) return d(0);
        if (x == 1 && y == 2) return e(1);
        if (x == 0 && y == 2) return d(1);
        if (x == 0 && y == 1) return e(2);
        if (x == 1 && y == 0) return e(-1);
        if (x == 2 && y == 0) return d(-1);
        assert(extras[x][y] >= 0);
        return extra(uint32_t(extras[x][y]));
    }

    Row unit(uint32_t i) const {
        Row r(size, 0.0);
        r[i] = 1.0;
        return r;
    }
    Row facePoint(uint32_t f) const {
        Row r(size, 0.0);
        for (uint32_t v : faces[f]) r[v] += 0.25;
        return r;
    }
    // Face with lower-left grid corner (x, y).
    uint32_t gridFace(int x, int y) const {
        std::array<uint32_t, 4> want = {grid(x, y), grid(x + 1, y), grid(x + 1, y + 1), grid(x, y + 1)};
        std::sort(want.begin(), want.end());
        for (uint32_t f = 0; f < faces.size(); ++f) {
            std::array<uint32_t, 4> have = faces[f];
            std::sort(have.begin(), have.end());
            if (have == want) return f;
        }
        assert(false && "grid face missing from the template");
        return 0;
    }
    Row edgePoint(uint32_t a, uint32_t b) const {
        Row r = unit(a);
        r[b] += 1.0;
        uint32_t found = 0;
        for (uint32_t f = 0; f < faces.size(); ++f)
            for (uint32_t k = 0; k < 4; ++k) {
                uint32_t p = faces[f][k], q = faces[f][(k + 1) % 4];
                if ((p == a && q == b) || (p == b && q == a)) {
                    Row fp = facePoint(f);
                    for (uint32_t i = 0; i < size; ++i) r[i] += fp[i];
                    ++found;
                }
            }
        assert(found == 2 && "edge point needs both faces in the template");
        for (double& w : r) w *= 0.25;
        return r;
    }
    Row vertexPoint(uint32_t x) const {
        std::vector<uint32_t> around, neighbours;
        for (uint32_t f = 0; f < faces.size(); ++f)
            for (uint32_t k = 0; k < 4; ++k)
                if (faces[f][k] == x) {
                    around.push_back(f);
                    neighbours.push_back(faces[f][(k + 1) % 4]);
                }
        const double m = double(around.size());
        Row r(size, 0.0);
        r[x] += (m - 2.0) / m;
        for (uint32_t v : neighbours) r[v] += 1.0 / (m * m);
        for (uint32_t f : around) {
            Row fp = facePoint(f);
            for (uint32_t i = 0; i < size; ++i) r[i] += fp[i] / (m * m);
        }
        return r;
    }
    // Child-level grid point (x, y), x and y in 1..5 (level-1 coordinates: twice level 0's).
    Row child(int x, int y) const {
        if (x % 2 == 0 && y % 2 == 0) return vertexPoint(grid(x / 2, y / 2));
        if (x % 2 == 1 && y % 2 == 0) return edgePoint(grid(x / 2, y / 2), grid(x / 2 + 1, y / 2));
        if (x % 2 == 0) return edgePoint(grid(x / 2, y / 2), grid(x / 2, y / 2 + 1));
        return facePoint(gridFace(x / 2, y / 2));
    }
};

std::unique_ptr<StamEigenStructure> compute(uint32_t n) {
    auto s = std::make_unique<StamEigenStructure>();
    Template t(n);
    const uint32_t size = t.size;
    s->valence = n;
    s->size = size;

    // A: the same 2n+8 structure one level down, around the child of v.
    std::vector<Row> rows(size);
    rows[0] = t.vertexPoint(0);
    for (int i = 0; i < int(n); ++i) {
        rows[t.e(i)] = t.edgePoint(0, t.e(i));
        rows[t.d(i)] = t.facePoint(uint32_t(i));
    }
    const int extraChild[7][2] = {{4, 1}, {4, 2}, {4, 3}, {4, 4}, {3, 4}, {2, 4}, {1, 4}};
    for (uint32_t j = 0; j < 7; ++j) rows[t.extra(j)] = t.child(extraChild[j][0], extraChild[j][1]);
    Eigen::MatrixXd A(size, size);
    for (uint32_t r = 0; r < size; ++r)
        for (uint32_t c = 0; c < size; ++c) A(r, c) = rows[r][c];

    // P_k A-bar: sub-patch k's 16 points; its corner (0,0) sits at child grid (3,2), (3,3), (2,3).
    const int origin[3][2] = {{3, 2}, {3, 3}, {2, 3}};
    Eigen::MatrixXd sub[3];
    for (int k = 0; k < 3; ++k) {
        sub[k].resize(16, size);
        for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col) {
                Row r = t.child(origin[k][0] + col - 1, origin[k][1] + row - 1);
                for (uint32_t c = 0; c < size; ++c) sub[k](4 * row + col, c) = r[c];
            }
    }

    // A's eigenvalues are real, and most are double (Fourier pairs); a general eigensolver may
    // return such a pair as lambda +- i eps with the same eigenvector twice. So take only the
    // eigenvalues from the solver, cluster them, and compute each cluster's eigenvectors as the
    // null space of A - lambda I (its smallest right singular vectors). A defective cluster (a
    // Jordan block) shows as a singular value that is not small, and in reconstructionError.
    Eigen::EigenSolver<Eigen::MatrixXd> solver(A, /*computeEigenvectors=*/false);
    std::vector<double> sorted(size);
    double imaginary = 0.0;
    for (uint32_t i = 0; i < size; ++i) {
        sorted[i] = solver.eigenvalues()[i].real();
        imaginary = std::max(imaginary, std::abs(solver.eigenvalues()[i].imag()));
    }
    std::sort(sorted.begin(), sorted.end(), std::greater<double>());
    Eigen::MatrixXd V(size, size);
    Eigen::VectorXd lambda(size);
    double nullity = 0.0;  // largest singular value accepted as zero
    for (uint32_t first = 0; first < size;) {
        uint32_t last = first + 1;
        while (last < size && sorted[first] - sorted[last] < 1e-9) ++last;
        const uint32_t multiplicity = last - first;
        double mu = 0.0;
        for (uint32_t i = first; i < last; ++i) mu += sorted[i] / multiplicity;
        Eigen::MatrixXd shifted = A - mu * Eigen::MatrixXd::Identity(size, size);
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(shifted, Eigen::ComputeFullV);
        for (uint32_t i = 0; i < multiplicity; ++i) {
            V.col(first + i) = svd.matrixV().col(size - multiplicity + i);
            lambda[first + i] = mu;
            nullity = std::max(nullity, svd.singularValues()[size - multiplicity + i]);
        }
        first = last;
    }
    // The eigenvalue-1 eigenvector is the constant vector: scale it to all ones, so its
    // eigenbasis function is exactly 1 and its coefficient the limit position.
    V.col(0) /= V.col(0).mean();
    Eigen::MatrixXd Vinv = V.inverse();

    // How well V Lambda^m V^-1 reproduces A^m (imaginary parts count as error too).
    double error = std::max(imaginary, nullity);
    Eigen::MatrixXd power = Eigen::MatrixXd::Identity(size, size);
    Eigen::VectorXd lambdaPower = Eigen::VectorXd::Ones(size);
    for (int m = 1; m <= 64; ++m) {
        power = power * A;
        lambdaPower = lambdaPower.cwiseProduct(lambda);
        Eigen::MatrixXd viaEigen = V * lambdaPower.asDiagonal() * Vinv;
        double difference = (viaEigen - power).cwiseAbs().maxCoeff();
        error = std::isfinite(difference) ? std::max(error, difference) : INFINITY;
    }
    s->reconstructionError = error;

    s->eigenvalues.assign(lambda.data(), lambda.data() + size);
    s->inverseEigenvectors.resize(size_t(size) * size);
    s->subdivision.resize(size_t(size) * size);
    for (uint32_t r = 0; r < size; ++r)
        for (uint32_t c = 0; c < size; ++c) {
            s->inverseEigenvectors[size_t(r) * size + c] = Vinv(r, c);
            s->subdivision[size_t(r) * size + c] = A(r, c);
        }
    for (int k = 0; k < 3; ++k) {
        Eigen::MatrixXd phi = sub[k] * V;
        s->basis[k].resize(16 * size_t(size));
        s->subpatches[k].resize(16 * size_t(size));
        for (uint32_t r = 0; r < 16; ++r)
            for (uint32_t c = 0; c < size; ++c) {
                s->basis[k][size_t(r) * size + c] = phi(r, c);
                s->subpatches[k][size_t(r) * size + c] = sub[k](r, c);
            }
    }
    return s;
}

}  // namespace

const StamEigenStructure& stamEigenStructure(uint32_t valence) {
    assert(valence >= 3);
    static std::mutex mutex;
    static std::map<uint32_t, std::unique_ptr<StamEigenStructure>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    auto& slot = cache[valence];
    if (!slot) slot = compute(valence);
    return *slot;
}

}  // namespace qp
