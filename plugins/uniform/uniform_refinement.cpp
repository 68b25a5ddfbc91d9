#include "uniform_refinement.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <opensubdiv/far/topologyRefiner.h>
#include <tbb/parallel_for.h>

#include "mesh/local_cage.h"
#include "plans/osd_refiner.h"

namespace qp {

using namespace OpenSubdiv;

namespace {

using Rule = Sdc::Crease::Rule;

// A vertex mask under construction: (buffer index, weight) pairs.
struct Mask {
    std::vector<std::pair<uint32_t, float>> terms;
    void add(uint32_t index, float weight) {
        for (auto& t : terms)
            if (t.first == index) {
                t.second += weight;
                return;
            }
        terms.push_back({index, weight});
    }
};

struct VertexContext {
    const Far::TopologyLevel& parent;
    const Far::TopologyLevel& child;
    uint32_t parentOffset, childOffset;
    Far::Index vertex;
};

// The other end of edge e at vertex v.
Far::Index otherEnd(const Far::TopologyLevel& level, Far::Index e, Far::Index v) {
    const Far::ConstIndexArray ends = level.GetEdgeVertices(e);
    return ends[0] == v ? ends[1] : ends[0];
}

// Adds `scale` times the mask of `rule` at the vertex; `sharp[i]` says whether its i-th edge
// counts as sharp for the crease rule.
void addRuleMask(const VertexContext& c, Rule rule, const std::vector<bool>& sharp, float scale, Mask& mask) {
    const Far::ConstIndexArray edges = c.parent.GetVertexEdges(c.vertex);
    const Far::ConstIndexArray faces = c.parent.GetVertexFaces(c.vertex);
    const uint32_t self = c.parentOffset + uint32_t(c.vertex);
    if (rule == Sdc::Crease::RULE_SMOOTH || rule == Sdc::Crease::RULE_DART) {
        // Interior: ((n-2)/n) v + (1/n^2) sum of edge neighbours + (1/n^2) sum of face points.
        if (faces.size() != edges.size() || edges.size() < 2) {
            mask.add(self, scale);  // not an interior fan: nothing smooth to do (no surface there)
            return;
        }
        const float n = float(edges.size());
        mask.add(self, scale * (n - 2.0f) / n);
        for (Far::Index e : edges) mask.add(c.parentOffset + uint32_t(otherEnd(c.parent, e, c.vertex)), scale / (n * n));
        for (Far::Index f : faces) mask.add(c.childOffset + uint32_t(c.parent.GetFaceChildVertex(f)), scale / (n * n));
        return;
    }
    if (rule == Sdc::Crease::RULE_CREASE) {
        std::vector<Far::Index> ends;
        for (int i = 0; i < edges.size(); ++i)
            if (sharp[size_t(i)]) ends.push_back(otherEnd(c.parent, edges[i], c.vertex));
        if (ends.size() == 2) {
            mask.add(self, scale * 0.75f);
            mask.add(c.parentOffset + uint32_t(ends[0]), scale * 0.125f);
            mask.add(c.parentOffset + uint32_t(ends[1]), scale * 0.125f);
            return;
        }
    }
    mask.add(self, scale);  // corner (and inconsistent crease data): the vertex stays
}

Mask vertexMask(const VertexContext& c) {
    const Far::ConstIndexArray edges = c.parent.GetVertexEdges(c.vertex);
    const Far::Index childVertex = c.parent.GetVertexChildVertex(c.vertex);
    const Rule parentRule = c.parent.GetVertexRule(c.vertex);
    const Rule childRule = c.child.GetVertexRule(childVertex);
    std::vector<bool> parentSharp(size_t(edges.size())), childSharp(size_t(edges.size()));
    std::vector<float> parentSharpness(size_t(edges.size())), childSharpness(size_t(edges.size()));
    for (int i = 0; i < edges.size(); ++i) {
        const Far::Index e = edges[i];
        const Far::ConstIndexArray childEdges = c.parent.GetEdgeChildEdges(e);
        const Far::Index childEdge = c.parent.GetEdgeVertices(e)[0] == c.vertex ? childEdges[0] : childEdges[1];
        parentSharpness[size_t(i)] = c.parent.GetEdgeSharpness(e);
        childSharpness[size_t(i)] = c.child.GetEdgeSharpness(childEdge);
        parentSharp[size_t(i)] = parentSharpness[size_t(i)] > 0.0f;
        childSharp[size_t(i)] = childSharpness[size_t(i)] > 0.0f;
    }
    Mask mask;
    if (parentRule == Sdc::Crease::RULE_SMOOTH || parentRule == Sdc::Crease::RULE_DART || parentRule == childRule) {
        addRuleMask(c, parentRule, parentSharp, 1.0f, mask);
        return mask;
    }
    // Sharpness runs out at this level: blend the parent's rule with the child's by the
    // average sharpness of what becomes smooth (Sdc::Crease::ComputeFractionalWeightAtVertex).
    float sum = 0.0f;
    uint32_t count = 0;
    const float parentVertexSharpness = c.parent.GetVertexSharpness(c.vertex);
    if (parentVertexSharpness > 0.0f && !(c.child.GetVertexSharpness(childVertex) > 0.0f)) {
        sum += parentVertexSharpness;
        ++count;
    }
    for (size_t i = 0; i < parentSharp.size(); ++i)
        if (parentSharp[i] && !childSharp[i]) {
            sum += parentSharpness[i];
            ++count;
        }
    const float weight = count ? std::min(sum / float(count), 1.0f) : 0.0f;
    addRuleMask(c, parentRule, parentSharp, weight, mask);
    addRuleMask(c, childRule, childSharp, 1.0f - weight, mask);
    return mask;
}

RefinementLevelTables buildTables(const Far::TopologyLevel& parent, const Far::TopologyLevel& child, uint32_t P,
                                  uint32_t C) {
    RefinementLevelTables t;
    t.faceOffsets.push_back(0);
    for (Far::Index f = 0; f < parent.GetNumFaces(); ++f) {
        t.faceChild.push_back(C + uint32_t(parent.GetFaceChildVertex(f)));
        for (Far::Index v : parent.GetFaceVertices(f)) t.faceVertices.push_back(P + uint32_t(v));
        t.faceOffsets.push_back(uint32_t(t.faceVertices.size()));
    }
    for (Far::Index e = 0; e < parent.GetNumEdges(); ++e) {
        const Far::ConstIndexArray ends = parent.GetEdgeVertices(e);
        const Far::ConstIndexArray faces = parent.GetEdgeFaces(e);
        t.edgeChild.push_back(C + uint32_t(parent.GetEdgeChildVertex(e)));
        const uint32_t v0 = P + uint32_t(ends[0]), v1 = P + uint32_t(ends[1]);
        if (faces.size() == 2) {
            t.edgePoints.insert(t.edgePoints.end(), {v0, v1, C + uint32_t(parent.GetFaceChildVertex(faces[0])),
                                                     C + uint32_t(parent.GetFaceChildVertex(faces[1]))});
            t.edgeSharpWeight.push_back(std::clamp(parent.GetEdgeSharpness(e), 0.0f, 1.0f));
        } else {
            // Boundary (and non-manifold) edges: the midpoint, B-spline curve rule (Loop 2010).
            t.edgePoints.insert(t.edgePoints.end(), {v0, v1, v0, v1});
            t.edgeSharpWeight.push_back(0.0f);
        }
    }
    t.vertexOffsets.push_back(0);
    for (Far::Index v = 0; v < parent.GetNumVertices(); ++v) {
        t.vertexChild.push_back(C + uint32_t(parent.GetVertexChildVertex(v)));
        const Mask mask = vertexMask(VertexContext{parent, child, P, C, v});
        for (const auto& [index, weight] : mask.terms) {
            t.vertexIndices.push_back(index);
            t.vertexWeights.push_back(weight);
        }
        const size_t room = 1 + size_t(parent.GetVertexEdges(v).size()) + size_t(parent.GetVertexFaces(v).size());
        for (size_t k = mask.terms.size(); k < room; ++k) {
            t.vertexIndices.push_back(P + uint32_t(v));
            t.vertexWeights.push_back(0.0f);
        }
        t.vertexOffsets.push_back(uint32_t(t.vertexIndices.size()));
    }
    return t;
}

// Where a child face's four vertices sit in the domain. A Catmull-Clark child face of corner j
// of face f has the child of that corner, the children of edges j and j-1 and the face's child
// point. The corner is found through the edge children, which stay distinct where a face
// visits a vertex twice (non-manifold cages). corner < 0: the child face is not of that shape.
struct ChildCorner {
    int corner = -1;
    Far::Index vertex = -1, edgeChild = -1, prevEdgeChild = -1, faceChild = -1;
};

ChildCorner identifyCorner(const Far::TopologyLevel& parent, const Far::TopologyLevel& child, Far::Index f,
                           Far::Index childFace) {
    const Far::ConstIndexArray pe = parent.GetFaceEdges(f), cv = child.GetFaceVertices(childFace);
    const int n = pe.size();
    ChildCorner c;
    if (cv.size() != 4) return c;
    auto has = [&](Far::Index v) { return std::find(cv.begin(), cv.end(), v) != cv.end(); };
    for (int j = 0; j < n && c.corner < 0; ++j) {
        const Far::Index e = parent.GetEdgeChildVertex(pe[j]), ePrev = parent.GetEdgeChildVertex(pe[(j + n - 1) % n]);
        if (e != ePrev && has(e) && has(ePrev)) {
            c.corner = j;
            c.edgeChild = e;
            c.prevEdgeChild = ePrev;
        }
    }
    c.faceChild = parent.GetFaceChildVertex(f);
    if (c.corner < 0 || !has(c.faceChild)) return ChildCorner{};
    for (Far::Index v : cv)
        if (v != c.edgeChild && v != c.prevEdgeChild && v != c.faceChild) c.vertex = v;
    return c;
}

// Gives each of the child face's vertices its domain position by what it is the child of.
bool assignDomain(const Far::ConstIndexArray& cv, const ChildCorner& c, glm::vec2 corner, glm::vec2 edgeMid,
                  glm::vec2 prevMid, glm::vec2 centre, glm::vec2 out[4]) {
    if (c.corner < 0) return false;
    for (int k = 0; k < 4; ++k)
        out[k] = cv[k] == c.faceChild ? centre : cv[k] == c.edgeChild ? edgeMid : cv[k] == c.prevEdgeChild ? prevMid : corner;
    return true;
}

// Child face of a quad whose corners sit at parentDomain[0..3].
bool childDomain(const Far::TopologyLevel& parent, const Far::TopologyLevel& child, Far::Index f,
                 const glm::vec2 parentDomain[4], Far::Index childFace, glm::vec2 out[4]) {
    const ChildCorner c = identifyCorner(parent, child, f, childFace);
    if (c.corner < 0) return false;
    const int j = c.corner;
    const glm::vec2 centre = 0.25f * (parentDomain[0] + parentDomain[1] + parentDomain[2] + parentDomain[3]);
    return assignDomain(child.GetFaceVertices(childFace), c, parentDomain[j], 0.5f * (parentDomain[j] + parentDomain[(j + 1) % 4]),
                        0.5f * (parentDomain[j] + parentDomain[(j + 3) % 4]), centre, out);
}

}  // namespace

Result<UniformRefinement> buildUniformRefinement(const PlannedCage& planned, uint32_t levels) {
    if (levels < 1 || levels > 8) return Error{"uniform: refinement level must be between 1 and 8"};
    const Cage& cage = planned.cage();
    auto created = createRefiner(cage, "uniform");
    if (!created) return created.error();
    Far::TopologyRefiner& r = **created;
    Far::TopologyRefiner::UniformOptions options{int(levels)};
    options.fullTopologyInLastLevel = true;
    r.RefineUniform(options);

    UniformRefinement out;
    out.levels = levels;
    out.levelOffset.push_back(0);
    for (uint32_t l = 0; l <= levels; ++l) out.levelOffset.push_back(out.levelOffset.back() + uint32_t(r.GetLevel(int(l)).GetNumVertices()));
    out.tables.resize(levels);
    tbb::parallel_for(uint32_t(0), levels, [&](uint32_t l) {
        out.tables[l] = buildTables(r.GetLevel(int(l)), r.GetLevel(int(l + 1)), out.levelOffset[l], out.levelOffset[l + 1]);
    });

    // Follow every face down the levels with its sub-face and the domain of its corners.
    struct Tracked {
        uint32_t subface;
        glm::vec2 domain[4];
    };
    std::vector<Tracked> current;        // per face of level 1
    std::vector<bool> known;
    {
        const Far::TopologyLevel& base = r.GetLevel(0);
        const Far::TopologyLevel& next = r.GetLevel(1);
        current.resize(size_t(next.GetNumFaces()));
        known.assign(current.size(), false);
        const glm::vec2 unit[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (Far::Index f = 0; f < base.GetNumFaces(); ++f) {
            const Far::ConstIndexArray children = base.GetFaceChildFaces(f);
            const uint32_t n = uint32_t(base.GetFaceVertices(f).size());
            for (Far::Index c : children) {
                if (c < 0) continue;
                Tracked t;
                if (n == 4) {
                    t.subface = planned.firstSubface(uint32_t(f));
                    if (!childDomain(base, next, f, unit, c, t.domain)) continue;
                } else {
                    // Sub-face k: corners (vertex k, mid edge k, centre, mid edge k-1) -> unit square.
                    const ChildCorner corner = identifyCorner(base, next, f, c);
                    if (corner.corner < 0) continue;
                    t.subface = planned.firstSubface(uint32_t(f)) + uint32_t(corner.corner);
                    if (!assignDomain(next.GetFaceVertices(c), corner, {0, 0}, {1, 0}, {0, 1}, {1, 1}, t.domain)) continue;
                }
                current[size_t(c)] = t;
                known[size_t(c)] = true;
            }
        }
    }
    for (uint32_t l = 1; l < levels; ++l) {
        const Far::TopologyLevel& parent = r.GetLevel(int(l));
        const Far::TopologyLevel& child = r.GetLevel(int(l + 1));
        std::vector<Tracked> next(size_t(child.GetNumFaces()));
        std::vector<bool> nextKnown(next.size(), false);
        for (Far::Index f = 0; f < parent.GetNumFaces(); ++f) {
            if (!known[size_t(f)]) continue;
            for (Far::Index c : parent.GetFaceChildFaces(f)) {
                if (c < 0) continue;
                Tracked t;
                t.subface = current[size_t(f)].subface;
                if (!childDomain(parent, child, f, current[size_t(f)].domain, c, t.domain)) continue;
                next[size_t(c)] = t;
                nextKnown[size_t(c)] = true;
            }
        }
        current = std::move(next);
        known = std::move(nextKnown);
    }

    const Far::TopologyLevel& finest = r.GetLevel(int(levels));
    const uint32_t subfaces = planned.subfaceCount();
    out.subfaceSide.assign(subfaces, 0);
    out.subfaceCellBase.assign(subfaces, 0);
    for (Far::Index f = 0; f < finest.GetNumFaces(); ++f) {
        if (!known[size_t(f)]) continue;
        RefinedQuad q;
        const Far::ConstIndexArray fv = finest.GetFaceVertices(f);
        for (int k = 0; k < 4; ++k) {
            q.vertices[k] = uint32_t(fv[k]);
            q.domain[k] = current[size_t(f)].domain[k];
        }
        q.subface = current[size_t(f)].subface;
        out.quads.push_back(q);
    }
    // Cell grids: a quad sub-face is 2^levels quads wide, an n-gon sub-face 2^(levels-1).
    for (const RefinedQuad& q : out.quads) {
        const float width = glm::length(q.domain[1] - q.domain[0]);
        out.subfaceSide[q.subface] = uint32_t(std::lround(1.0f / width));
    }
    uint32_t cells = 0;
    for (uint32_t s = 0; s < subfaces; ++s) {
        out.subfaceCellBase[s] = cells;
        cells += out.subfaceSide[s] * out.subfaceSide[s];
    }
    out.cellQuad.assign(cells, UINT32_MAX);
    for (uint32_t i = 0; i < out.quads.size(); ++i) {
        const RefinedQuad& q = out.quads[i];
        const uint32_t side = out.subfaceSide[q.subface];
        glm::vec2 lo = glm::min(glm::min(q.domain[0], q.domain[1]), glm::min(q.domain[2], q.domain[3]));
        const uint32_t x = std::min(side - 1, uint32_t(lo.x * float(side) + 0.5f));
        const uint32_t y = std::min(side - 1, uint32_t(lo.y * float(side) + 0.5f));
        out.cellQuad[out.subfaceCellBase[q.subface] + y * side + x] = i;
        if (planned.hasSurface(q.subface)) out.drawnQuads.push_back(i);
    }
    out.refiner = std::move(*created);
    return out;
}

void applyUniformRefinement(const UniformRefinement& refinement, std::span<const glm::vec3> cagePositions,
                            std::vector<glm::vec3>& buffer) {
    buffer.resize(refinement.levelOffset.back());
    std::copy(cagePositions.begin(), cagePositions.end(), buffer.begin());
    for (const RefinementLevelTables& t : refinement.tables) {
        // Face points, then edge points (which read the new face points), then vertex points.
        tbb::parallel_for(size_t(0), t.faceChild.size(), [&](size_t f) {
            glm::vec3 sum(0.0f);
            for (uint32_t k = t.faceOffsets[f]; k < t.faceOffsets[f + 1]; ++k) sum += buffer[t.faceVertices[k]];
            buffer[t.faceChild[f]] = sum / float(t.faceOffsets[f + 1] - t.faceOffsets[f]);
        });
        tbb::parallel_for(size_t(0), t.edgeChild.size(), [&](size_t e) {
            const uint32_t* p = &t.edgePoints[4 * e];
            const glm::vec3 smooth = 0.25f * (buffer[p[0]] + buffer[p[1]] + buffer[p[2]] + buffer[p[3]]);
            const glm::vec3 sharp = 0.5f * (buffer[p[0]] + buffer[p[1]]);
            const float w = t.edgeSharpWeight[e];
            buffer[t.edgeChild[e]] = w > 0.0f ? (1.0f - w) * smooth + w * sharp : smooth;
        });
        tbb::parallel_for(size_t(0), t.vertexChild.size(), [&](size_t v) {
            glm::vec3 sum(0.0f);
            for (uint32_t k = t.vertexOffsets[v]; k < t.vertexOffsets[v + 1]; ++k)
                sum += t.vertexWeights[k] * buffer[t.vertexIndices[k]];
            buffer[t.vertexChild[v]] = sum;
        });
    }
}

std::vector<glm::vec3> refinedNormals(const UniformRefinement& refinement, std::span<const glm::vec3> finest) {
    std::vector<glm::vec3> normals(finest.size(), glm::vec3(0.0f));
    for (uint32_t i : refinement.drawnQuads) {
        const RefinedQuad& q = refinement.quads[i];
        const glm::vec3* p[4] = {&finest[q.vertices[0]], &finest[q.vertices[1]], &finest[q.vertices[2]], &finest[q.vertices[3]]};
        const glm::vec3 n = glm::cross(*p[2] - *p[0], *p[3] - *p[1]);  // twice the area, along the normal
        for (uint32_t v : q.vertices) normals[v] += n;
    }
    for (glm::vec3& n : normals) {
        const float length = glm::length(n);
        n = length > 0.0f ? n / length : glm::vec3(0.0f);
    }
    return normals;
}

RefinedSample sampleRefined(const UniformRefinement& refinement, std::span<const glm::vec3> finest,
                            std::span<const glm::vec3> normals, uint32_t subface, float u, float v) {
    const uint32_t side = refinement.subfaceSide[subface];
    const uint32_t x = std::min(side - 1, uint32_t(std::max(0.0f, u) * float(side)));
    const uint32_t y = std::min(side - 1, uint32_t(std::max(0.0f, v) * float(side)));
    const uint32_t quad = refinement.cellQuad[refinement.subfaceCellBase[subface] + y * side + x];
    RefinedSample out{};
    if (quad == UINT32_MAX) return out;
    const RefinedQuad& q = refinement.quads[quad];
    // The quad's own coordinates (s, t) along its edges 0->1 and 0->3.
    const glm::vec2 e1 = q.domain[1] - q.domain[0], e3 = q.domain[3] - q.domain[0], d = glm::vec2(u, v) - q.domain[0];
    const float s = std::clamp(glm::dot(d, e1) / glm::dot(e1, e1), 0.0f, 1.0f);
    const float t = std::clamp(glm::dot(d, e3) / glm::dot(e3, e3), 0.0f, 1.0f);
    const glm::vec3 &p0 = finest[q.vertices[0]], &p1 = finest[q.vertices[1]], &p2 = finest[q.vertices[2]], &p3 = finest[q.vertices[3]];
    const glm::vec3 &n0 = normals[q.vertices[0]], &n1 = normals[q.vertices[1]], &n2 = normals[q.vertices[2]], &n3 = normals[q.vertices[3]];
    glm::vec3 ds, dt, normal;
    if (s >= t) {  // triangle (0, 1, 2)
        ds = p1 - p0;
        dt = p2 - p1;
        normal = n0 + s * (n1 - n0) + t * (n2 - n1);
    } else {       // triangle (0, 2, 3)
        ds = p2 - p3;
        dt = p3 - p0;
        normal = n0 + s * (n2 - n3) + t * (n3 - n0);
    }
    out.position = p0 + s * ds + t * dt;
    const float length = glm::length(normal);
    out.normal = length > 0.0f ? normal / length : glm::vec3(0.0f);
    // Chain rule from (s, t) to the sub-face's (u, v).
    out.du = ds * (e1.x / glm::dot(e1, e1)) + dt * (e3.x / glm::dot(e3, e3));
    out.dv = ds * (e1.y / glm::dot(e1, e1)) + dt * (e3.y / glm::dot(e3, e3));
    return out;
}

namespace {

void sortUnique(std::vector<uint32_t>& list) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
}

// Per level, local component -> the same component of the whole refinement.
struct ComponentMap {
    std::vector<Far::Index> vertex, edge, face;
    std::vector<char> vertexMarked, edgeMarked, faceMarked;  // descends from the re-planned faces
};

Status mapEdges(const Far::TopologyLevel& local, const Far::TopologyLevel& global, ComponentMap& map) {
    map.edge.resize(size_t(local.GetNumEdges()));
    for (Far::Index e = 0; e < local.GetNumEdges(); ++e) {
        const Far::ConstIndexArray ends = local.GetEdgeVertices(e);
        map.edge[size_t(e)] = global.FindEdge(map.vertex[size_t(ends[0])], map.vertex[size_t(ends[1])]);
        if (map.edge[size_t(e)] == Far::INDEX_INVALID) return Error{"uniform: a local edge has no match"};
    }
    return success();
}

}  // namespace

Status updateUniformTags(UniformRefinement& out, const PlannedCage& planned, std::span<const uint32_t> subfaces) {
    if (!out.refiner) return Error{"uniform: no refinement to update"};
    const Cage& cage = planned.cage();
    const Topology& topology = planned.topology();
    std::vector<uint32_t> region;  // faces of the re-planned sub-faces
    for (uint32_t s : subfaces) {
        uint32_t lo = 0, hi = cage.faceCount();
        while (hi - lo > 1) {
            const uint32_t mid = (lo + hi) / 2;
            (planned.firstSubface(mid) <= s ? lo : hi) = mid;
        }
        region.push_back(lo);
    }
    sortUnique(region);
    std::vector<uint32_t> around;  // every face at a vertex of the region: all the masks read
    for (uint32_t f : region)
        for (uint32_t i = 0; i < cage.faceSize(f); ++i) {
            const uint32_t v = cage.faceBegin(f)[i];
            for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k)
                around.push_back(topology.vertexFaces[k]);
        }
    sortUnique(around);

