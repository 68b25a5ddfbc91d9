#include "viewport_input.h"

#include <algorithm>
#include <utility>

#include <imgui.h>

#include "actions.h"
#include "cage_pick.h"
#include "editor_app.h"

namespace qp::editor {

namespace {

constexpr float kVertexPickRadius = 12.0f;  // framebuffer pixels
constexpr float kEdgePickRadius = 6.0f;

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

ScreenMapping mappingOf(const ViewportState& v) { return {v.viewProjection, v.rect}; }

// Left click without Alt: pick a vertex (and grab the selection to move it), else an edge.
void clickSelect(EditorApp& app, uint32_t viewport, glm::vec2 cursor, bool add) {
    Document& doc = *app.doc;
    if (!doc.planned) return;
    const ViewportState& v = app.viewports[viewport];
    const Cage& cage = doc.planned->cage();
    if (std::optional<uint32_t> vertex = pickVertex(cage, mappingOf(v), cursor, kVertexPickRadius)) {
        const bool selected = std::binary_search(doc.selection.vertices.begin(), doc.selection.vertices.end(), *vertex);
        if (add || !selected) (void)selectVertex(doc, *vertex, add);
        if (add) return;
        Drag& d = app.drag;
        d = Drag{DragKind::MoveSelection, viewport, 0, cursor};
        d.anchor = cage.positions[*vertex];
        d.vertices = doc.selection.vertices;
        for (uint32_t s : d.vertices) d.startPositions.push_back(cage.positions[s]);
        d.viewProjection = v.viewProjection;
        d.rect = v.rect;
        return;
    }
    if (add) return;
    if (auto edge = pickEdge(cage, doc.planned->topology(), mappingOf(v), cursor, kEdgePickRadius))
        (void)selectEdge(doc, edge->first, edge->second);
    else
        clearSelection(doc);
}

void startDrag(EditorApp& app, DragKind kind, uint32_t viewport, int button, glm::vec2 cursor) {
    app.drag = Drag{kind, viewport, button, cursor};
}

void continueDrag(EditorApp& app, glm::vec2 cursor, glm::vec2 delta) {
    Drag& d = app.drag;
    ViewCamera& camera = cameraOf(app, d.viewport);
    const float height = float(app.viewports[std::min<size_t>(d.viewport, app.viewports.size() - 1)].rect.extent.height);
    switch (d.kind) {
        case DragKind::Orbit: orbit(camera, delta.x, delta.y, height); break;
        case DragKind::Pan: pan(camera, delta.x, delta.y, height); break;
        case DragKind::Zoom: dolly(camera, -delta.y * 0.02f); break;
        case DragKind::MoveSelection: {
            if (delta == glm::vec2(0.0f) || d.vertices.empty()) break;
            // From the start of the drag, not frame to frame, so nothing drifts.
            const glm::vec3 offset = dragOffset({d.viewProjection, d.rect}, d.anchor, cursor - d.start);
            MoveVertices move{d.vertices, d.startPositions};
            for (glm::vec3& p : move.positions) p += offset;
            if (!edit(app, move)) d = Drag{};
            break;
        }
        case DragKind::None: break;
    }
}

}  // namespace

void handleViewportInput(EditorApp& app) {
    const ImGuiIO& io = ImGui::GetIO();
    const float scale = io.DisplayFramebufferScale.x > 0 ? io.DisplayFramebufferScale.x : 1.0f;
    const glm::vec2 cursor = cursorInFramebuffer();
    if (app.drag.kind != DragKind::None) {
        if (!io.MouseDown[app.drag.button]) app.drag = Drag{};
        else continueDrag(app, cursor, glm::vec2(io.MouseDelta.x, io.MouseDelta.y) * scale);
        return;
    }
    if (io.WantCaptureMouse || app.loader.busy()) return;
    const int hovered = viewportAt(app, cursor);
    if (hovered < 0) return;
    const uint32_t viewport = uint32_t(hovered);
    app.activeViewport = viewport;
    if (io.MouseWheel != 0.0f) dolly(cameraOf(app, viewport), io.MouseWheel);
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        if (io.KeyAlt) startDrag(app, DragKind::Orbit, viewport, ImGuiMouseButton_Left, cursor);
        else clickSelect(app, viewport, cursor, io.KeyShift);
    } else if (ImGui::IsMouseClicked(ImGuiMouseButton_Middle)) {
        const DragKind kind = io.KeyCtrl ? DragKind::Zoom : (io.KeyAlt || io.KeyShift) ? DragKind::Pan : DragKind::Orbit;
        startDrag(app, kind, viewport, ImGuiMouseButton_Middle, cursor);
    } else if (ImGui::IsMouseClicked(ImGuiMouseButton_Right) && io.KeyAlt) {
        startDrag(app, DragKind::Zoom, viewport, ImGuiMouseButton_Right, cursor);
    }
}

void handleShortcuts(EditorApp& app) {
    std::vector<KeyPress> presses = std::exchange(app.keyPresses, {});
    if (ImGui::GetIO().WantTextInput || ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId)) return;
    for (const KeyPress& press : presses)
        for (const ActionInfo& action : actions())
            if (action.chord.key == press.key && action.chord.ctrl == press.ctrl && action.chord.shift == press.shift &&
                !press.alt)
                runAction(app, action.id);
}

}  // namespace qp::editor
