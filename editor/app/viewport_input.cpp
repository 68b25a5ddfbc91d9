#include "viewport_input.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>  // GetTopMostPopupModal, ClosePopupsExceptModals

#include "actions.h"
#include "cage_pick.h"
#include "document_objects.h"
#include "editor_app.h"
#include "extrude_tool.h"
#include "object_mode.h"
#include "sculpt_tool.h"
#include "tools.h"

namespace qp::editor {

namespace {

constexpr float kDragThreshold = 4.0f;  // framebuffer pixels before a press becomes a drag


glm::vec2 viewportOrigin(const ViewportState& v) { return {float(v.rect.offset.x), float(v.rect.offset.y)}; }

// Plain: replace; Shift: add; Ctrl: remove; Ctrl+Shift: toggle.
SelectOp selectOp(const ImGuiIO& io) {
    if (io.KeyCtrl && io.KeyShift) return SelectOp::Toggle;
    if (io.KeyCtrl) return SelectOp::Remove;
    if (io.KeyShift) return SelectOp::Add;
    return SelectOp::Replace;
}

bool isSelected(const Document& doc, const PickHit& hit) {
    const Selection& s = doc.selection;
    if (hit.mode != s.mode) return false;
    switch (hit.mode) {
    case SelectionMode::Vertex: return std::binary_search(s.vertices.begin(), s.vertices.end(), hit.element);
    case SelectionMode::Edge: return std::binary_search(s.edges.begin(), s.edges.end(), hit.edge);
    case SelectionMode::Face: return std::binary_search(s.faces.begin(), s.faces.end(), hit.element);
    }
    return false;
}

// Starts moving the whole selection with the cursor, in the view plane through `anchor`.
void startMove(EditorApp& app, Drag& d, const glm::vec3& anchor) {
    const Cage& cage = app.doc->planned->cage();
    const ViewportState& v = app.viewports[d.viewport];
    d.kind = DragKind::MoveSelection;
    d.vertices = selectedVertices(app.doc->selection, cage);
    d.startPositions = positionsOf(cage, d.vertices);
    d.anchor = anchor;
    d.viewProjection = v.viewProjection;
    d.rect = v.rect;
}

// Where the pressed element is, for a view-plane move that keeps it under the cursor.
glm::vec3 anchorOf(const EditorApp& app, const PickHit& hit) {
    const Cage& cage = app.doc->planned->cage();
    switch (hit.mode) {
    case SelectionMode::Vertex: return cage.positions[hit.element];
    case SelectionMode::Edge: return glm::mix(cage.positions[hit.edge.v0], cage.positions[hit.edge.v1], hit.edgeT);
    case SelectionMode::Face: return centroid(cage, std::span<const uint32_t>(cage.faceBegin(hit.element), cage.faceSize(hit.element)));
    }
    return glm::vec3(0.0f);
}

void applyMove(EditorApp& app, Drag& d, const std::vector<glm::vec3>& positions, const char* name) {
    MoveVertices move{d.vertices, positions, d.applied, name};
    if (edit(app, move)) d.applied = true;
    else d = Drag{};
}

// Object mode's handle: the object follows the drag (no history entry until it ends).
void moveObjectLive(EditorApp& app, Drag& d, const GizmoDrag& g) {
    const uint32_t object = objectIndexOfId(*app.doc, d.objectId);
    const std::optional<ObjectTransform> t = object == kNoObject ? std::nullopt : draggedTransform(d.objectStart, d.shape, g);
    if (!t) return;  // a degenerate step: keep the last good one
    app.doc->scene.objects[object].transform = *t;
    ++app.doc->sceneRevision;
    d.applied = true;
    char text[128];
    if (d.shape.mode == GizmoMode::Move)
        std::snprintf(text, sizeof text, "location %.3f %.3f %.3f", t->translation.x, t->translation.y, t->translation.z);
    else if (d.shape.mode == GizmoMode::Rotate)
        std::snprintf(text, sizeof text, "rotate %.1f deg (XYZ %.1f %.1f %.1f)", g.values.x, t->rotationDegrees.x,
                      t->rotationDegrees.y, t->rotationDegrees.z);
    else
        std::snprintf(text, sizeof text, "scale %.3f %.3f %.3f", t->scale.x, t->scale.y, t->scale.z);
    d.readout = text;
}

// The object's drag ended: one history entry from where it started to where it is.
void finishObjectDrag(EditorApp& app, const Drag& d) {
    const uint32_t object = objectIndexOfId(*app.doc, d.objectId);
    if (object == kNoObject || !d.applied) return;
    const ObjectTransform now = app.doc->scene.objects[object].transform;
    if (now == d.objectStart) return;
    if (Status done = setObjectTransform(*app.doc, object, d.objectStart, now, app.frame); !done) {
        app.doc->scene.objects[object].transform = d.objectStart;
        ++app.doc->sceneRevision;
        showError(app, "Transform failed: " + done.error().message);
        return;
    }
    app.ui.status = d.readout;
}

void continueDrag(EditorApp& app, glm::vec2 cursor, glm::vec2 delta) {
    Drag& d = app.drag;
    if (d.kind == DragKind::Sculpt) return continueSculptStroke(app, cursor);  // it keeps its own cursor
    d.cursor = cursor;
    ViewCamera& camera = cameraOf(app, d.viewport);
    const float height = float(app.viewports[std::min<size_t>(d.viewport, app.viewports.size() - 1)].rect.extent.height);
    const bool navigation = d.kind == DragKind::Orbit || d.kind == DragKind::Pan || d.kind == DragKind::Zoom;
    if (navigation && delta != glm::vec2(0.0f)) noteCameraMoved(app);  // held still, it refines
    switch (d.kind) {
    case DragKind::Orbit: orbit(camera, delta.x, delta.y, height); break;
    case DragKind::Pan: pan(camera, delta.x, delta.y, height); break;
    case DragKind::Zoom: dolly(camera, -delta.y * 0.02f); break;
    case DragKind::Press: {
        if (glm::length(cursor - d.start) < kDragThreshold || !app.doc->planned) break;
        startMove(app, d, d.anchor);
        [[fallthrough]];
    }
    case DragKind::MoveSelection: {
        if (d.vertices.empty() || (delta == glm::vec2(0.0f) && d.applied)) break;
        // From the start of the drag, not frame to frame, so nothing drifts.
        const glm::vec3 offset = dragOffset({d.viewProjection, d.rect}, d.anchor, cursor - d.start);
        std::vector<glm::vec3> positions = d.startPositions;
        for (glm::vec3& p : positions) p += offset;
        char text[96];
        std::snprintf(text, sizeof text, "move %.3f %.3f %.3f", offset.x, offset.y, offset.z);
        d.readout = text;
        applyMove(app, d, positions, "");
        break;
    }
    case DragKind::Gizmo: {
        if (delta == glm::vec2(0.0f) && d.applied) break;
        const ViewportState& v = app.viewports[d.viewport];
        const PickView view{d.viewProjection, glm::vec2(float(d.rect.extent.width), float(d.rect.extent.height))};
        const glm::vec2 origin = viewportOrigin(v);
        const GizmoDrag g = dragGizmo(d.shape, d.handle, view, d.start - origin, cursor - origin, ImGui::GetIO().KeyCtrl);
        if (d.objectId != 0) {
            moveObjectLive(app, d, g);
            break;
        }
        Result<std::vector<glm::vec3>> positions = transformPoints(d.startPositions, g.matrix);
        if (!positions) break;  // a degenerate scale: keep the last good step
        const char* name = d.shape.mode == GizmoMode::Move ? "move" : d.shape.mode == GizmoMode::Rotate ? "rotate" : "scale";
        char text[96];
        if (d.shape.mode == GizmoMode::Rotate) std::snprintf(text, sizeof text, "rotate %.1f deg", g.values.x);
        else std::snprintf(text, sizeof text, "%s %.3f %.3f %.3f", name, g.values.x, g.values.y, g.values.z);
        d.readout = text;
        applyMove(app, d, *positions, name);
        break;
    }
    case DragKind::BoxSelect:
    case DragKind::Sculpt:
    case DragKind::None: break;
    }
}

void finishDrag(EditorApp& app) {
    if (app.drag.kind == DragKind::Sculpt) return finishSculptStroke(app);
    Drag d = std::exchange(app.drag, Drag{});
    const bool click = glm::length(d.cursor - d.start) < kDragThreshold;
    if (d.kind == DragKind::Gizmo && d.objectId != 0) {
        finishObjectDrag(app, d);
    } else if (d.kind == DragKind::Press) {  // a click on an element: select just it
        PickHit hit = pickAt(app, d.viewport, d.start);
        applyPickHit(app, hit, SelectOp::Replace);
    } else if (d.kind == DragKind::BoxSelect) {
        if (click) applyPickHit(app, pickAt(app, d.viewport, d.start), d.op);  // empty space with Replace clears
        else boxSelectIn(app, d.viewport, d.start, d.cursor, d.op);
    } else if (d.kind == DragKind::Orbit && d.loopClick && click) {  // Alt+click, not an orbit
        selectLoopAt(app, d.viewport, d.start, d.ring ? LoopKind::Ring : LoopKind::Loop, d.op);
    }
}

// Object mode: a handle drags the selected object; anywhere else a click selects the object
// under the cursor.
void objectPress(EditorApp& app, uint32_t viewport, glm::vec2 cursor) {
    if (std::optional<GizmoShape> shape = gizmoIn(app, viewport)) {
        const GizmoHandle handle = hitGizmo(*shape, cursor - viewportOrigin(app.viewports[viewport]));
        const uint32_t object = selectedObject(*app.doc);
        if (handle != GizmoHandle::None && object != kNoObject) {
            Drag& d = app.drag;
            d = Drag{DragKind::Gizmo, viewport, ImGuiMouseButton_Left, cursor, cursor};
            d.shape = *shape;
            d.handle = handle;
            d.viewProjection = app.viewports[viewport].worldViewProjection;
            d.rect = app.viewports[viewport].rect;
            d.objectId = app.doc->objectIds[object];
            d.objectStart = app.doc->scene.objects[object].transform;
            return;
        }
    }
    clickObject(app, viewport, cursor);
}

void leftPress(EditorApp& app, uint32_t viewport, glm::vec2 cursor) {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.KeyAlt) {
        // An orbit, unless the button comes up where it went down: then a loop (Ctrl: ring) click.
        app.drag = Drag{DragKind::Orbit, viewport, ImGuiMouseButton_Left, cursor, cursor};
        app.drag.loopClick = app.mode == EditorMode::Edit && app.tools.tool != Tool::Sculpt && !app.tools.loopTool;
        app.drag.ring = io.KeyCtrl;
        app.drag.op = io.KeyShift ? SelectOp::Add : SelectOp::Replace;
        return;
    }
    if (!app.doc->planned) return;
    if (app.mode == EditorMode::Object) return objectPress(app, viewport, cursor);
    if (app.tools.tool == Tool::Sculpt && !app.tools.loopTool) {
        startSculptStroke(app, viewport, cursor, io.KeyCtrl, io.KeyShift);
        return;
    }
    if (app.tools.loopTool) {
        const PickHit hit = pickEdgeAt(app, viewport, cursor);
        if (!hit.hit) {
            app.ui.status = "Loop tool: no edge under the cursor";
            return;
        }
        const float t = std::clamp(hit.edgeT, 0.02f, 0.98f);
        if (insertLoop(app, hit.edge.v0, hit.edge.v1, t) && !io.KeyShift) app.tools.loopTool = false;  // Shift: keep cutting
        return;
    }
    if (std::optional<GizmoShape> shape = gizmoIn(app, viewport)) {
        const GizmoHandle handle = hitGizmo(*shape, cursor - viewportOrigin(app.viewports[viewport]));
        if (handle != GizmoHandle::None) {
            Drag& d = app.drag;
            d = Drag{DragKind::Gizmo, viewport, ImGuiMouseButton_Left, cursor, cursor};
            startMove(app, d, shape->frame.pivot);
            d.kind = DragKind::Gizmo;
            d.shape = *shape;
            d.handle = handle;
            return;
        }
    }
    const SelectOp op = selectOp(io);
    // ImGui's double click serves the automation hook's synthetic presses, which bypass GLFW.
    if ((io.MouseDoubleClicked[ImGuiMouseButton_Left] || app.leftDoubleClick) && app.doc->selection.mode == SelectionMode::Edge) {
        selectLoopAt(app, viewport, cursor, LoopKind::Loop, op == SelectOp::Add ? op : SelectOp::Replace);
        return;
    }
    // Only the move tool moves what a drag starts on; every other drag is a box, so nothing
    // moves by accident. A click (no drag) picks at the press.
    const PickHit hit = app.tools.tool == Tool::Move && op == SelectOp::Replace ? pickAt(app, viewport, cursor) : PickHit{};
    if (!hit.hit) {
        app.drag = Drag{DragKind::BoxSelect, viewport, ImGuiMouseButton_Left, cursor, cursor};
        app.drag.op = op;
        return;
    }
    if (!isSelected(*app.doc, hit)) applyPickHit(app, hit, SelectOp::Replace);
    app.drag = Drag{DragKind::Press, viewport, ImGuiMouseButton_Left, cursor, cursor};
    app.drag.anchor = anchorOf(app, hit);
    app.drag.viewProjection = app.viewports[viewport].viewProjection;
    app.drag.rect = app.viewports[viewport].rect;
}

// What the loop tool would cut under the cursor, for the overlay.
void updateLoopPreview(EditorApp& app, uint32_t viewport, glm::vec2 cursor) {
    const PickHit hit = pickEdgeAt(app, viewport, cursor);
    if (!hit.hit) {
        app.ui.loopPreview.clear();
        app.ui.loopPreviewKey.clear();
        return;
    }
    const float t = std::round(std::clamp(hit.edgeT, 0.02f, 0.98f) * 50.0f) / 50.0f;
    char key[64];
    std::snprintf(key, sizeof key, "%u-%u@%.2f#%llu", hit.edge.v0, hit.edge.v1, double(t),
                  (unsigned long long)app.doc->positionRevision);
    if (app.ui.loopPreviewKey == key) return;
    app.ui.loopPreviewKey = key;
    app.ui.loopPreview.clear();
    Result<TopologyEdit> loop = insertEdgeLoop(app.doc->planned->cage(), app.doc->planned->topology(), hit.edge.v0, hit.edge.v1, t);
    if (!loop) return;
    for (const EdgeKey& e : loop->resultEdges) {
        app.ui.loopPreview.push_back(loop->cage.positions[e.v0]);
        app.ui.loopPreview.push_back(loop->cage.positions[e.v1]);
    }
}

}  // namespace

