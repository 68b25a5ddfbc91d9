// Cage picking (vertices, edges, faces), visibility and box selection. The limit-surface
// picker is in limit_picker.cpp.
#include "edit/picking.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

glm::vec3 unproject(const glm::mat4& inverse, float x, float y, float z) {
    glm::vec4 p = inverse * glm::vec4(x, y, z, 1.0f);
    return glm::vec3(p) / p.w;
}

float distanceToSegment(const glm::vec2& p, const glm::vec2& a, const glm::vec2& b) {
    const glm::vec2 ab = b - a;
    const float length2 = glm::dot(ab, ab);
    const float s = length2 > 0.0f ? std::clamp(glm::dot(p - a, ab) / length2, 0.0f, 1.0f) : 0.0f;
    return glm::length(p - (a + s * ab));
}

// Parameter along a -> b of the segment point nearest the line (origin, direction).
float closestOnSegmentToRay(const glm::vec3& a, const glm::vec3& b, const Ray& ray) {
    const glm::vec3 u = b - a, w = a - ray.origin;
    const float uu = glm::dot(u, u), ud = glm::dot(u, ray.direction), uw = glm::dot(u, w), dw = glm::dot(ray.direction, w);
    const float denominator = uu - ud * ud;  // |direction| = 1
    if (!(denominator > 1e-12f * uu)) return 0.5f;  // parallel to the ray
    return std::clamp((ud * dw - uw) / denominator, 0.0f, 1.0f);
}

// Clip-space point to pixel.
glm::vec2 toPixel(const glm::vec4& clip, const glm::vec2& size) {
    return (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * size;
}

// The elements i < count for which accepts(i), in increasing order, tested on every core (a
// flag each, so the order does not depend on the threads).
template <typename Accepts>
std::vector<uint32_t> elementsWhere(uint32_t count, const Accepts& accepts) {
    std::vector<uint8_t> flags(count);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 256), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t i = range.begin(); i < range.end(); ++i) flags[i] = accepts(i);
    });
    std::vector<uint32_t> list;
    for (uint32_t i = 0; i < count; ++i)
        if (flags[i]) list.push_back(i);
    return list;
}

// An edge's projection from its ends' clip coordinates, clipped against the near plane (clip
// z >= 0, Vulkan depth); false when nothing of it is in front.
bool projectEdge(const PickView& view, glm::vec4 ca, glm::vec4 cb, glm::vec2& pa, glm::vec2& pb) {
    if (ca.z < 0.0f && cb.z < 0.0f) return false;
    if (ca.z < 0.0f) ca = ca + (cb - ca) * (ca.z / (ca.z - cb.z));
    if (cb.z < 0.0f) cb = cb + (ca - cb) * (cb.z / (cb.z - ca.z));
    if (ca.w <= 0.0f || cb.w <= 0.0f) return false;
    pa = toPixel(ca, view.size), pb = toPixel(cb, view.size);
    return true;
}

}  // namespace

Ray PickView::rayThrough(const glm::vec2& pixel) const {
    const glm::mat4 inverse = glm::inverse(viewProjection);
    const float x = pixel.x / size.x * 2.0f - 1.0f, y = pixel.y / size.y * 2.0f - 1.0f;
    const glm::vec3 near = unproject(inverse, x, y, 0.0f), far = unproject(inverse, x, y, 1.0f);
    return {near, glm::normalize(far - near)};
}

PickView::Projected PickView::project(const glm::vec3& point) const {
    const glm::vec4 clip = viewProjection * glm::vec4(point, 1.0f);
    Projected p;
    p.inFront = clip.w > 0.0f && clip.z >= 0.0f;
    if (clip.w != 0.0f) {
        p.pixel = toPixel(clip, size);
        p.depth = clip.z / clip.w;
    }
    return p;
}

