// Patch basis weights: internal consistency (partition of unity, finite differences) and
// agreement with OpenSubdiv (Far patch tables built with adaptive refinement).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include "plans/patch_basis.h"

namespace {

using namespace OpenSubdiv;
using qp::BasisWeights;

struct Point {
    double p[3] = {0, 0, 0};
    void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(const Point& s, double w) {
        for (int i = 0; i < 3; ++i) p[i] += w * s.p[i];
    }
};

double dist(const Point& a, const Point& b) {
    return std::sqrt((a.p[0] - b.p[0]) * (a.p[0] - b.p[0]) + (a.p[1] - b.p[1]) * (a.p[1] - b.p[1]) +
                     (a.p[2] - b.p[2]) * (a.p[2] - b.p[2]));
}

// A quad cage with optional creases; positions are part of it so Far and our bases see the same.
struct Mesh {
    std::vector<int> faceSizes, faceVerts, creasePairs;
    std::vector<float> creaseSharpness;
    std::vector<Point> positions;
};

// n x n quads on [0,n]^2, jittered in the plane and lifted randomly in z, so no weight error can
// hide behind symmetry. Vertex (x,y) has index y*(n+1)+x; face (x,y) = y*n+x has corner 0 at
// vertex (x,y) and u along x, v along y.
Mesh makeGrid(int n, std::mt19937& rng) {
    std::uniform_real_distribution<double> jitter(-0.2, 0.2), height(-0.5, 0.5);
    Mesh m;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) m.positions.push_back({{x + jitter(rng), y + jitter(rng), height(rng)}});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            int v = y * (n + 1) + x;
            m.faceSizes.push_back(4);
            m.faceVerts.insert(m.faceVerts.end(), {v, v + 1, v + n + 2, v + n + 1});
        }
    return m;
}

int gridVertex(int n, int x, int y) { return (x < 0 || y < 0 || x > n || y > n) ? -1 : y * (n + 1) + x; }

// Crease of sharpness s along the whole grid line y = row.
void addCreaseLine(Mesh& m, int n, int row, float s) {
    for (int x = 0; x < n; ++x) {
        m.creasePairs.insert(m.creasePairs.end(), {gridVertex(n, x, row), gridVertex(n, x + 1, row)});
        m.creaseSharpness.push_back(s);
    }
}

Mesh makeCube() {
    Mesh m;
    m.positions = {{{-1, -1, -1}}, {{1, -1, -1}}, {{1, 1, -1}}, {{-1, 1, -1}},
                   {{-1, -1, 1}},  {{1, -1, 1}},  {{1, 1, 1}},  {{-1, 1, 1}}};
    m.faceVerts = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    m.faceSizes.assign(6, 4);
    m.positions[6].p[0] = 1.7;  // break the symmetry
    m.positions[2].p[2] = -0.4;
    return m;
}

// OpenSubdiv's adaptive patch table of a mesh, with every point its patches read.
struct FarLimit {
    std::unique_ptr<Far::TopologyRefiner> refiner;
    std::unique_ptr<Far::PatchTable> table;
    std::unique_ptr<Far::PatchMap> map;
    std::vector<Point> points;  // all refined vertices, then the local (end cap) points

    FarLimit(const Mesh& m, int isolation) {
        Sdc::Options sdc;
        sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
        sdc.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
        Far::TopologyDescriptor desc;
        desc.numVertices = int(m.positions.size());
        desc.numFaces = int(m.faceSizes.size());
        desc.numVertsPerFace = m.faceSizes.data();
        desc.vertIndicesPerFace = m.faceVerts.data();
        desc.numCreases = int(m.creaseSharpness.size());
        desc.creaseVertexIndexPairs = m.creasePairs.data();
        desc.creaseWeights = m.creaseSharpness.data();
        using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
        refiner.reset(Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));

        Far::PatchTableFactory::Options options(isolation);
        options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
        options.SetPatchPrecision<double>();
        options.useSingleCreasePatch = false;  // subdivide semi-sharp creases away: exact
        // Infinitely sharp regular creases become boundary patches (exact) instead of being
        // isolated to the last level and approximated by end caps there.
        options.useInfSharpPatch = true;
        refiner->RefineAdaptive(options.GetRefineAdaptiveOptions());
        table.reset(Far::PatchTableFactory::Create(*refiner, options));
        map = std::make_unique<Far::PatchMap>(*table);

