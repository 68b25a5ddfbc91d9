// DisplacedPicker: ray picking on the displaced limit surface (see displaced_picker.h).
#include "displacement/displaced_picker.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>
#include <tbb/parallel_for.h>

#include "displacement/sculpt_samples.h"
#include "edit/grid_hit.h"

namespace qp {

namespace {

// Whether the displacement has this sub-face (a layout of another cage, met only if a caller
// breaks the contract, reads as no displacement rather than out of bounds).
bool covers(const Displacement& displacement, uint32_t subface) {
    return !displacement.empty() && subface < displacement.layout.tiles.size();
}

DisplacementValue displacementAt(const Displacement& displacement, uint32_t subface, float u, float v) {
    if (!covers(displacement, subface)) return {};
    return evaluateDisplacement(displacement, subface, u, v);
}

std::vector<uint32_t> everySubface(const PlannedCage& planned) {
    std::vector<uint32_t> all(planned.subfaceCount());
    std::iota(all.begin(), all.end(), 0u);
    return all;
}

}  // namespace

DisplacedPoint displacedSurfacePoint(const PlannedCage& planned, const Displacement& displacement, uint32_t subface,
                                     float u, float v) {
    const LimitSample s = planned.evaluate(subface, u, v);
    const glm::vec3 normal = limitNormal(planned, subface, u, v, s);
    return displacePoint(s.position, s.du, s.dv, normal, displacementAt(displacement, subface, u, v));
}

DisplacedPicker::DisplacedPicker(const PlannedCage& planned, const Displacement& displacement, uint32_t minResolution)
    : DisplacedPicker(planned, displacement, everySubface(planned), minResolution) {}

DisplacedPicker::DisplacedPicker(const PlannedCage& planned, const Displacement& displacement,
                                 std::span<const uint32_t> subfaces, uint32_t minResolution)
    : minResolution_(std::clamp(minResolution, 1u, kMaxPickResolution)) {
    grids_.assign(planned.subfaceCount(), {});
    boxes_.assign(planned.subfaceCount(), Box{});
    if (!displacement.empty()) users_ = buildDisplacementUsers(displacement.layout);
    resample(planned, displacement, subfaces, true);
}

uint32_t DisplacedPicker::wantedResolution(const Displacement& displacement, uint32_t subface) const {
    const uint32_t tile = covers(displacement, subface) ? displacement.layout.tiles[subface].cells : 1u;
    return std::clamp(tile, minResolution_, kMaxPickResolution);
}

void DisplacedPicker::sampleLimit(const PlannedCage& planned, const Displacement& displacement, uint32_t subface) {
    Grid& g = grids_[subface];
    if (!planned.hasSurface(subface)) {
        g = Grid{};
        return;
    }
    g.n = wantedResolution(displacement, subface);
    const uint32_t n = g.n, count = (n + 1) * (n + 1);
    g.limit.resize(count);
    g.normal.resize(count);
    g.displaced.resize(count);
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            const float u = float(i) / float(n), v = float(j) / float(n);
            const LimitSample s = planned.evaluate(subface, u, v);
            g.limit[j * (n + 1) + i] = s.position;
            g.normal[j * (n + 1) + i] = limitNormal(planned, subface, u, v, s);
        }
}

void DisplacedPicker::displace(const Displacement& displacement, uint32_t subface) {
    Grid& g = grids_[subface];
    Box& box = boxes_[subface];
    box = Box{};
    if (g.n == 0) return;
    const uint32_t n = g.n;
    if (!covers(displacement, subface)) {
        g.displaced = g.limit;
    } else {
        const SubfaceDisplacement d(displacement, subface);
        for (uint32_t j = 0; j <= n; ++j)
            for (uint32_t i = 0; i <= n; ++i) {
                const uint32_t k = j * (n + 1) + i;
                g.displaced[k] = g.limit[k] + d.evaluate(float(i) / float(n), float(j) / float(n)).value * g.normal[k];
            }
    }
    for (const glm::vec3& p : g.displaced) box.add(p);
    growForRounding(box);
}