CageRaycaster::CageRaycaster(const Cage& cage) {
    std::vector<Box> boxes(cage.faceCount());
    fanOffsets_.reserve(cage.faceCount() + 1);
    fanOffsets_.push_back(0);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        glm::vec3 centre(0.0f);
        for (uint32_t i = 0; i < cage.faceSize(f); ++i) centre += cage.positions[cage.faceBegin(f)[i]];
        centre /= float(cage.faceSize(f));
        fanPoints_.push_back(centre);
        for (uint32_t i = 0; i < cage.faceSize(f); ++i) fanPoints_.push_back(cage.positions[cage.faceBegin(f)[i]]);
        fanOffsets_.push_back(uint32_t(fanPoints_.size()));
        for (uint32_t i = fanOffsets_[f]; i < fanOffsets_[f + 1]; ++i) boxes[f].add(fanPoints_[i]);
    }
    bvh_ = BoxBvh(boxes);
}

CageRaycaster::Hit CageRaycaster::intersect(const Ray& ray, float maxDistance) const {
    Hit hit;
    bvh_.traverse(ray.origin, ray.direction, maxDistance, [&](uint32_t f, float tMax) {
        const glm::vec3* fan = fanPoints_.data() + fanOffsets_[f];
        const uint32_t n = fanOffsets_[f + 1] - fanOffsets_[f] - 1;
        for (uint32_t i = 0; i < n; ++i) {
            float t, b1, b2;
            if (rayHitsTriangle(ray.origin, ray.direction, fan[0], fan[1 + i], fan[1 + (i + 1) % n], t, b1, b2) && t < tMax) {
                tMax = t;
                hit = {f, t, ray.origin + t * ray.direction};
            }
        }
        return tMax;
    });
    return hit;
}

Occluder cageOccluder(const CageRaycaster& raycaster, float tolerance) {
    return {[&raycaster, tolerance](const Ray& ray, float distance) {
        return raycaster.intersect(ray, distance - tolerance).face != kNoHit;
    }};
}

Occluder limitOccluder(const LimitPicker& picker, const PlannedCage& planned, float tolerance) {
    return {[&picker, &planned, tolerance](const Ray& ray, float distance) {
        return picker.hides(planned, ray, distance - tolerance);
    }};
}

bool isVisible(const PickView& view, const glm::vec3& point, const Occluder* occluder) {
    const PickView::Projected p = view.project(point);
    if (!p.inFront) return false;
    if (!occluder) return true;
    const Ray ray = view.rayThrough(p.pixel);
    const float along = glm::dot(point - ray.origin, ray.direction);
    return !occluder->hides(ray, along);
}

VertexPick pickVertex(const Cage& cage, const PickView& view, const glm::vec2& pixel, float tolerancePixels,
                      const Occluder* occluder) {
    // The vertices within the tolerance are found on every core (a million-face cage's
    // vertices took 29 ms on one); the choice among them runs in vertex order, as the ties want.
    auto within = [&](uint32_t v) {
        const PickView::Projected p = view.project(cage.positions[v]);
        return p.inFront && glm::length(p.pixel - pixel) <= tolerancePixels;
    };
    VertexPick best;
    for (uint32_t v : elementsWhere(cage.vertexCount(), within)) {
        const PickView::Projected p = view.project(cage.positions[v]);
        const float d = glm::length(p.pixel - pixel);
        const bool better = best.vertex == kNoHit || d < best.pixelDistance - 0.5f ||
                            (d <= best.pixelDistance + 0.5f && p.depth < best.depth);
        if (!better || !isVisible(view, cage.positions[v], occluder)) continue;
        best = {v, d, p.depth};
    }
    return best;
}