        int refined = refiner->GetNumVerticesTotal();
        points.resize(refined + table->GetNumLocalPoints());
        std::copy(m.positions.begin(), m.positions.end(), points.begin());
        Far::PrimvarRefinerReal<double> primvar(*refiner);
        Point* src = points.data();
        for (int level = 1; level <= refiner->GetMaxLevel(); ++level) {
            Point* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
            primvar.Interpolate(level, src, dst);
            src = dst;
        }
        if (auto* stencils = table->GetLocalPointStencilTable<double>())
            stencils->UpdateValues(points.data(), points.data() + refined);
    }

    // Limit point and base-face derivatives at (u,v) of base face `face`.
    void eval(int face, double u, double v, Point out[3]) const {
        const Far::PatchMap::Handle* h = map->FindPatch(face, u, v);
        EXPECT_NE(h, nullptr);
        if (!h) return;
        double w[3][20];
        table->EvaluateBasis(*h, u, v, w[0], w[1], w[2]);
        Far::ConstIndexArray cvs = table->GetPatchVertices(*h);
        for (int k = 0; k < 3; ++k) {
            out[k].Clear();
            for (int i = 0; i < cvs.size(); ++i) out[k].AddWithWeight(points[cvs[i]], w[k][i]);
        }
    }
};

// Our patch from its (up to 20) control points.
void evalOurs(const BasisWeights& b, const std::vector<Point>& cvs, Point out[3]) {
    const float* w[3] = {b.w, b.du, b.dv};
    for (int k = 0; k < 3; ++k) {
        out[k].Clear();
        for (size_t i = 0; i < cvs.size(); ++i) out[k].AddWithWeight(cvs[i], w[k][i]);
    }
}

// The 16 base-level control points of grid face (x,y), row-major with row along v. Points off
// the grid are phantoms and get a wild value: their weight must be exactly 0.
std::vector<Point> gridPatch(const Mesh& m, int n, int x, int y) {
    std::vector<Point> cvs;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            int v = gridVertex(n, x - 1 + c, y - 1 + r);
            cvs.push_back(v < 0 ? Point{{1e6, -1e6, 1e6}} : m.positions[v]);
        }
    return cvs;
}

// Every kind the header offers, as a plain function of (u,v).
std::vector<std::pair<const char*, std::function<void(float, float, BasisWeights&)>>> allKinds() {
    std::vector<std::pair<const char*, std::function<void(float, float, BasisWeights&)>>> kinds;
    kinds.push_back({"bspline", qp::bsplineWeights});
    kinds.push_back({"gregory", [](float u, float v, BasisWeights& b) { qp::gregoryWeights(u, v, b); }});
    kinds.push_back({"gregory exact", [](float u, float v, BasisWeights& b) { qp::gregoryWeights(u, v, b, true); }});
    for (float s : {0.0f, 0.5f, 1.0f, 1.3f, 2.7f, 4.7f, 10.0f})
        kinds.push_back({"crease", [s](float u, float v, BasisWeights& b) { qp::creaseWeights(u, v, s, b); }});
    for (int mask : {1, 2, 4, 8, 3, 6, 12, 9, 5, 15})
        kinds.push_back({"bspline+fold", [mask](float u, float v, BasisWeights& b) {
                             qp::bsplineWeights(u, v, b);
                             qp::foldBoundaryWeights(mask, b);
                         }});
    kinds.push_back({"crease+fold", [](float u, float v, BasisWeights& b) {
                         qp::creaseWeights(u, v, 1.3f, b);
                         qp::foldBoundaryWeights(2 | 8, b);
                     }});
    return kinds;
}

}  // namespace

TEST(PatchBasis, PartitionOfUnity) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    for (auto& [name, fn] : allKinds())
        for (int i = 0; i < 200; ++i) {
            float u = uni(rng), v = uni(rng);
            BasisWeights b;
            fn(u, v, b);
            double sw = 0, su = 0, sv = 0;
            for (int k = 0; k < 20; ++k) sw += b.w[k], su += b.du[k], sv += b.dv[k];
            EXPECT_NEAR(sw, 1.0, 1e-5) << name << " at " << u << "," << v;
            EXPECT_NEAR(su, 0.0, 1e-4) << name << " at " << u << "," << v;
            EXPECT_NEAR(sv, 0.0, 1e-4) << name << " at " << u << "," << v;
        }
}

