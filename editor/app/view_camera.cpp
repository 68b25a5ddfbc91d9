#include "view_camera.h"

#include <algorithm>
#include <cmath>

namespace qp::editor {

namespace {

constexpr float kHalfPi = 1.5707963f;

// Yaw and pitch live in a Y-up frame; with Z up it is turned so that its y is the world's z
// and its front (+z) is the world's -y (right-handed: x stays x).
glm::vec3 toWorld(UpAxis up, const glm::vec3& v) { return up == UpAxis::Z ? glm::vec3(v.x, -v.z, v.y) : v; }
glm::vec3 toFrame(UpAxis up, const glm::vec3& v) { return up == UpAxis::Z ? glm::vec3(v.x, v.z, -v.y) : v; }

glm::vec3 direction(const ViewCamera& c) {  // from the target toward the eye
    return toWorld(c.up, {std::cos(c.pitch) * std::sin(c.yaw), std::sin(c.pitch), std::cos(c.pitch) * std::cos(c.yaw)});
}

}  // namespace

glm::vec3 eyePosition(const ViewCamera& c) { return c.target + c.distance * direction(c); }

glm::vec3 rightVector(const ViewCamera& c) { return toWorld(c.up, {std::cos(c.yaw), 0.0f, -std::sin(c.yaw)}); }

glm::vec3 upVector(const ViewCamera& c) { return glm::cross(rightVector(c), -direction(c)); }

float orthoHeight(const ViewCamera& c) { return 2.0f * c.distance * std::tan(0.5f * c.fovY); }

void orbit(ViewCamera& c, float dx, float dy, float viewportHeight) {
    const float radiansPerPixel = 3.14159265f / std::max(viewportHeight, 1.0f);
    c.yaw = std::remainder(c.yaw - dx * radiansPerPixel, 2.0f * 3.14159265f);
    c.pitch = std::clamp(c.pitch + dy * radiansPerPixel, -kHalfPi, kHalfPi);
}

void pan(ViewCamera& c, float dx, float dy, float viewportHeight) {
    const float worldPerPixel = orthoHeight(c) / std::max(viewportHeight, 1.0f);
    c.target += worldPerPixel * (-dx * rightVector(c) + dy * upVector(c));
}

void dolly(ViewCamera& c, float steps) { c.distance = std::max(c.distance * std::pow(0.85f, steps), 1e-4f); }

void setStandardView(ViewCamera& c, StandardView view) {
    switch (view) {
        case StandardView::Front: c.yaw = 0.0f, c.pitch = 0.0f; break;
        case StandardView::Back: c.yaw = 2.0f * kHalfPi, c.pitch = 0.0f; break;
        case StandardView::Right: c.yaw = kHalfPi, c.pitch = 0.0f; break;
        case StandardView::Left: c.yaw = -kHalfPi, c.pitch = 0.0f; break;
        case StandardView::Top: c.yaw = 0.0f, c.pitch = kHalfPi; break;
        case StandardView::Bottom: c.yaw = 0.0f, c.pitch = -kHalfPi; break;
    }
}

void frameBox(ViewCamera& c, const glm::vec3& min, const glm::vec3& max, float aspect) {
    c.target = 0.5f * (min + max);
    const float radius = std::max(0.5f * glm::length(max - min), 1e-3f);
    const float halfFov = 0.5f * c.fovY;
    const float halfFovX = std::atan(std::tan(halfFov) * std::max(aspect, 1e-3f));
    c.distance = 1.1f * radius / std::sin(std::min(halfFov, halfFovX));
}

UpAxis guessUpAxis(const Bounds& b) {
    const glm::vec3 extent = b.max - b.min;
    const float size = std::max({extent.x, extent.y, extent.z, 1e-6f});
    const float touching = 1e-3f * size;
    const bool standsOnZ = std::abs(b.min.z) <= touching && extent.z > 0.2f * size;
    const bool standsOnY = std::abs(b.min.y) <= touching;
    return standsOnZ && !standsOnY ? UpAxis::Z : UpAxis::Y;
}

glm::vec3 upDirection(UpAxis up) { return up == UpAxis::Z ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0); }

ViewCamera fromSceneCamera(const Camera& s, UpAxis up) {
    ViewCamera c;
    c.up = up;
    c.target = s.target;
    glm::vec3 offset = toFrame(up, s.eye - s.target);
    c.distance = std::max(glm::length(offset), 1e-4f);
    offset /= c.distance;
    c.pitch = std::asin(std::clamp(offset.y, -1.0f, 1.0f));
    c.yaw = std::atan2(offset.x, offset.z);
    c.fovY = glm::radians(std::clamp(s.fovYDegrees, 1.0f, 170.0f));
    c.orthographic = s.projection == Projection::Orthographic;
    if (c.orthographic) c.distance = std::max(s.orthoHeight / (2.0f * std::tan(0.5f * c.fovY)), 1e-4f);
    return c;
}

Camera toSceneCamera(const ViewCamera& c) {
    Camera s;
    s.eye = eyePosition(c);
    s.target = c.target;
    s.up = upVector(c);
    s.fovYDegrees = glm::degrees(c.fovY);
    s.projection = c.orthographic ? Projection::Orthographic : Projection::Perspective;
    s.orthoHeight = orthoHeight(c);
    return s;
}

RenderCamera renderCamera(const ViewCamera& c, float aspect, const Bounds& bounds) {
    RenderCamera r;
    r.eye = eyePosition(c);
    r.target = c.target;
    r.up = upVector(c);
    r.fovY = c.fovY;
    r.aspect = aspect;
    r.orthographic = c.orthographic;
    r.orthoHeight = orthoHeight(c);
    const float radius = std::max(0.5f * bounds.diagonal(), 1e-4f);
    const float toCentre = glm::length(0.5f * (bounds.min + bounds.max) - r.eye);
    r.farZ = toCentre + 2.0f * radius;
    // An orthographic view may put the eye inside the model: its near plane can lie behind it.
    r.nearZ = c.orthographic ? toCentre - 2.0f * radius : std::max(toCentre - 2.0f * radius, r.farZ * 1e-4f);
    return r;
}

}  // namespace qp::editor
