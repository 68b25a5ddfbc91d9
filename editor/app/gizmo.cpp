#include "gizmo.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

namespace qp::editor {

namespace {

float distanceToSegment(glm::vec2 p, glm::vec2 a, glm::vec2 b) {
    const glm::vec2 ab = b - a;
    const float t = std::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-12f), 0.0f, 1.0f);
    return glm::length(p - (a + t * ab));
}

float snapTo(float value, float step) { return step > 0.0f ? std::round(value / step) * step : value; }

// Parameter along the axis line pivot + t * axis of the point nearest the ray; false when the
// ray runs (nearly) along the axis.
bool axisParameter(const Ray& ray, const glm::vec3& pivot, const glm::vec3& axis, float& t) {
    const float b = glm::dot(axis, ray.direction);
    const float denom = 1.0f - b * b;
    if (denom < 1e-4f) return false;
    const glm::vec3 w = pivot - ray.origin;
    t = (b * glm::dot(ray.direction, w) - glm::dot(axis, w)) / denom;
    return std::isfinite(t);
}

// Where the ray meets the plane through `point` facing `normal` (the ray's origin when parallel).
glm::vec3 onPlane(const Ray& ray, const glm::vec3& point, const glm::vec3& normal) {
    const float d = glm::dot(ray.direction, normal);
    if (std::abs(d) < 1e-6f) return ray.origin;
    return ray.origin + ray.direction * (glm::dot(point - ray.origin, normal) / d);
}

// Degrees the cursor turned about `centre` from `start` to `pixel`, counter-clockwise on screen
// positive (pixel y points down).
float screenTurnDegrees(glm::vec2 centre, glm::vec2 start, glm::vec2 pixel) {
    const glm::vec2 a = start - centre, b = pixel - centre;
    const float cross = a.x * b.y - a.y * b.x, dot = glm::dot(a, b);
    return -std::atan2(cross, dot) * 180.0f / glm::pi<float>();
}

}  // namespace

GizmoShape gizmoShape(GizmoMode mode, const TransformFrame& frame, const PickView& view, const glm::vec3& eye,
                      const glm::vec3& viewDirection, bool orthographic, float axisPixels) {
    GizmoShape shape;
    shape.mode = mode;
    shape.frame = frame;
    const glm::vec3 toEye = orthographic ? -viewDirection : eye - frame.pivot;
    shape.toEye = glm::length(toEye) > 0.0f ? glm::normalize(toEye) : glm::vec3(0.0f, 0.0f, 1.0f);
    const PickView::Projected centre = view.project(frame.pivot);
    shape.visible = centre.inFront;
    if (!shape.visible) return shape;
    shape.centre = centre.pixel;
    // Pixels per world unit at the pivot, measured across the view direction.
    glm::vec3 across = glm::cross(shape.toEye, std::abs(shape.toEye.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0));
    across = glm::normalize(across);
    const float probe = std::max(1e-3f * glm::length(eye - frame.pivot), 1e-5f);
    const float pixelsPerUnit = glm::length(view.project(frame.pivot + across * probe).pixel - shape.centre) / probe;
    shape.worldLength = pixelsPerUnit > 0.0f ? axisPixels / pixelsPerUnit : 1.0f;
    for (int i = 0; i < 3; ++i) {
        shape.axisEnd[i] = view.project(frame.pivot + frame.axes[i] * shape.worldLength).pixel;
        if (mode != GizmoMode::Rotate) continue;
        const glm::vec3 u = frame.axes[(i + 1) % 3], v = frame.axes[(i + 2) % 3];
        constexpr int kSegments = 64;
        for (int k = 0; k <= kSegments; ++k) {
            const float angle = 2.0f * glm::pi<float>() * float(k) / float(kSegments);
            const glm::vec3 p = frame.pivot + shape.worldLength * (std::cos(angle) * u + std::sin(angle) * v);
            shape.ring[i].push_back(view.project(p).pixel);
        }
    }
    shape.viewRingRadius = axisPixels * 1.25f;
    return shape;
}

