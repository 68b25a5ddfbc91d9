// ViewCamera: an orbit camera (target, distance, yaw, pitch) driven the way Maya and Blender
// users expect: orbit around the target, pan in the view plane, dolly toward the target,
// standard views and framing. The camera orbits about the scene's up axis: with Y up, +Z is
// the front (render/camera.h's frameBounds); with Z up (Blender), -Y is the front, so the
// Numpad views are Blender's. Yaw and pitch are measured in that frame.
#pragma once

#include <glm/glm.hpp>

#include "camera.h"
#include "mesh/cage.h"
#include "scene/scene.h"

namespace qp::editor {

struct ViewCamera {
    glm::vec3 target{0.0f};
    float distance = 5.0f;
    float yaw = 0.0f;    // radians around +Y; 0: the eye is on the +Z side (front view)
    float pitch = 0.0f;  // radians, -pi/2..pi/2; positive: the eye is above the target
    float fovY = glm::radians(35.0f);
    bool orthographic = false;  // the orthographic view height follows the distance (toggling keeps the size)
    UpAxis up = UpAxis::Y;      // yaw turns about it, pitch lifts the eye along it

    bool operator==(const ViewCamera&) const = default;
};

enum class StandardView { Front, Back, Right, Left, Top, Bottom };

glm::vec3 eyePosition(const ViewCamera& camera);
glm::vec3 upVector(const ViewCamera& camera);     // screen up, well defined in top and bottom views
glm::vec3 rightVector(const ViewCamera& camera);  // screen right
float orthoHeight(const ViewCamera& camera);      // world height of the orthographic view

// Drag amounts are in pixels; `viewportHeight` converts them to world units so that the point
// under the cursor follows it (pan) and a full-height drag turns about 180 degrees (orbit).
void orbit(ViewCamera& camera, float dxPixels, float dyPixels, float viewportHeight);
void pan(ViewCamera& camera, float dxPixels, float dyPixels, float viewportHeight);
// steps > 0 moves toward the target (one wheel notch = one step); never through it.
void dolly(ViewCamera& camera, float steps);

void setStandardView(ViewCamera& camera, StandardView view);
// Keeps the direction, moves target and distance so the box fills the view with a margin.
void frameBox(ViewCamera& camera, const glm::vec3& min, const glm::vec3& max, float aspect);

// A model's up axis when its file does not say: Z when the cage stands on the z = 0 plane (its
// lowest z is 0, it has some height along z) and not on y = 0, as models made Z-up usually do;
// else Y, the old default. Extents alone cannot tell a Y-up car (long along z) from a Z-up
// figure (tall along z), so a model floating about the origin keeps Y.
UpAxis guessUpAxis(const Bounds& bounds);
glm::vec3 upDirection(UpAxis up);  // the world's unit up vector

ViewCamera fromSceneCamera(const Camera& camera, UpAxis up = UpAxis::Y);
Camera toSceneCamera(const ViewCamera& camera);

// A renderer camera with near and far planes that hold `bounds` (the whole model).
RenderCamera renderCamera(const ViewCamera& camera, float aspect, const Bounds& bounds);

}  // namespace qp::editor