    if (around.size() == cage.faceCount()) {  // an options change, or a small cage: all of it anew
        Result<UniformRefinement> fresh = buildUniformRefinement(planned, out.levels);
        if (!fresh) return fresh.error();
        out = std::move(*fresh);
        return success();
    }
    if (!region.empty()) {
        const LocalCage local = localCage(cage, around);
        auto created = createRefiner(local.cage, "uniform (local)");
        if (!created) return created.error();
        Far::TopologyRefiner& r = **created;
        Far::TopologyRefiner::UniformOptions options{int(out.levels)};
        options.fullTopologyInLastLevel = true;
        r.RefineUniform(options);
        const Far::TopologyRefiner& whole = *out.refiner;

        // Level 0 by construction; the region's faces, edges and vertices are marked.
        ComponentMap map;
        const Far::TopologyLevel& base = r.GetLevel(0);
        map.vertex.assign(local.globalVertex.begin(), local.globalVertex.end());
        map.face.assign(around.begin(), around.end());
        if (Status s = mapEdges(base, whole.GetLevel(0), map); !s) return s;
        map.vertexMarked.assign(size_t(base.GetNumVertices()), 0);
        map.edgeMarked.assign(size_t(base.GetNumEdges()), 0);
        map.faceMarked.assign(size_t(base.GetNumFaces()), 0);
        for (Far::Index f = 0; f < base.GetNumFaces(); ++f) {
            if (!std::binary_search(region.begin(), region.end(), around[size_t(f)])) continue;
            map.faceMarked[size_t(f)] = 1;
            for (Far::Index v : base.GetFaceVertices(f)) map.vertexMarked[size_t(v)] = 1;
            for (Far::Index e : base.GetFaceEdges(f)) map.edgeMarked[size_t(e)] = 1;
        }

        // Level by level: the local tables, written where they are marked (once all levels
        // matched), then the children mapped.
        struct Write {
            uint32_t level;
            bool edge;       // edgeSharpWeight[at] = weight; else mask term `at` = (index, weight)
            uint32_t at;
            float weight;
            uint32_t index = 0;
        };
        std::vector<Write> writes;
        uint32_t localOffset = 0;
        for (uint32_t l = 0; l < out.levels; ++l) {
            const Far::TopologyLevel &parent = r.GetLevel(int(l)), &child = r.GetLevel(int(l + 1));
            const Far::TopologyLevel &wholeParent = whole.GetLevel(int(l)), &wholeChild = whole.GetLevel(int(l + 1));
            const uint32_t localChildOffset = localOffset + uint32_t(parent.GetNumVertices());
            const RefinementLevelTables lt = buildTables(parent, child, localOffset, localChildOffset);

            ComponentMap next;
            next.vertex.assign(size_t(child.GetNumVertices()), Far::INDEX_INVALID);
            next.face.assign(size_t(child.GetNumFaces()), Far::INDEX_INVALID);
            next.vertexMarked.assign(next.vertex.size(), 0);
            next.faceMarked.assign(next.face.size(), 0);
            std::vector<char> childEdgeMarked(size_t(child.GetNumEdges()), 0);
            for (Far::Index f = 0; f < parent.GetNumFaces(); ++f) {
                const Far::Index g = map.face[size_t(f)];
                next.vertex[size_t(parent.GetFaceChildVertex(f))] = wholeParent.GetFaceChildVertex(g);
                const Far::ConstIndexArray mine = parent.GetFaceChildFaces(f), theirs = wholeParent.GetFaceChildFaces(g);
                if (mine.size() != theirs.size()) return Error{"uniform: a local face refines differently"};
                for (int k = 0; k < mine.size(); ++k) next.face[size_t(mine[k])] = theirs[k];
                if (!map.faceMarked[size_t(f)]) continue;
                next.vertexMarked[size_t(parent.GetFaceChildVertex(f))] = 1;
                for (Far::Index c : mine) next.faceMarked[size_t(c)] = 1;
                for (Far::Index c : parent.GetFaceChildEdges(f)) childEdgeMarked[size_t(c)] = 1;
            }
            for (Far::Index e = 0; e < parent.GetNumEdges(); ++e) {
                next.vertex[size_t(parent.GetEdgeChildVertex(e))] = wholeParent.GetEdgeChildVertex(map.edge[size_t(e)]);
                if (!map.edgeMarked[size_t(e)]) continue;
                next.vertexMarked[size_t(parent.GetEdgeChildVertex(e))] = 1;
                for (Far::Index c : parent.GetEdgeChildEdges(e)) childEdgeMarked[size_t(c)] = 1;
            }
            for (Far::Index v = 0; v < parent.GetNumVertices(); ++v) {
                next.vertex[size_t(parent.GetVertexChildVertex(v))] = wholeParent.GetVertexChildVertex(map.vertex[size_t(v)]);
                if (map.vertexMarked[size_t(v)]) next.vertexMarked[size_t(parent.GetVertexChildVertex(v))] = 1;
            }
            if (Status s = mapEdges(child, wholeChild, next); !s) return s;
            next.edgeMarked = std::move(childEdgeMarked);

            // Local buffer index -> the whole refinement's (parent vertices, then child face points).
            const uint32_t P = out.levelOffset[l], C = out.levelOffset[l + 1];
            auto translate = [&](uint32_t index) {
                return index < localChildOffset ? P + uint32_t(map.vertex[index - localOffset])
                                                : C + uint32_t(next.vertex[index - localChildOffset]);
            };
            const RefinementLevelTables& t = out.tables[l];
            for (Far::Index e = 0; e < parent.GetNumEdges(); ++e)
                if (map.edgeMarked[size_t(e)])
                    writes.push_back({l, true, uint32_t(map.edge[size_t(e)]), lt.edgeSharpWeight[size_t(e)]});
            for (Far::Index v = 0; v < parent.GetNumVertices(); ++v) {
                if (!map.vertexMarked[size_t(v)]) continue;
                const uint32_t g = uint32_t(map.vertex[size_t(v)]);
                const uint32_t begin = t.vertexOffsets[g], room = t.vertexOffsets[g + 1] - begin;
                const uint32_t localBegin = lt.vertexOffsets[size_t(v)], terms = lt.vertexOffsets[size_t(v) + 1] - localBegin;
                if (terms != room) return Error{"uniform: a local vertex has another valence"};
                for (uint32_t k = 0; k < terms; ++k)
                    writes.push_back({l, false, begin + k, lt.vertexWeights[localBegin + k], translate(lt.vertexIndices[localBegin + k])});
            }
            map = std::move(next);
            localOffset = localChildOffset;
        }
        for (const Write& w : writes) {
            RefinementLevelTables& t = out.tables[w.level];
            if (w.edge) {
                t.edgeSharpWeight[w.at] = w.weight;
            } else {
                t.vertexIndices[w.at] = w.index;
                t.vertexWeights[w.at] = w.weight;
            }
        }
    }

    out.drawnQuads.clear();
    for (uint32_t i = 0; i < out.quads.size(); ++i)
        if (planned.hasSurface(out.quads[i].subface)) out.drawnQuads.push_back(i);
    return success();
}

}  // namespace qp