GizmoHandle hitGizmo(const GizmoShape& shape, const glm::vec2& pixel, float tolerance) {
    if (!shape.visible) return GizmoHandle::None;
    const glm::vec2 d = pixel - shape.centre;
    if (shape.mode != GizmoMode::Rotate) {
        if (std::max(std::abs(d.x), std::abs(d.y)) <= shape.centreHalf + 2.0f) return GizmoHandle::View;
        float best = tolerance;
        GizmoHandle handle = GizmoHandle::None;
        for (int i = 0; i < 3; ++i) {
            const float distance = distanceToSegment(pixel, shape.centre, shape.axisEnd[i]);
            if (distance <= best) best = distance, handle = GizmoHandle(int(GizmoHandle::X) + i);
        }
        return handle;
    }
    float best = tolerance;
    GizmoHandle handle = GizmoHandle::None;
    for (int i = 0; i < 3; ++i) {
        // A ring seen edge-on is a line through the centre: turning the cursor about the centre
        // cannot say how far it rotates, and it would shadow the rings that face the eye.
        if (std::abs(glm::dot(shape.frame.axes[i], shape.toEye)) < 0.05f) continue;
        for (size_t k = 0; k + 1 < shape.ring[i].size(); ++k) {
            const float distance = distanceToSegment(pixel, shape.ring[i][k], shape.ring[i][k + 1]);
            if (distance <= best) best = distance, handle = GizmoHandle(int(GizmoHandle::X) + i);
        }
    }
    if (handle == GizmoHandle::None && std::abs(glm::length(d) - shape.viewRingRadius) <= tolerance) return GizmoHandle::View;
    return handle;
}

GizmoDrag dragGizmo(const GizmoShape& shape, GizmoHandle handle, const PickView& view, const glm::vec2& start,
                    const glm::vec2& pixel, bool snap) {
    GizmoDrag drag;
    if (handle == GizmoHandle::None || !shape.visible) return drag;
    const TransformFrame& frame = shape.frame;
    const int axis = handle == GizmoHandle::View ? -1 : int(handle) - int(GizmoHandle::X);
    switch (shape.mode) {
    case GizmoMode::Move: {
        glm::vec3 offset(0.0f);  // in frame coordinates
        if (axis >= 0) {
            const glm::vec3 direction = frame.axes[axis];
            float t0 = 0.0f, t1 = 0.0f;
            if (!axisParameter(view.rayThrough(start), frame.pivot, direction, t0) ||
                !axisParameter(view.rayThrough(pixel), frame.pivot, direction, t1)) {
                const glm::vec2 screen = shape.axisEnd[axis] - shape.centre;
                const float length = std::max(glm::length(screen), 1.0f);
                t0 = 0.0f;
                t1 = glm::dot(pixel - start, screen / length) / length * shape.worldLength;
            }
            offset[axis] = t1 - t0;
        } else {
            const glm::vec3 world = onPlane(view.rayThrough(pixel), frame.pivot, shape.toEye) -
                                    onPlane(view.rayThrough(start), frame.pivot, shape.toEye);
            offset = glm::transpose(frame.axes) * world;
        }
        if (snap) {
            const float step = std::pow(10.0f, std::floor(std::log10(std::max(shape.worldLength * 0.5f, 1e-6f))));
            for (int i = 0; i < 3; ++i) offset[i] = snapTo(offset[i], step);
        }
        drag.values = offset;
        drag.matrix = translation(frame, offset);
        break;
    }
    case GizmoMode::Rotate: {
        float degrees = screenTurnDegrees(shape.centre, start, pixel);
        glm::vec3 axisInFrame;
        if (axis >= 0) {
            axisInFrame = glm::vec3(0.0f);
            axisInFrame[axis] = 1.0f;
            if (glm::dot(frame.axes[axis], shape.toEye) < 0.0f) degrees = -degrees;
        } else {
            axisInFrame = glm::transpose(frame.axes) * shape.toEye;
        }
        if (snap) degrees = snapTo(degrees, 15.0f);
        drag.values = glm::vec3(degrees, 0.0f, 0.0f);
        drag.matrix = rotation(frame, axisInFrame, degrees);
        break;
    }
    case GizmoMode::Scale: {
        glm::vec3 factors(1.0f);
        if (axis >= 0) {
            const glm::vec2 screen = shape.axisEnd[axis] - shape.centre;
            const float length = std::max(glm::length(screen), 1.0f);
            float s = 1.0f + glm::dot(pixel - start, screen / length) / length;
            if (snap) s = snapTo(s, 0.1f);
            factors[axis] = s;
        } else {
            float s = glm::length(pixel - shape.centre) / std::max(glm::length(start - shape.centre), 1.0f);
            if (snap) s = snapTo(s, 0.1f);
            factors = glm::vec3(s);
        }
        drag.values = factors;
        drag.matrix = scaling(frame, factors);
        break;
    }
    }
    return drag;
}

}  // namespace qp::editor
