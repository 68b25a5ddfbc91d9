#include "plans/plan_builder.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <bit>
#include <memory>
#include <numeric>

#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include "plans/dense_stencils.h"
#include "plans/osd_refiner.h"
#include "plans/tangent_plane.h"

namespace qp {

using namespace OpenSubdiv;

namespace {

// The local mesh serialised in a configuration key.
struct LocalMesh {
    uint32_t maxDepth = 0;
    bool useCreaseNodes = false;
    SubdivisionOptions options;
    uint32_t vertexCount = 0;
    std::vector<int> faceSizes, faceVertices, creaseVertices, cornerVertices;
    std::vector<float> creaseWeights, cornerWeights;
};

LocalMesh parseKey(const std::vector<uint32_t>& key) {
    LocalMesh mesh;
    size_t i = 1;  // skip the version
    mesh.maxDepth = key[i++];
    mesh.useCreaseNodes = key[i++] != 0;
    uint32_t optionWord = key[i++];
    mesh.options.boundary = BoundaryInterpolation(optionWord & 0xf);
    mesh.options.creaseMethod = CreaseMethod((optionWord >> 4) & 0xf);
    mesh.options.triangleSubdivision = TriangleSubdivision((optionWord >> 8) & 0xf);
    mesh.vertexCount = key[i++];
    uint32_t faceCount = key[i++];
    for (uint32_t f = 0; f < faceCount; ++f) {
        uint32_t size = key[i++];
        mesh.faceSizes.push_back(int(size));
        for (uint32_t k = 0; k < size; ++k) mesh.faceVertices.push_back(int(key[i++]));
    }
    uint32_t creaseCount = key[i++];
    for (uint32_t c = 0; c < creaseCount; ++c) {
        mesh.creaseVertices.push_back(int(key[i++]));
        mesh.creaseVertices.push_back(int(key[i++]));
        mesh.creaseWeights.push_back(std::bit_cast<float>(key[i++]));
    }
    uint32_t cornerCount = key[i++];
    for (uint32_t c = 0; c < cornerCount; ++c) {
        mesh.cornerVertices.push_back(int(key[i++]));
        mesh.cornerWeights.push_back(std::bit_cast<float>(key[i++]));
    }
    return mesh;
}

Result<std::unique_ptr<Far::TopologyRefiner>> createLocalRefiner(const LocalMesh& mesh) {
    Far::TopologyDescriptor desc;
    desc.numVertices = int(mesh.vertexCount);
    desc.numFaces = int(mesh.faceSizes.size());
    desc.numVertsPerFace = mesh.faceSizes.data();
    desc.vertIndicesPerFace = mesh.faceVertices.data();
    desc.numCreases = int(mesh.creaseWeights.size());
    desc.creaseVertexIndexPairs = mesh.creaseVertices.data();
    desc.creaseWeights = mesh.creaseWeights.data();
    desc.numCorners = int(mesh.cornerWeights.size());
    desc.cornerVertexIndices = mesh.cornerVertices.data();
    desc.cornerWeights = mesh.cornerWeights.data();
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Far::TopologyRefiner* refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, toSdcOptions(mesh.options)));
    if (!refiner) return Error{"OpenSubdiv rejected the local topology of a face configuration"};
    return std::unique_ptr<Far::TopologyRefiner>(refiner);
}

// A leaf as Far produced it, before quadtree assembly. Points are Far vertex indices (all
// refinement levels, then end-cap local points).
struct FarLeaf {
    uint32_t depth, u, v;  // depth below the (sub-)face, integer position at that depth
    PlanNode node;
    std::vector<uint32_t> farPoints;
};

