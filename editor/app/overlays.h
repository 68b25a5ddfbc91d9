// Viewport overlays drawn with Dear ImGui (no 3D redraw): the transform handle, the box of a
// box selection, the loop tool's preview, a drag's readout, the heat map's colour scale and
// the axis triad in each viewport's lower right corner.
#pragma once

#include <array>

#include <glm/glm.hpp>

namespace qp::editor {

struct EditorApp;

// The world's x, y, z axes as the triad draws them: screen directions (x right, y down; unit
// length when the axis lies in the view plane, shorter as it turns toward or away from the
// viewer) and how far each points toward the viewer (-1..1), from a Vulkan view-projection.
struct AxisTriad {
    std::array<glm::vec2, 3> screen;
    std::array<float, 3> towardViewer;
};
AxisTriad axisTriad(const glm::mat4& viewProjection);

void drawViewportOverlays(EditorApp& app);

}  // namespace qp::editor