// Central differences of the float weights, step 1e-3: float rounding (~3e-5) and truncation
// (~2e-4 for the steep s = 4.7 crease profile) stay well below the 1e-3 tolerance.
TEST(PatchBasis, DerivativesMatchFiniteDifferences) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> uni(0.02f, 0.98f);
    const float h = 1e-3f;
    double worst = 0;
    for (auto& [name, fn] : allKinds())
        for (int i = 0; i < 200 && name != std::string("gregory"); ++i) {  // OpenSubdiv's: see below
            float u = uni(rng), v = uni(rng);
            BasisWeights b, up, um, vp, vm;
            fn(u, v, b);
            fn(u + h, v, up);
            fn(u - h, v, um);
            fn(u, v + h, vp);
            fn(u, v - h, vm);
            for (int k = 0; k < 20; ++k) {
                double fu = (double(up.w[k]) - um.w[k]) / (2 * h), fv = (double(vp.w[k]) - vm.w[k]) / (2 * h);
                EXPECT_NEAR(b.du[k], fu, 1e-3) << name << " weight " << k << " at " << u << "," << v;
                EXPECT_NEAR(b.dv[k], fv, 1e-3) << name << " weight " << k << " at " << u << "," << v;
                worst = std::max({worst, std::abs(b.du[k] - fu), std::abs(b.dv[k] - fv)});
            }
        }
    std::printf("[ measured ] max finite-difference error %.3g\n", worst);
}

// The crease basis reduces to the plain and to the folded (infinitely sharp) B-spline.
TEST(PatchBasis, CreaseLimits) {
    for (float u : {0.0f, 0.3f, 1.0f})
        for (float v : {0.0f, 0.01f, 0.4f, 1.0f}) {
            BasisWeights plain, sharp, c0, c10;
            qp::bsplineWeights(u, v, plain);
            qp::bsplineWeights(u, v, sharp);
            qp::foldBoundaryWeights(1, sharp);
            qp::creaseWeights(u, v, 0.0f, c0);
            qp::creaseWeights(u, v, 10.0f, c10);
            for (int k = 0; k < 16; ++k) {
                EXPECT_NEAR(c0.w[k], plain.w[k], 1e-6);
                EXPECT_NEAR(c0.dv[k], plain.dv[k], 1e-6);
                EXPECT_NEAR(c10.w[k], sharp.w[k], 1e-6);
                EXPECT_NEAR(c10.dv[k], sharp.dv[k], 1e-6);
            }
        }
}

// Gregory derivatives as OpenSubdiv computes them (blend weights held fixed) differ from the
// exact ones only by the derivative of the blend, which is zero on the patch edges and cancels
// within each Fp/Fm pair.
TEST(PatchBasis, GregoryDefaultDerivativesHoldBlendFixed) {
    std::mt19937 rng(6);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    for (int i = 0; i < 400; ++i) {
        float u = uni(rng), v = uni(rng);
        if (i % 4 == 1) v = float(i % 8 == 1);  // on the edges v=0 and v=1
        if (i % 4 == 2) u = float(i % 8 == 2);  // on the edges u=0 and u=1
        BasisWeights osd, exact;
        qp::gregoryWeights(u, v, osd);
        qp::gregoryWeights(u, v, exact, true);
        bool onEdge = u == 0 || u == 1 || v == 0 || v == 1;
        for (int k = 0; k < 20; ++k) {
            EXPECT_EQ(osd.w[k], exact.w[k]);
            bool facePoint = k % 5 >= 3;
            if (!facePoint || onEdge) {
                EXPECT_NEAR(osd.du[k], exact.du[k], 1e-6) << k << " at " << u << "," << v;
                EXPECT_NEAR(osd.dv[k], exact.dv[k], 1e-6) << k << " at " << u << "," << v;
            }
            if (k % 5 == 3) {
                EXPECT_NEAR(osd.du[k] + osd.du[k + 1], exact.du[k] + exact.du[k + 1], 1e-6);
                EXPECT_NEAR(osd.dv[k] + osd.dv[k + 1], exact.dv[k] + exact.dv[k + 1], 1e-6);
            }
        }
    }
    BasisWeights a, b;  // and the blend does matter inside the patch
    qp::gregoryWeights(0.3f, 0.6f, a);
    qp::gregoryWeights(0.3f, 0.6f, b, true);
    EXPECT_GT(std::abs(a.du[3] - b.du[3]), 1e-2);
}