Result<std::vector<FarLeaf>> collectLeaves(const Far::PatchTable& patches) {
    std::vector<FarLeaf> leaves;
    for (int array = 0; array < patches.GetNumPatchArrays(); ++array) {
        Far::PatchDescriptor::Type type = patches.GetPatchArrayDescriptor(array).GetType();
        for (int p = 0; p < patches.GetNumPatches(array); ++p) {
            Far::PatchParam param = patches.GetPatchParam(array, p);
            if (param.GetFaceId() != 0) continue;  // another sub-face of an n-gon
            Far::ConstIndexArray cvs = patches.GetPatchVertices(array, p);
            FarLeaf leaf;
            leaf.depth = param.GetDepth() - (param.NonQuadRoot() ? 1 : 0);
            leaf.u = param.GetU();
            leaf.v = param.GetV();
            if (type == Far::PatchDescriptor::REGULAR) {
                // Far keeps no sharpness table at all unless single-crease patches were asked for.
                float sharpness = patches.GetSharpnessIndexTable().empty()
                                      ? 0.0f
                                      : patches.GetSingleCreasePatchSharpnessValue(array, p);
                if (sharpness > 0.0f) {
                    // Far marks the creased edge, and only it, in a single-crease patch's
                    // boundary mask (such patches never lie on a real boundary).
                    int mask = param.GetBoundary();
                    if (std::popcount(unsigned(mask)) != 1) return Error{"unexpected single-crease patch from OpenSubdiv"};
                    leaf.node.kind = NodeKind::Crease;
                    leaf.node.edge = uint8_t(std::countr_zero(unsigned(mask)));
                    leaf.node.sharpness = sharpness;
                } else {
                    leaf.node.kind = NodeKind::Regular;
                    leaf.node.boundaryMask = uint8_t(param.GetBoundary());
                }
            } else {
                assert(type == Far::PatchDescriptor::GREGORY_BASIS);
                leaf.node.kind = NodeKind::Extraordinary;
            }
            for (int k = 0; k < cvs.size(); ++k) leaf.farPoints.push_back(uint32_t(cvs[k]));
            leaves.push_back(std::move(leaf));
        }
    }
    return leaves;
}

// Intermediate quadtree: nodes whose leaf points are still Far indices.
struct Tree {
    std::vector<PlanNode> nodes{PlanNode{}};
    std::vector<std::vector<uint32_t>> points{{}};  // per node (leaves only)
    std::vector<bool> filled{false};
};

void insertLeaf(Tree& tree, const FarLeaf& leaf) {
    uint32_t node = 0;
    for (uint32_t level = 1; level <= leaf.depth; ++level) {
        if (tree.nodes[node].kind != NodeKind::Internal || !tree.filled[node]) {
            tree.nodes[node] = PlanNode{NodeKind::Internal, 0, 0, 0, uint32_t(tree.nodes.size()), 0.0f};
            tree.filled[node] = true;
            tree.nodes.resize(tree.nodes.size() + 4);
            tree.points.resize(tree.nodes.size());
            tree.filled.resize(tree.nodes.size(), false);
        }
        uint32_t shift = leaf.depth - level;
        uint32_t child = ((leaf.u >> shift) & 1) | (((leaf.v >> shift) & 1) << 1);
        node = tree.nodes[node].first + child;
    }
    tree.nodes[node] = leaf.node;
    tree.points[node] = leaf.farPoints;
    tree.filled[node] = true;
}

// Grid position (0..4, 0..4) of control point k of child quadrant `child`, mirrored so the EV
// corner `corner` of the parent is at grid (1,1).
std::pair<int, int> terminalGridPosition(uint32_t child, uint32_t k, uint32_t corner) {
    int x = int(child & 1) + int(k % 4) - 1;  // -1..3 in the parent's child grid
    int y = int(child >> 1) + int(k / 4) - 1;
    bool mirrorU = corner == 1 || corner == 2, mirrorV = corner == 2 || corner == 3;
    if (mirrorU) x = 2 - x;
    if (mirrorV) y = 2 - y;
    return {x + 1, y + 1};
}

constexpr uint32_t kCornerChild[4] = {0, 1, 3, 2};  // child quadrant touching parent corner c