EdgePick pickEdge(const Cage& cage, const Topology& topology, const PickView& view, const glm::vec2& pixel,
                  float tolerancePixels, const Occluder* occluder) {
    // As for vertices: every vertex projected once, the edges within the tolerance found on
    // every core (a million faces' two million edges took 86 ms on one, projecting each end
    // again), then the choice among them in edge order.
    std::vector<glm::vec4> clip(cage.vertexCount());
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, cage.vertexCount(), 1024),
                      [&](const tbb::blocked_range<uint32_t>& range) {
                          for (uint32_t v = range.begin(); v < range.end(); ++v)
                              clip[v] = view.viewProjection * glm::vec4(cage.positions[v], 1.0f);
                      });
    auto project = [&](uint32_t e, glm::vec2& pa, glm::vec2& pb) {
        return projectEdge(view, clip[topology.edgeVertices[2 * e]], clip[topology.edgeVertices[2 * e + 1]], pa, pb);
    };
    auto within = [&](uint32_t e) {
        glm::vec2 pa, pb;
        return project(e, pa, pb) && distanceToSegment(pixel, pa, pb) <= tolerancePixels;
    };
    EdgePick best;
    float bestDepth = 0.0f;
    const Ray ray = view.rayThrough(pixel);
    for (uint32_t e : elementsWhere(topology.edgeCount(), within)) {
        const glm::vec3 a = cage.positions[topology.edgeVertices[2 * e]], b = cage.positions[topology.edgeVertices[2 * e + 1]];
        glm::vec2 pa(0.0f), pb(0.0f);
        project(e, pa, pb);
        const float d = distanceToSegment(pixel, pa, pb);
        const float t = closestOnSegmentToRay(a, b, ray);
        const glm::vec3 point = a + t * (b - a);
        const float depth = view.project(point).depth;
        const bool better = !best.hit || d < best.pixelDistance - 0.5f || (d <= best.pixelDistance + 0.5f && depth < bestDepth);
        if (!better || !isVisible(view, point, occluder)) continue;
        best = {{topology.edgeVertices[2 * e], topology.edgeVertices[2 * e + 1]}, true, d, t};
        bestDepth = depth;
    }
    return best;
}

CageRaycaster::Hit pickFace(const CageRaycaster& raycaster, const PickView& view, const glm::vec2& pixel) {
    return raycaster.intersect(view.rayThrough(pixel));
}

Selection boxSelect(const Cage& cage, const Topology& topology, SelectionMode mode, const PickView& view,
                    const glm::vec2& cornerA, const glm::vec2& cornerB, const Occluder* occluder) {
    const glm::vec2 lo = glm::min(cornerA, cornerB), hi = glm::max(cornerA, cornerB);
    auto inside = [&](const glm::vec3& p) {
        const PickView::Projected q = view.project(p);
        return q.inFront && q.pixel.x >= lo.x && q.pixel.x <= hi.x && q.pixel.y >= lo.y && q.pixel.y <= hi.y;
    };
    // Element i is taken when it is inside and `visibleAt(i)` is: the visibility rays (most of
    // the time) run on every core and the result keeps element order.
    auto taken = [&](uint32_t count, auto&& isInside, auto&& visibleAt) {
        return elementsWhere(count, [&](uint32_t i) { return isInside(i) && visibleAt(i); });
    };
    Selection s;
    s.mode = mode;
    switch (mode) {
    case SelectionMode::Vertex:
        s.vertices = taken(
            cage.vertexCount(), [&](uint32_t v) { return inside(cage.positions[v]); },
            [&](uint32_t v) { return isVisible(view, cage.positions[v], occluder); });
        break;
    case SelectionMode::Edge: {
        auto end = [&](uint32_t e, int side) { return cage.positions[topology.edgeVertices[2 * e + side]]; };
        for (uint32_t e : taken(
                 topology.edgeCount(), [&](uint32_t e) { return inside(end(e, 0)) && inside(end(e, 1)); },
                 [&](uint32_t e) { return isVisible(view, 0.5f * (end(e, 0) + end(e, 1)), occluder); }))
            s.edges.push_back({topology.edgeVertices[2 * e], topology.edgeVertices[2 * e + 1]});
        std::sort(s.edges.begin(), s.edges.end());
        break;
    }
    case SelectionMode::Face: {
        auto centre = [&](uint32_t f) {
            glm::vec3 sum(0.0f);
            for (uint32_t i = 0; i < cage.faceSize(f); ++i) sum += cage.positions[cage.faceBegin(f)[i]];
            return sum / float(cage.faceSize(f));
        };
        s.faces = taken(
            cage.faceCount(), [&](uint32_t f) { return inside(centre(f)); },
            [&](uint32_t f) { return isVisible(view, centre(f), occluder); });
        break;
    }
    }
    return s;
}

}  // namespace qp