void DisplacedPicker::resample(const PlannedCage& planned, const Displacement& displacement,
                               std::span<const uint32_t> subfaces, bool limitToo) {
    tbb::parallel_for(size_t(0), subfaces.size(), [&](size_t k) {
        const uint32_t s = subfaces[k];
        // A tile whose resolution changed needs a grid of its own size: evaluate the limit again.
        if (limitToo || (grids_[s].n != 0 && grids_[s].n != wantedResolution(displacement, s)))
            sampleLimit(planned, displacement, s);
        displace(displacement, s);
    });
    lastUpdated_.assign(subfaces.begin(), subfaces.end());
    bvh_ = BoxBvh(boxes_);
}

void DisplacedPicker::updateSubfaces(const PlannedCage& planned, const Displacement& displacement,
                                     std::span<const uint32_t> subfaces) {
    resample(planned, displacement, subfaces, true);
}

void DisplacedPicker::updateSamples(const PlannedCage& planned, const Displacement& displacement,
                                    std::span<const uint32_t> samples) {
    if (displacement.empty() || users_.offsets.empty()) {  // no layout to map samples through
        lastUpdated_.clear();
        return;
    }
    const std::vector<uint32_t> subfaces = subfacesReadingSamples(displacement.layout, users_, samples);
    resample(planned, displacement, subfaces, false);
}

DisplacedPicker::Hit DisplacedPicker::triangleHit(const Ray& ray, float maxDistance) const {
    Hit hit;
    const RayFrame frame(ray.origin, ray.direction);
    thread_local std::vector<glm::vec3> scratchOfThread;
    std::vector<glm::vec3>& scratch = scratchOfThread;
    bvh_.traverse(ray.origin, ray.direction, maxDistance, [&](uint32_t s, float tMax) {
        const Grid& grid = grids_[s];
        const GridHit g = nearestGridHit(frame, grid.displaced.data(), grid.n, CellRange::all(grid.n), tMax, scratch);
        if (!g.hit()) return tMax;
        hit.subface = s;
        hit.u = g.u;
        hit.v = g.v;
        hit.distance = g.distance;
        return g.distance;
    });
    return hit;
}

// Newton on f(u, v) = origin + t direction, unknowns (u, v, t), Jacobian (f_u, f_v, -direction)
// with Blinn's f_u ~ s_u + D_u N. The approximate Jacobian converges linearly (by about D kappa
// per step) rather than quadratically, hence more iterations than LimitPicker's. Returns
// whether it converged inside the sub-face, near the triangle hit (then `hit` is updated).
namespace {

struct NewtonPoint {
    LimitSample s;
    glm::vec3 normal;
    DisplacementValue d;
    DisplacedPoint f;
    glm::vec3 residual;
};

// Newton stays a hair inside the sub-face: ON an edge, D is the edge function with its
// parameter snapped to 2^-14 (displacement.h: bit-identical seams), a staircase that a steep
// displacement turns into residuals of 1e-4 that no step can remove.
constexpr float kInset = 1e-6f;

NewtonPoint newtonPoint(const PlannedCage& planned, const Displacement& displacement, const Ray& ray, uint32_t subface,
                        float u, float v, float t) {
    NewtonPoint p;
    u = std::clamp(u, kInset, 1.0f - kInset);
    v = std::clamp(v, kInset, 1.0f - kInset);
    p.s = planned.evaluate(subface, u, v);
    p.normal = limitNormal(planned, subface, u, v, p.s);
    p.d = displacementAt(displacement, subface, u, v);
    p.f = displacePoint(p.s.position, p.s.du, p.s.dv, p.normal, p.d);
    p.residual = p.f.position - (ray.origin + t * ray.direction);
    return p;
}

}  // namespace

