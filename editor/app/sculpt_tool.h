// The sculpt tool (B): a left drag over the displaced surface paints with the brush of
// ToolSettings::sculpt (core/displacement/brush.h: raise, lower, smooth, flatten, erase, inflate, crease,
// mask, unmask; radius, strength, falloff, mirror). Ctrl swaps raise and lower, mask and
// unmask, Shift smooths, for the stroke they start. One stroke is one undo entry; a right click or Esc during the stroke puts the samples
// back. Strokes follow the displaced surface under the cursor, the one the user sees: the pick,
// the dab centres and the brush circle are all on s + D N.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include <glm/glm.hpp>

#include "displacement/brush.h"

namespace qp::editor {

struct EditorApp;

// What the panel, the shortcuts and automation change.
struct SculptSettings {
    BrushKind kind = BrushKind::Raise;
    float radius = 0.05f;    // fraction of the cage's bounding-box diagonal
    float strength = 0.05f;  // brush.h's meaning per kind
    Falloff falloff = Falloff::Smooth;
    MirrorAxis mirror = MirrorAxis::None;
    uint32_t resolution = 16;  // of a new displacement, and what "Apply resolution" sets
};

// The DISPLACED surface under a cursor (framebuffer pixels): the exact limit surface moved by
// the displacement, s + D N (core/displacement/displaced_picker.h), with its unit normal normalize(f_u x f_v)
// there: where dabs act and the brush circle lies. `limit` is the undisplaced point s.
struct SurfaceHit {
    glm::vec3 position{0.0f}, normal{0.0f, 0.0f, 1.0f}, limit{0.0f};
    uint32_t subface = 0;  // where: (sub-face, u, v) of PlannedCage::evaluate
    float u = 0.0f, v = 0.0f;
};
std::optional<SurfaceHit> surfaceUnderCursor(EditorApp& app, uint32_t viewport, glm::vec2 cursor);

// The brush in world units, with the modifiers' changes (Ctrl: raise <-> lower, Shift: smooth).
StrokeOptions sculptStrokeOptions(const EditorApp& app, bool ctrl, bool shift);

// A stroke: start (false when nothing is under the cursor or the stroke cannot begin),
// continue with each new cursor position, finish (one history entry) or cancel.
bool startSculptStroke(EditorApp& app, uint32_t viewport, glm::vec2 cursor, bool ctrl, bool shift);
void continueSculptStroke(EditorApp& app, glm::vec2 cursor);
void finishSculptStroke(EditorApp& app);
void cancelSculptStroke(EditorApp& app);

// Panel buttons: every sub-face at the settings' resolution (resampled), or no displacement.
bool applyDisplacementResolution(EditorApp& app);
bool clearDisplacementTool(EditorApp& app);

// The resolution a new displacement gets on a cage of this many sub-faces: 16, or less so that
// the whole surface holds at most about 128k samples (sculpted all over, every sample is a grid
// vertex: on lavapipe about 100 ms a frame at that size, docs/editor.md).
uint32_t defaultDisplacementResolution(uint32_t subfaces);

// The sculpt tool's actions ("brush." in actions.cpp): choose the mask, inflate or crease brush
// (and the sculpt tool), invert or clear the mask (one undo entry each).
void runBrushAction(EditorApp& app, std::string_view id);
bool invertMaskTool(EditorApp& app);
bool clearMaskTool(EditorApp& app);

// Multiplies the brush radius (the [ and ] keys), within 0.1% .. 50% of the diagonal.
void scaleBrushRadius(EditorApp& app, float factor);

}  // namespace qp::editor
