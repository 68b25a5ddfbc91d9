// The transform handle ("gizmo") drawn over a viewport at the selection's pivot: axis arrows
// and a centre square to move, axis rings and an outer view ring to rotate, axis boxes and a
// centre box to scale (Maya's W, E, R). Its geometry lives in the viewport's pixels, so it keeps
// its size on screen; hit tests and drags are plain functions of that geometry and the view
// (testable without a window); gizmo_draw.cpp draws it with Dear ImGui.
//
// Drags map the cursor to a transform of the start positions, in the frame's axes (world or
// local, core/edit/transform.h):
//   - axis move: the point of the axis nearest the cursor's ray, so the grabbed point stays
//     under the cursor (falls back to the axis's screen direction when it points at the eye);
//   - centre move: in the view plane through the pivot;
//   - axis rotation: the angle the cursor turned about the pivot's projection, signed by
//     whether the axis faces the eye; the view ring turns about the view direction;
//   - axis scale: 1 + the drag along the axis's screen direction in units of the handle's
//     length; centre scale: the cursor's distance from the pivot over the grab's.
// With snapping: moves by tenths of the handle's world length rounded to a power of ten,
// rotations by 15 degrees, scales by 0.1.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "edit/picking.h"
#include "edit/transform.h"

namespace qp::editor {

enum class GizmoMode : uint8_t { Move, Rotate, Scale };
enum class GizmoHandle : uint8_t { None, X, Y, Z, View };  // View: centre square/box, or the outer ring

inline constexpr float kGizmoPixels = 90.0f;  // axis length on screen
inline constexpr float kGizmoGrabPixels = 8.0f;

// The handle in one viewport, in that viewport's pixels (PickView conventions).
struct GizmoShape {
    GizmoMode mode = GizmoMode::Move;
    TransformFrame frame;
    glm::vec3 toEye{0.0f, 0.0f, 1.0f};  // unit, from the pivot toward the eye (or the view direction reversed)
    float worldLength = 1.0f;           // world length of an axis handle
    bool visible = false;               // the pivot is in front of the camera
    glm::vec2 centre{0.0f};
    std::array<glm::vec2, 3> axisEnd{};          // Move, Scale
    std::array<std::vector<glm::vec2>, 3> ring;  // Rotate: the axis circles (closed polylines)
    float viewRingRadius = 0.0f;                 // Rotate: the outer ring, pixels
    float centreHalf = 6.0f;                     // Move, Scale: half-size of the centre square
};

// `eye` is the camera position (perspective) and `viewDirection` where it looks; for an
// orthographic view the eye direction is -viewDirection everywhere.
GizmoShape gizmoShape(GizmoMode mode, const TransformFrame& frame, const PickView& view, const glm::vec3& eye,
                      const glm::vec3& viewDirection, bool orthographic, float axisPixels = kGizmoPixels);

// The handle under the pixel (centre handles win over axes), or None.
GizmoHandle hitGizmo(const GizmoShape& shape, const glm::vec2& pixel, float tolerance = kGizmoGrabPixels);

struct GizmoDrag {
    glm::mat4 matrix{1.0f};  // start positions -> current ones
    glm::vec3 values{0.0f};  // what the drag amounts to, in the frame's axes: offset, (degrees, 0, 0) or factors
};
// The transform of a drag of `handle` from `start` to `pixel` (viewport pixels). `shape` is
// the shape at the start of the drag; `view` the view at the start.
GizmoDrag dragGizmo(const GizmoShape& shape, GizmoHandle handle, const PickView& view, const glm::vec2& start,
                    const glm::vec2& pixel, bool snap);

}  // namespace qp::editor