// Collapses an internal node whose children are three plain regular quadrants and one
// Extraordinary or Terminal child at a corner into one Terminal node (bottom-up).
bool collapseTerminal(Tree& tree, uint32_t node) {
    PlanNode& parent = tree.nodes[node];
    if (parent.kind != NodeKind::Internal) return false;
    for (uint32_t corner = 0; corner < 4; ++corner) {
        uint32_t evChild = parent.first + kCornerChild[corner];
        const PlanNode& ev = tree.nodes[evChild];
        bool chainBelow = ev.kind == NodeKind::Extraordinary || (ev.kind == NodeKind::Terminal && ev.edge == corner);
        if (!chainBelow) continue;

        std::vector<int32_t> grid(25, -1);
        bool ok = true;
        for (uint32_t c = 0; c < 4 && ok; ++c) {
            if (c == kCornerChild[corner]) continue;
            const PlanNode& quadrant = tree.nodes[parent.first + c];
            if (quadrant.kind != NodeKind::Regular || quadrant.boundaryMask != 0) ok = false;
            for (uint32_t k = 0; ok && k < 16; ++k) {
                auto [gx, gy] = terminalGridPosition(c, k, corner);
                int32_t& slot = grid[gy * 5 + gx];
                int32_t point = int32_t(tree.points[parent.first + c][k]);
                if (slot >= 0 && slot != point) ok = false;
                slot = point;
            }
        }
        if (!ok || grid[0] >= 0 || std::count(grid.begin() + 1, grid.end(), -1) != 0) return false;

        std::vector<uint32_t> points(grid.begin() + 1, grid.end());
        const std::vector<uint32_t>& below = tree.points[evChild];
        points.insert(points.end(), below.begin(), below.end());
        uint8_t levels = uint8_t(ev.kind == NodeKind::Terminal ? ev.levels + 1 : 1);
        parent = PlanNode{NodeKind::Terminal, 0, uint8_t(corner), levels, 0, 0.0f};
        tree.points[node] = std::move(points);
        return true;
    }
    return false;
}

void collapseTerminals(Tree& tree, uint32_t node) {
    if (tree.nodes[node].kind != NodeKind::Internal) return;
    for (uint32_t c = 0; c < 4; ++c) collapseTerminals(tree, tree.nodes[node].first + c);
    collapseTerminal(tree, node);
}

// Copies the reachable part of `tree` into `plan` in breadth-first order (dropping the
// children of collapsed nodes), with leaf points still as Far indices.
void flattenTree(const Tree& tree, Plan& plan, std::vector<uint32_t>& farPoints) {
    plan.nodes.clear();
    std::vector<uint32_t> source{0};
    plan.nodes.push_back(tree.nodes[0]);
    for (size_t i = 0; i < source.size(); ++i) {
        PlanNode& node = plan.nodes[i];
        const std::vector<uint32_t>& pts = tree.points[source[i]];
        if (node.kind == NodeKind::Internal) {
            uint32_t firstChild = tree.nodes[source[i]].first;
            node.first = uint32_t(plan.nodes.size());
            for (uint32_t c = 0; c < 4; ++c) {
                source.push_back(firstChild + c);
                plan.nodes.push_back(tree.nodes[firstChild + c]);
            }
        } else {
            node.first = uint32_t(farPoints.size());
            farPoints.insert(farPoints.end(), pts.begin(), pts.end());
        }
    }
}

// Lowest level each Far point is needed at, from the leaves that read it (before collapsing);
// indexed by Far point, UINT32_MAX for points no leaf reads.
std::vector<uint32_t> pointLevels(const std::vector<FarLeaf>& leaves, uint32_t maxDepth, uint32_t farPointCount) {
    std::vector<uint32_t> levels(farPointCount, UINT32_MAX);
    for (const FarLeaf& leaf : leaves) {
        float size = std::ldexp(1.0f, -int(leaf.depth));
        uint32_t level = nodeNeededLevel(float(leaf.u) * size, float(leaf.v) * size, size, maxDepth);
        for (uint32_t p : leaf.farPoints) levels[p] = std::min(levels[p], level);
    }
    return levels;
}

// Which corner of the (sub-)face the leaf's corner i ((0,0) (1,0) (1,1) (0,1)) lies on, or -1.
int leafCornerAtFaceCorner(const FarLeaf& leaf, uint32_t i) { return patchCornerOfDomain(leaf.u, leaf.v, 1u << leaf.depth, i); }