// Regular patches, interior and on the boundary (with the boundary mask folded), against Far's
// EvaluateBasis on a 5x5 grid whose patches all sit at level 0: weights per cage vertex.
TEST(PatchBasis, BSplineAndBoundaryFoldMatchFar) {
    const int n = 5;
    std::mt19937 rng(3);
    Mesh mesh = makeGrid(n, rng);
    FarLimit far(mesh, 4);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    double worstW = 0, worstP = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            int mask = (y == 0 ? 1 : 0) | (x == n - 1 ? 2 : 0) | (y == n - 1 ? 4 : 0) | (x == 0 ? 8 : 0);
            std::vector<Point> cvs = gridPatch(mesh, n, x, y);
            for (int i = 0; i < 20; ++i) {
                double u = i == 0 ? 0.0 : uni(rng), v = i == 0 ? 1.0 : uni(rng);
                const Far::PatchMap::Handle* h = far.map->FindPatch(y * n + x, u, v);
                ASSERT_NE(h, nullptr);
                Far::PatchParam param = far.table->GetPatchParam(*h);
                ASSERT_EQ(far.table->GetPatchDescriptor(*h).GetType(), Far::PatchDescriptor::REGULAR);
                ASSERT_EQ(param.GetDepth(), 0);
                ASSERT_EQ(param.GetBoundary(), mask) << "face " << x << "," << y;  // our bit order is Far's

                double fw[3][20];
                far.table->EvaluateBasis(*h, u, v, fw[0], fw[1], fw[2]);
                Far::ConstIndexArray idx = far.table->GetPatchVertices(*h);
                BasisWeights ours;
                qp::bsplineWeights(float(u), float(v), ours);
                qp::foldBoundaryWeights(mask, ours);
                const float* ow[3] = {ours.w, ours.du, ours.dv};
                for (int k = 0; k < 3; ++k) {
                    std::map<int, double> farByVertex, oursByVertex;
                    for (int i2 = 0; i2 < 16; ++i2) {
                        if (idx[i2] >= 0) farByVertex[idx[i2]] += fw[k][i2];
                        int gv = gridVertex(n, x - 1 + i2 % 4, y - 1 + i2 / 4);
                        if (gv < 0)
                            EXPECT_EQ(ow[k][i2], 0.0f) << "phantom weight not folded";
                        else
                            oursByVertex[gv] += ow[k][i2];
                    }
                    for (auto [vtx, w] : farByVertex) {
                        EXPECT_NEAR(oursByVertex[vtx], w, 1e-5) << "face " << x << "," << y << " vertex " << vtx;
                        worstW = std::max(worstW, std::abs(oursByVertex[vtx] - w));
                    }
                    for (auto [vtx, w] : oursByVertex) EXPECT_NEAR(farByVertex[vtx], w, 1e-5);
                }
                Point fp[3], op[3];
                far.eval(y * n + x, u, v, fp);
                evalOurs(ours, cvs, op);
                for (int k = 0; k < 3; ++k) {
                    EXPECT_LT(dist(fp[k], op[k]), 1e-5 * n) << "face " << x << "," << y;
                    worstP = std::max(worstP, dist(fp[k], op[k]));
                }
            }
        }
    std::printf("[ measured ] regular/boundary: max weight error %.3g, max point error %.3g\n", worstW, worstP);
}

