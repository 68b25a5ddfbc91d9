// Viewport overlays drawn with Dear ImGui (no 3D redraw): the transform handle, the box of a
// box selection, the loop tool's preview, a drag's readout, the heat map's colour scale.
#pragma once

namespace qp::editor {

struct EditorApp;

void drawViewportOverlays(EditorApp& app);

}  // namespace qp::editor