// The exact tangent masks of the (sub-)face's extraordinary corners that an end cap (a
// Gregory-basis leaf) touches and that have them (smooth and dart vertices, tangent_plane.h),
// by plan-frame corner: a quad's four vertices; an n-gon's sub-face has its face's vertex at
// corner 0 and the face's centre, a valence-n vertex from level 1 on, at corner 2.
using CornerTangents = std::array<std::optional<ExactTangents>, 4>;
CornerTangents endCapCornerTangents(const Far::TopologyRefiner& refiner, const std::vector<FarLeaf>& leaves) {
    const Far::ConstIndexArray face = refiner.GetLevel(0).GetFaceVertices(0);
    const bool quad = face.size() == 4;
    CornerTangents tangents;
    std::array<bool, 4> touched{};
    for (const FarLeaf& leaf : leaves) {
        if (leaf.node.kind != NodeKind::Extraordinary) continue;
        for (uint32_t i = 0; i < 4; ++i)
            if (const int c = leafCornerAtFaceCorner(leaf, i); c >= 0) touched[size_t(c)] = true;
    }
    for (int c = 0; c < 4; ++c) {
        if (!touched[size_t(c)]) continue;
        if (quad || c == 0) tangents[size_t(c)] = exactTangents(refiner, face[quad ? c : 0], true);
        else if (c == 2) tangents[size_t(c)] = faceCentreTangents(refiner, 0);
    }
    return tangents;
}

// Far's Gregory-basis end caps take a corner's tangents from Sdc's limit masks, which at a dart
// are the smooth rule's and not the limit's (tangent_plane.h). At each end-cap corner on a dart
// corner of the face, the edge points Ep and Em are moved onto the exact tangent plane: their
// tangent masks (Ep - P, Em - P) projected onto the dart's dominant eigenvectors, so the patch's
// normal at the corner is the limit's for any positions of the cage.
void exactDartCorners(const LocalMesh& mesh, const std::vector<FarLeaf>& leaves, const CornerTangents& tangents,
                      const std::vector<uint32_t>& slotOf, Plan& plan) {
    std::vector<char> done(slotOf.size(), 0);
    for (const FarLeaf& leaf : leaves) {
        if (leaf.node.kind != NodeKind::Extraordinary) continue;
        for (uint32_t i = 0; i < 4; ++i) {  // the patch's corner i, (0,0) (1,0) (1,1) (0,1)
            const int c = leafCornerAtFaceCorner(leaf, i);
            if (c < 0 || !tangents[size_t(c)] || !tangents[size_t(c)]->dart) continue;
            const ExactTangents& t = *tangents[size_t(c)];
            const float* p = &plan.stencilWeights[size_t(slotOf[leaf.farPoints[5 * i]]) * mesh.vertexCount];
            for (uint32_t edgePoint : {leaf.farPoints[5 * i + 1], leaf.farPoints[5 * i + 2]}) {
                if (done[edgePoint]) continue;  // shared with the neighbouring end cap
                done[edgePoint] = 1;
                float* row = &plan.stencilWeights[size_t(slotOf[edgePoint]) * mesh.vertexCount];
                std::vector<double> mask(t.ring.size());
                for (size_t j = 0; j < t.ring.size(); ++j) mask[j] = double(row[t.ring[j]]) - double(p[t.ring[j]]);
                const std::vector<double> exact = t.project(mask);
                for (size_t j = 0; j < t.ring.size(); ++j) row[t.ring[j]] = float(double(p[t.ring[j]]) + exact[j]);
            }
        }
    }
}

}  // namespace

uint32_t nodeNeededLevel(float u0, float v0, float size, uint32_t maxDepth) {
    // Tessellation vertices at factor f <= 2^n have coordinates 0, 1, or in [1/f, 1 - 1/f]; on
    // a split line the evaluator picks the side towards the face centre. So a node is reached
    // at level n when, in both directions, it touches the face edge or meets (2^-n, 1 - 2^-n).
    // At level 1 the only inner coordinate is the centre line 0.5 itself, which the root
    // split may send either way.
    auto reaches = [](float lo, float hi, float margin) {
        return lo == 0.0f || hi == 1.0f || (hi > margin && lo < 1.0f - margin) ||
               (margin == 0.5f && (hi == 0.5f || lo == 0.5f));
    };
    for (uint32_t n = 0; n <= maxDepth; ++n) {
        float margin = std::ldexp(1.0f, -int(n));
        if (reaches(u0, u0 + size, margin) && reaches(v0, v0 + size, margin)) return n;
    }
    return maxDepth;
}