std::optional<GizmoShape> gizmoIn(const EditorApp& app, uint32_t viewport) {
    const Tool tool = app.tools.tool;
    if ((tool != Tool::Move && tool != Tool::Rotate && tool != Tool::Scale) || viewport >= app.viewports.size())
        return std::nullopt;
    const bool objects = app.mode == EditorMode::Object;
    std::optional<TransformFrame> frame = objects ? objectFrame(app) : selectionFrame(app);
    if (!frame) return std::nullopt;
    const ViewportState& v = app.viewports[viewport];
    const PickView view{objects ? v.worldViewProjection : v.viewProjection,
                        glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
    const GizmoMode mode = app.tools.tool == Tool::Move ? GizmoMode::Move : app.tools.tool == Tool::Rotate ? GizmoMode::Rotate : GizmoMode::Scale;
    const RenderCamera& c = v.renderCamera;
    GizmoShape shape = gizmoShape(mode, *frame, view, c.eye, glm::normalize(c.target - c.eye), c.orthographic);
    if (!shape.visible) return std::nullopt;
    return shape;
}

void cancelDrag(EditorApp& app) {
    if (app.drag.kind == DragKind::Sculpt) return cancelSculptStroke(app);
    Drag d = std::exchange(app.drag, Drag{});
    if (d.kind == DragKind::Gizmo && d.objectId != 0) {
        const uint32_t object = objectIndexOfId(*app.doc, d.objectId);
        if (object != kNoObject && d.applied) {
            app.doc->scene.objects[object].transform = d.objectStart;
            ++app.doc->sceneRevision;
            app.ui.status = "Cancelled the drag";
        }
        return;
    }
    if ((d.kind == DragKind::MoveSelection || d.kind == DragKind::Gizmo) && d.applied) {
        undoTool(app);
        app.ui.status = "Cancelled the drag";
    }
}

glm::vec2 cursorInFramebuffer() {
    const ImGuiIO& io = ImGui::GetIO();
    const float scale = io.DisplayFramebufferScale.x > 0 ? io.DisplayFramebufferScale.x : 1.0f;
    return glm::vec2(io.MousePos.x, io.MousePos.y) * scale;
}

int viewportAt(const EditorApp& app, glm::vec2 p) {
    for (size_t i = 0; i < app.viewports.size(); ++i) {
        const VkRect2D& r = app.viewports[i].rect;
        if (p.x >= float(r.offset.x) && p.y >= float(r.offset.y) && p.x < float(r.offset.x + int32_t(r.extent.width)) &&
            p.y < float(r.offset.y + int32_t(r.extent.height)))
            return int(i);
    }
    return -1;
}

void handleViewportInput(EditorApp& app) {
    const ImGuiIO& io = ImGui::GetIO();
    const float scale = io.DisplayFramebufferScale.x > 0 ? io.DisplayFramebufferScale.x : 1.0f;
    const glm::vec2 cursor = cursorInFramebuffer();
    app.ui.gizmoHover = GizmoHandle::None;
    app.ui.brushHover.reset();
    if (app.extrude) return updateInteractiveExtrude(app);  // it owns the mouse until it ends
    if (app.drag.kind != DragKind::None) {
        if (app.drag.button == ImGuiMouseButton_Left && ImGui::IsMouseClicked(ImGuiMouseButton_Right)) cancelDrag(app);
        else if (!io.MouseDown[app.drag.button]) finishDrag(app);
        else continueDrag(app, cursor, glm::vec2(io.MouseDelta.x, io.MouseDelta.y) * scale);
        if (app.drag.kind == DragKind::Sculpt) {  // the brush circle follows the stroke
            app.ui.brushHover = surfaceUnderCursor(app, app.drag.viewport, cursor);
            app.ui.brushViewport = app.drag.viewport;
        }
        return;
    }
    if (io.WantCaptureMouse || app.loader.busy() || app.job.busy()) return;
    const int hovered = viewportAt(app, cursor);
    if (hovered < 0) return;
    const uint32_t viewport = uint32_t(hovered);
    app.activeViewport = viewport;
    if (std::optional<GizmoShape> shape = gizmoIn(app, viewport))
        app.ui.gizmoHover = hitGizmo(*shape, cursor - viewportOrigin(app.viewports[viewport]));
    if (app.tools.loopTool && app.doc->planned) updateLoopPreview(app, viewport, cursor);
    if (app.mode == EditorMode::Edit && app.tools.tool == Tool::Sculpt && app.doc->planned) {
        app.ui.brushHover = surfaceUnderCursor(app, viewport, cursor);
        app.ui.brushViewport = viewport;
    }
    if (io.MouseWheel != 0.0f) {
        dolly(cameraOf(app, viewport), io.MouseWheel);
        noteCameraMoved(app);
    }
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        leftPress(app, viewport, cursor);
    } else if (ImGui::IsMouseClicked(ImGuiMouseButton_Middle)) {
        const DragKind kind = io.KeyCtrl ? DragKind::Zoom : (io.KeyAlt || io.KeyShift) ? DragKind::Pan : DragKind::Orbit;
        app.drag = Drag{kind, viewport, ImGuiMouseButton_Middle, cursor, cursor};
    } else if (ImGui::IsMouseClicked(ImGuiMouseButton_Right)) {
        if (io.KeyAlt) app.drag = Drag{DragKind::Zoom, viewport, ImGuiMouseButton_Right, cursor, cursor};
        else if (app.tools.loopTool) app.tools.loopTool = false;
    }
}

