#include "sculpt_tool.h"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include <imgui.h>

#include "displacement/sculpt_samples.h"
#include "editor_app.h"

namespace qp::editor {

namespace {

float modelDiagonal(const EditorApp& app) { return std::max(cageExtent(*app.doc).bounds.diagonal(), 1e-6f); }

bool canSculpt(EditorApp& app) {
    if (app.doc->planned && !app.loader.busy()) return true;
    app.ui.status = "No cage is open (or a file is still loading).";
    return false;
}

std::string strokeName(const StrokeOptions& options, uint32_t dabs) {
    std::string name = brushKindName(options.brush.kind);
    name[0] = char(std::toupper(name[0]));
    return name + " stroke (" + std::to_string(dabs) + (dabs == 1 ? " dab)" : " dabs)");
}

void dabReadout(EditorApp& app) {
    const Drag& d = app.drag;
    char text[96];
    std::snprintf(text, sizeof text, "%s: %u dabs", brushKindName(d.stroke.brush.kind), d.strokeDabs);
    app.drag.readout = text;
}

// Ctrl's brush: the opposite where there is one (crease's ridge and a deflate are not brushes).
BrushKind invertedBrush(BrushKind kind) {
    switch (kind) {
    case BrushKind::Raise: return BrushKind::Lower;
    case BrushKind::Lower: return BrushKind::Raise;
    case BrushKind::Mask: return BrushKind::Unmask;
    case BrushKind::Unmask: return BrushKind::Mask;
    default: return kind;
    }
}

// Brushes whose strength is a height in radii (up to kMaxHeightStrength); the others blend (0..1).
bool movesHeight(BrushKind kind) {
    return kind == BrushKind::Raise || kind == BrushKind::Lower || kind == BrushKind::Inflate || kind == BrushKind::Crease;
}

void chooseBrush(EditorApp& app, BrushKind kind, const char* status) {
    app.tools.sculpt.kind = kind;
    app.tools.tool = Tool::Sculpt;
    app.ui.status = status;
}

}  // namespace

std::optional<SurfaceHit> surfaceUnderCursor(EditorApp& app, uint32_t viewport, glm::vec2 cursor) {
    if (!app.doc->planned || viewport >= app.viewports.size()) return std::nullopt;
    const ViewportState& v = app.viewports[viewport];
    const PickView view{v.viewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
    const glm::vec2 pixel = cursor - glm::vec2(float(v.rect.offset.x), float(v.rect.offset.y));
    const PlannedCage& planned = *app.doc->planned;
    const DisplacedPicker& picker = displacedPicker(app.picking, *app.doc, app.documentGeneration);
    const DisplacedPicker::Hit hit = picker.intersect(planned, displacementOf(*app.doc), view.rayThrough(pixel));
    if (hit.subface == kNoHit) return std::nullopt;
    return SurfaceHit{hit.position, hit.normal, hit.limit, hit.subface, hit.u, hit.v};
}

StrokeOptions sculptStrokeOptions(const EditorApp& app, bool ctrl, bool shift) {
    const SculptSettings& s = app.tools.sculpt;
    StrokeOptions options;
    options.brush.kind = s.kind;
    if (ctrl) options.brush.kind = invertedBrush(s.kind);
    if (shift) options.brush.kind = BrushKind::Smooth;
    options.brush.radius = s.radius * modelDiagonal(app);
    options.brush.strength = s.strength;
    if (!movesHeight(options.brush.kind)) options.brush.strength = std::min(options.brush.strength, 1.0f);
    options.brush.falloff = s.falloff;
    options.mirror = s.mirror;
    return options;
}

bool startSculptStroke(EditorApp& app, uint32_t viewport, glm::vec2 cursor, bool ctrl, bool shift) {
    if (!canSculpt(app)) return false;
    const std::optional<SurfaceHit> hit = surfaceUnderCursor(app, viewport, cursor);
    if (!hit) {
        app.ui.status = "Sculpt: no surface under the cursor";
        return false;
    }
    const StrokeOptions options = sculptStrokeOptions(app, ctrl, shift);
    if (Status valid = validateBrush(options.brush); !valid) {
        showError(app, "Sculpt: " + valid.error().message);
        return false;
    }
    if (Status begun = beginStroke(*app.doc, app.tools.sculpt.resolution, app.frame); !begun) {
        showError(app, "Sculpt: " + begun.error().message);
        return false;
    }
    Drag& d = app.drag;
    d = Drag{DragKind::Sculpt, viewport, ImGuiMouseButton_Left, cursor, cursor};
    d.stroke = options;
    d.strokeDabs = 0;
    strokeTo(*app.doc, options, hit->position);
    d.strokeDabs = app.doc->sculptor ? app.doc->sculptor->dabCount() : 0;
    dabReadout(app);
    return true;
}

void continueSculptStroke(EditorApp& app, glm::vec2 cursor) {
    Drag& d = app.drag;
    if (d.kind != DragKind::Sculpt || !strokeActive(*app.doc) || cursor == d.cursor) return;
    d.cursor = cursor;
    // Off the surface the stroke pauses; it resumes from its last point.
    const std::optional<SurfaceHit> hit = surfaceUnderCursor(app, d.viewport, cursor);
    if (!hit) return;
    strokeTo(*app.doc, d.stroke, hit->position);
    d.strokeDabs = app.doc->sculptor->dabCount();
    dabReadout(app);
}

void finishSculptStroke(EditorApp& app) {
    const Drag d = std::exchange(app.drag, Drag{});
    if (!strokeActive(*app.doc)) return;
    Result<EditReport> report = endStroke(*app.doc, strokeName(d.stroke, d.strokeDabs), app.frame);
    if (!report) {
        showError(app, "Sculpt: " + report.error().message);
        return;
    }
    app.ui.status = strokeName(d.stroke, d.strokeDabs) + ": nothing re-planned";
}

void cancelSculptStroke(EditorApp& app) {
    app.drag = Drag{};
    if (!strokeActive(*app.doc)) return;
    cancelStroke(*app.doc);
    app.ui.status = "Cancelled the stroke";
}

bool applyDisplacementResolution(EditorApp& app) {
    if (!canSculpt(app)) return false;
    const uint32_t resolution = app.tools.sculpt.resolution;
    Result<EditReport> report = setDisplacementResolution(*app.doc, resolution, app.frame);
    if (!report) {
        showError(app, "Displacement: " + report.error().message);
        return false;
    }
    app.ui.status = "Displacement tiles at " + std::to_string(resolution) + " x " + std::to_string(resolution) + " (" +
                    std::to_string(displacementOf(*app.doc).samples.size()) + " samples)";
    return true;
}

bool clearDisplacementTool(EditorApp& app) {
    if (!canSculpt(app)) return false;
    Result<EditReport> report = clearDisplacement(*app.doc, app.frame);
    if (!report) {
        showError(app, "Displacement: " + report.error().message);
        return false;
    }
    app.ui.status = "Cleared the displacement (undo brings it back)";
    return true;
}

uint32_t defaultDisplacementResolution(uint32_t subfaces) {
    constexpr uint32_t kSampleBudget = 1u << 17;
    uint32_t resolution = 16;
    while (resolution > 1 && uint64_t(subfaces) * resolution * resolution > kSampleBudget) resolution /= 2;
    return resolution;
}

bool invertMaskTool(EditorApp& app) {
    if (!canSculpt(app)) return false;
    Result<EditReport> report = invertSculptMask(*app.doc, app.frame);
    if (!report) {
        showError(app, "Invert mask: " + report.error().message);
        return false;
    }
    app.ui.status = "Inverted the mask (undo brings it back)";
    return true;
}

bool clearMaskTool(EditorApp& app) {
    if (!canSculpt(app)) return false;
    const size_t entries = app.doc->history.size();
    Result<EditReport> report = clearSculptMask(*app.doc, app.frame);
    if (!report) {
        showError(app, "Clear mask: " + report.error().message);
        return false;
    }
    app.ui.status = app.doc->history.size() == entries ? "Nothing is masked" : "Cleared the mask (undo brings it back)";
    return true;
}

void runBrushAction(EditorApp& app, std::string_view id) {
    if (id == "brush.mask") chooseBrush(app, BrushKind::Mask, "Mask brush: painted samples keep their displacement (Ctrl: unmask)");
    else if (id == "brush.inflate") chooseBrush(app, BrushKind::Inflate, "Inflate brush");
    else if (id == "brush.crease") chooseBrush(app, BrushKind::Crease, "Crease brush");
    else if (id == "brush.invert_mask") invertMaskTool(app);
    else if (id == "brush.clear_mask") clearMaskTool(app);
    else showError(app, "unknown action '" + std::string(id) + "'");
}

void scaleBrushRadius(EditorApp& app, float factor) {
    float& radius = app.tools.sculpt.radius;
    radius = std::clamp(radius * factor, 0.001f, 0.5f);
    char text[64];
    std::snprintf(text, sizeof text, "Brush radius %.1f%% of the model's size", double(radius) * 100.0);
    app.ui.status = text;
}

}  // namespace qp::editor