Result<Plan> buildPlan(const std::vector<uint32_t>& key) {
    LocalMesh mesh = parseKey(key);
    auto refiner = createLocalRefiner(mesh);
    if (!refiner) return refiner.error();

    Far::PatchTableFactory::Options patchOptions = planPatchOptions(mesh.maxDepth, mesh.useCreaseNodes);

    Far::Index selected[1] = {0};
    Far::ConstIndexArray selectedFaces(selected, 1);
    // With Chaikin creases, Far's adaptive refinement of one selected face computes the child
    // sharpness of its neighbourhood wrongly (catmark_chaikin1 is off by 5e-4 of its size);
    // refining the whole 1-ring is exact. It costs more, so only Chaikin cages pay for it.
    if (mesh.options.creaseMethod == CreaseMethod::Chaikin && !mesh.creaseWeights.empty())
        (*refiner)->RefineAdaptive(patchOptions.GetRefineAdaptiveOptions());
    else
        (*refiner)->RefineAdaptive(patchOptions.GetRefineAdaptiveOptions(), selectedFaces);
    std::unique_ptr<Far::PatchTable> patches(Far::PatchTableFactory::Create(**refiner, patchOptions, selectedFaces));
    thread_local DenseStencils stencils;  // reused: fresh memory for each plan cost page faults
    computeDenseStencils(**refiner, *patches, stencils);

    Result<std::vector<FarLeaf>> collected = collectLeaves(*patches);
    if (!collected) return collected.error();
    std::vector<FarLeaf> leaves = std::move(collected).value();
    if (leaves.empty()) return Plan{};  // no limit surface, e.g. a boundary face with boundary rule "none"

    Tree tree;
    for (const FarLeaf& leaf : leaves) insertLeaf(tree, leaf);
    for (size_t i = 0; i < tree.nodes.size(); ++i)
        if (!tree.filled[i]) return Error{"OpenSubdiv's patches leave part of a face uncovered"};
    collapseTerminals(tree, 0);

    Plan plan;
    plan.ringSize = mesh.vertexCount;
    plan.maxDepth = mesh.maxDepth;
    std::vector<uint32_t> farPoints;
    flattenTree(tree, plan, farPoints);

    // Order the distinct points by needed level, then by first use.
    const uint32_t farPointCount = stencils.pointCount;
    std::vector<uint32_t> levels = pointLevels(leaves, mesh.maxDepth, farPointCount);
    std::vector<uint32_t> order;
    std::vector<uint32_t> slotOf(farPointCount, UINT32_MAX);
    for (uint32_t p : farPoints)
        if (slotOf[p] == UINT32_MAX) {
            slotOf[p] = 0;
            order.push_back(p);
        }
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return levels[a] < levels[b]; });

    // First the exact tangents of the extraordinary corners (Plan::cornerTangents), then the
    // points in that order.
    const CornerTangents tangents = endCapCornerTangents(**refiner, leaves);
    const uint32_t first = 2 * uint32_t(std::ranges::count_if(tangents, [](const auto& t) { return t.has_value(); }));
    plan.stencilWeights.assign((first + order.size()) * plan.ringSize, 0.0f);
    for (uint32_t c = 0, row = 0; c < 4; ++c) {
        if (!tangents[c]) continue;
        plan.cornerTangents |= 1u << c;
        for (size_t k = 0; k < 2; ++k, ++row)
            for (size_t j = 0; j < tangents[c]->ring.size(); ++j)
                plan.stencilWeights[row * plan.ringSize + uint32_t(tangents[c]->ring[j])] = float(tangents[c]->left[k][j]);
    }
    for (uint32_t n = 0; n <= kMaxPlanDepth; ++n) plan.stencilCountByLevel[n] = first;
    for (uint32_t slot = first; slot < first + order.size(); ++slot) {
        const uint32_t point = order[slot - first];
        slotOf[point] = slot;
        std::ranges::copy(stencils.row(point), plan.stencilWeights.begin() + size_t(slot) * plan.ringSize);
        for (uint32_t n = levels[point]; n <= kMaxPlanDepth; ++n) plan.stencilCountByLevel[n] = slot + 1;
    }
    exactDartCorners(mesh, leaves, tangents, slotOf, plan);
    plan.points.reserve(farPoints.size());
    for (uint32_t p : farPoints) plan.points.push_back(slotOf[p]);
    return plan;
}

}  // namespace qp