// Gregory end caps (and the regular patches beside them) of a cube refined to level 2: weight
// arrays in Far's point order, derivatives rescaled from base-face to patch parameters.
TEST(PatchBasis, GregoryMatchesFar) {
    FarLimit far(makeCube(), 2);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    int gregory = 0, regular = 0;
    double worst = 0;
    for (int face = 0; face < 6; ++face)
        for (int i = 0; i < 400; ++i) {
            // Some samples exactly on patch corners and edges (u,v multiples of 1/4).
            double u = i < 25 ? (i % 5) / 4.0 : uni(rng), v = i < 25 ? (i / 5) / 4.0 : uni(rng);
            const Far::PatchMap::Handle* h = far.map->FindPatch(face, u, v);
            ASSERT_NE(h, nullptr);
            Far::PatchParam param = far.table->GetPatchParam(*h);
            Far::PatchDescriptor::Type type = far.table->GetPatchDescriptor(*h).GetType();
            double fw[3][20];
            far.table->EvaluateBasis(*h, u, v, fw[0], fw[1], fw[2]);
            double pu = u, pv = v, scale = 1 << param.GetDepth();  // d/du(face) = scale * d/du(patch)
            param.Normalize(pu, pv);
            BasisWeights ours;
            int count = 0;
            if (type == Far::PatchDescriptor::GREGORY_BASIS) {
                qp::gregoryWeights(float(pu), float(pv), ours);
                count = 20;
                ++gregory;
            } else {
                ASSERT_EQ(type, Far::PatchDescriptor::REGULAR);
                qp::bsplineWeights(float(pu), float(pv), ours);
                qp::foldBoundaryWeights(param.GetBoundary(), ours);
                count = 16;
                ++regular;
            }
            for (int k = 0; k < count; ++k) {
                EXPECT_NEAR(ours.w[k], fw[0][k], 1e-5) << "point " << k << " at " << pu << "," << pv;
                EXPECT_NEAR(ours.du[k], fw[1][k] / scale, 1e-5) << "point " << k << " at " << pu << "," << pv;
                EXPECT_NEAR(ours.dv[k], fw[2][k] / scale, 1e-5) << "point " << k << " at " << pu << "," << pv;
                worst = std::max({worst, std::abs(ours.w[k] - fw[0][k]), std::abs(ours.du[k] - fw[1][k] / scale),
                                  std::abs(ours.dv[k] - fw[2][k] / scale)});
            }
        }
    EXPECT_GT(gregory, 500);
    EXPECT_GT(regular, 200);
    std::printf("[ measured ] gregory: %d Gregory + %d regular samples, max weight error %.3g\n", gregory, regular,
                worst);
}

// Semi-sharp creases: our crease patch on the 16 base-level points against the exact limit
// (Far adaptive refinement isolates the crease until its sharpness is spent, level <= 10).
class PatchBasisCrease : public ::testing::TestWithParam<float> {};

TEST_P(PatchBasisCrease, MatchesFarLimit) {
    const float s = GetParam();
    const int n = 8, row = 4;
    std::mt19937 rng(5);
    Mesh mesh = makeGrid(n, rng);
    addCreaseLine(mesh, n, row, s);
    FarLimit far(mesh, 10);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    double worstP = 0, worstD = 0;
    auto check = [&](int x, int y, int mask, bool mirrored) {
        // Mirrored: the face below the crease; our v = 1 - face v and our rows run downwards.
        std::vector<Point> cvs;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) {
                int gy = mirrored ? y + 2 - r : y - 1 + r, gv = gridVertex(n, x - 1 + c, gy);
                cvs.push_back(gv < 0 ? Point{{1e6, -1e6, 1e6}} : mesh.positions[gv]);
            }
        for (int i = 0; i < 60; ++i) {
            double u = uni(rng), t = uni(rng);
            double v = i % 2 ? t : std::pow(t, 4);  // half the samples close to the crease
            if (i == 0) v = 0;
            BasisWeights ours;
            qp::creaseWeights(float(u), float(v), s, ours);
            qp::foldBoundaryWeights(mask, ours);
            Point op[3], fp[3];
            evalOurs(ours, cvs, op);
            far.eval(y * n + x, u, mirrored ? 1 - v : v, fp);
            if (mirrored)
                for (double& c : fp[2].p) c = -c;
            double ep = dist(op[0], fp[0]), ed = std::max(dist(op[1], fp[1]), dist(op[2], fp[2]));
            EXPECT_LT(ep, 1e-5 * n) << "s " << s << " face " << x << "," << y << " at " << u << "," << v;
            EXPECT_LT(ed, 1e-4) << "s " << s << " face " << x << "," << y << " at " << u << "," << v;
            worstP = std::max(worstP, ep);
            worstD = std::max(worstD, ed);
        }
    };
    for (int x = 2; x <= 5; ++x) {
        check(x, row, 0, false);
        check(x, row - 1, 0, true);
    }
    // The crease meeting the boundary (u=0 and u=1 edges folded).
    check(0, row, 8, false);
    check(n - 1, row, 2, false);
    check(0, row - 1, 8, true);
    std::printf("[ measured ] crease s=%g: max point error %.3g, max derivative error %.3g\n", s, worstP, worstD);
}

INSTANTIATE_TEST_SUITE_P(PatchBasis, PatchBasisCrease,
                         ::testing::Values(0.5f, 1.0f, 1.3f, 2.0f, 2.7f, 4.7f, 10.0f));