bool pairPress(ClickPairing& pairing, double time, glm::dvec2 at, double maxInterval, double maxDistance) {
    const bool paired = pairing.lastTime >= 0.0 && time - pairing.lastTime <= maxInterval &&
                        glm::length(at - pairing.lastAt) <= maxDistance;
    pairing.lastTime = paired ? -1.0 : time;
    pairing.lastAt = at;
    return paired;
}

void handleShortcuts(EditorApp& app) {
    std::vector<KeyPress> presses = std::exchange(app.keyPresses, {});
    auto plain = [](const KeyPress& p) { return !p.ctrl && !p.shift && !p.alt; };
    // A dialog on top takes Enter and Esc (panels.cpp answers them) and nothing else.
    if (ImGui::GetTopMostPopupModal()) {
        for (const KeyPress& press : presses) {
            if (!plain(press)) continue;
            if (press.key == GLFW_KEY_ESCAPE) app.ui.dialogKey = DialogKey::Cancel;
            if (press.key == GLFW_KEY_ENTER || press.key == GLFW_KEY_KP_ENTER) app.ui.dialogKey = DialogKey::Confirm;
        }
        return;
    }
    if (ImGui::GetIO().WantTextInput) return;
    auto matches = [](const KeyChord& c, const KeyPress& p) {
        return c.key != 0 && c.key == p.key && c.ctrl == p.ctrl && c.shift == p.shift && c.alt == p.alt;
    };
    const ActionScope otherMode = app.mode == EditorMode::Edit ? ActionScope::ObjectMode : ActionScope::EditMode;
    for (const KeyPress& press : presses) {
        if (app.extrude) {  // digits, Enter and Esc belong to the extrude until it ends
            extrudeKey(app, press);
            continue;
        }
        // An open menu or drop-down: Esc closes it; any other shortcut closes it and runs, so
        // the keyboard never goes dead behind a forgotten drop-down.
        if (ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId)) {
            ImGui::ClosePopupsExceptModals();
            if (press.key == GLFW_KEY_ESCAPE && plain(press)) continue;
        }
        if (press.key == GLFW_KEY_ESCAPE && plain(press)) {
            if (app.drag.kind != DragKind::None) {
                cancelDrag(app);
                continue;
            }
            if (app.tools.loopTool) {
                app.tools.loopTool = false;
                app.ui.status = "Loop tool off";
                continue;
            }
        }
        // The sculpt tool's keys first while it is active; skipped otherwise.
        const bool sculpting = app.mode == EditorMode::Edit && app.tools.tool == Tool::Sculpt;
        const ActionInfo* chosen = nullptr;
        for (const ActionInfo& action : actions()) {
            const ActionScope scope = scopeOf(action.id);
            if (!(matches(action.chord, press) || matches(action.alternate, press)) || scope == otherMode) continue;
            if (scope == ActionScope::SculptTool && !sculpting) continue;
            if (!chosen || scope == ActionScope::SculptTool) chosen = &action;
            if (scope == ActionScope::SculptTool) break;
        }
        if (chosen) runAction(app, chosen->id);
    }
}

}  // namespace qp::editor