bool DisplacedPicker::newton(const PlannedCage& planned, const Displacement& displacement, const Ray& ray,
                             uint32_t subface, glm::vec2 uv, Hit& hit) const {
    const Box& box = boxes_[subface];
    const float scale = std::max(glm::length(box.max - box.min), 1e-6f);
    const glm::vec3 triangle = ray.origin + hit.distance * ray.direction;
    const float tolerance = 2e-6f * std::max(scale, glm::length(triangle));
    float u = uv.x, v = uv.y, t = hit.distance;
    NewtonPoint p = newtonPoint(planned, displacement, ray, subface, u, v, t);
    for (int iteration = 0; iteration < 32; ++iteration) {
        if (glm::length(p.residual) <= tolerance) {
            if (!(std::fabs(t - hit.distance) < 0.25f * scale)) return false;
            hit = Hit{subface, std::clamp(u, kInset, 1.0f - kInset), std::clamp(v, kInset, 1.0f - kInset), p.f.position, p.f.normal,
                      p.s.position, t, true};
            return true;
        }
        const glm::mat3 jacobian(p.s.du + p.d.du * p.normal, p.s.dv + p.d.dv * p.normal, -ray.direction);
        if (!(std::fabs(glm::determinant(jacobian)) > 1e-20f)) return false;
        const glm::vec3 step = glm::inverse(jacobian) * (-p.residual);
        // Steps from far off can overshoot where D curves (its second derivatives jump at cell
        // lines). Halving the step until the residual shrinks keeps it converging.
        float lambda = 1.0f;
        NewtonPoint next;
        for (int halving = 0; halving < 8; ++halving, lambda *= 0.5f) {
            next = newtonPoint(planned, displacement, ray, subface, u + lambda * step.x, v + lambda * step.y,
                               t + lambda * step.z);
            if (glm::length(next.residual) < glm::length(p.residual)) break;
        }
        u += lambda * step.x;
        v += lambda * step.y;
        t += lambda * step.z;
        p = next;
        if (u < -1e-3f || u > 1.001f || v < -1e-3f || v > 1.001f || !std::isfinite(t)) return false;  // left the sub-face
    }
    return false;
}

// The sampled triangles err most where tall displacement meets a grazing ray, so the exact
// crossing may lie across a sub-face edge from the triangle hit, where Newton on the hit's
// sub-face leaves it. Then each other sub-face whose box holds the triangle hit is tried, from
// its grid point nearest the hit; the converged crossing nearest the triangle hit wins.
void DisplacedPicker::refine(const PlannedCage& planned, const Displacement& displacement, const Ray& ray,
                             Hit& hit) const {
    if (newton(planned, displacement, ray, hit.subface, {hit.u, hit.v}, hit)) return;
    const glm::vec3 point = ray.origin + hit.distance * ray.direction;
    const float slack = 1e-3f * std::max(glm::length(boxes_[hit.subface].max - boxes_[hit.subface].min), 1e-6f);
    Hit best = hit;
    float bestGap = kNoDistance;
    for (uint32_t s = 0; s < grids_.size(); ++s) {
        const Box& b = boxes_[s];
        if (s == hit.subface || b.empty() || glm::any(glm::lessThan(point, b.min - slack)) ||
            glm::any(glm::greaterThan(point, b.max + slack)))
            continue;
        const Grid& g = grids_[s];
        uint32_t nearest = 0;
        for (uint32_t k = 1; k < g.displaced.size(); ++k)
            if (glm::length(g.displaced[k] - point) < glm::length(g.displaced[nearest] - point)) nearest = k;
        const glm::vec2 uv(float(nearest % (g.n + 1)) / float(g.n), float(nearest / (g.n + 1)) / float(g.n));
        Hit candidate = hit;
        if (newton(planned, displacement, ray, s, uv, candidate) && std::fabs(candidate.distance - hit.distance) < bestGap) {
            bestGap = std::fabs(candidate.distance - hit.distance);
            best = candidate;
        }
    }
    hit = best;
}

DisplacedPicker::Hit DisplacedPicker::intersect(const PlannedCage& planned, const Displacement& displacement,
                                                const Ray& ray, float maxDistance) const {
    Hit hit = triangleHit(ray, maxDistance);
    if (hit.subface == kNoHit) return hit;
    // Unrefined, the hit keeps the triangle's point with the surface's values at its (u, v).
    const DisplacedPoint f = displacedSurfacePoint(planned, displacement, hit.subface, hit.u, hit.v);
    hit.position = ray.origin + hit.distance * ray.direction;
    hit.normal = f.normal;
    hit.limit = planned.evaluate(hit.subface, hit.u, hit.v).position;
    refine(planned, displacement, ray, hit);
    return hit;
}

}  // namespace qp
