#include "panel_sections.h"

#include <cstdio>

#include <imgui.h>

#include "editor_app.h"
#include "panel_widgets.h"
#include "tools.h"

namespace qp::editor {

namespace {


const char* modeName(SelectionMode mode) {
    return mode == SelectionMode::Vertex ? "vertices" : mode == SelectionMode::Edge ? "edges" : "faces";
}

}  // namespace



void toolsSection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Select and transform", ImGuiTreeNodeFlags_DefaultOpen)) return;
    Document& doc = *app.doc;
    const SelectionMode mode = doc.selection.mode;
    if (radio(app, "Vertex", mode == SelectionMode::Vertex, "Select vertices (1 or F9)")) setMode(app, SelectionMode::Vertex);
    ImGui::SameLine();
    if (radio(app, "Edge", mode == SelectionMode::Edge, "Select edges (2 or F10)")) setMode(app, SelectionMode::Edge);
    ImGui::SameLine();
    if (radio(app, "Face", mode == SelectionMode::Face, "Select faces (3 or F11)")) setMode(app, SelectionMode::Face);
    const Tool tool = app.tools.tool;
    if (radio(app, "Select##tool", tool == Tool::Select, "Click, box and drag to select (Q)")) app.tools.tool = Tool::Select;
    ImGui::SameLine();
    if (radio(app, "Move##tool", tool == Tool::Move, "Move handle (W): arrows along an axis, centre square in the view plane"))
        app.tools.tool = Tool::Move;
    ImGui::SameLine();
    if (radio(app, "Rotate##tool", tool == Tool::Rotate, "Rotate handle (E): rings about an axis, outer ring about the view"))
        app.tools.tool = Tool::Rotate;
    ImGui::SameLine();
    if (radio(app, "Scale##tool", tool == Tool::Scale, "Scale handle (R): boxes along an axis, centre box evenly"))
        app.tools.tool = Tool::Scale;
    const bool world = app.tools.space == TransformSpace::World;
    if (radio(app, "World axes", world, "The handle and numeric entry use the world's x, y, z (L toggles)"))
        app.tools.space = TransformSpace::World;
    ImGui::SameLine();
    if (radio(app, "Local axes", !world, "z along the selection's normal, x from the world's x (L toggles)"))
        app.tools.space = TransformSpace::Local;
    bool hidden = !app.tools.visibleOnly;
    if (checkbox(app, "Select hidden", &hidden, "Clicks and boxes also take elements the limit surface hides (x-ray)"))
        app.tools.visibleOnly = !hidden;
    ImGui::SameLine();
    checkbox(app, "Faces on surface", &app.tools.facesOnSurface,
             "Face clicks pick the face whose limit patch is under the cursor (else the cage face)");
    actionButton(app, "All", "select.all");
    ImGui::SameLine();
    actionButton(app, "None", "select.none");
    ImGui::SameLine();
    actionButton(app, "Invert", "select.invert");
    ImGui::SameLine();
    actionButton(app, "Grow", "select.grow");
    ImGui::SameLine();
    actionButton(app, "Shrink", "select.shrink");
    if (!doc.planned) return;
    const std::vector<uint32_t> vertices = selectedVertices(doc.selection, doc.planned->cage());
    ImGui::Text("%zu %s selected (%zu vertices)", doc.selection.size(), modeName(mode), vertices.size());
    if (vertices.empty()) {
        ImGui::TextDisabled("Click or drag a box in a viewport to select.");
        return;
    }
    ImGui::BeginDisabled(app.loader.busy());
    if (vertices.size() == 1) {
        glm::vec3 p = doc.planned->cage().positions[vertices[0]];
        const std::string label = "Vertex " + std::to_string(vertices[0]) + "##position";
        inputFloat3(app, label.c_str(), &p, "Type a new position; Enter applies it");
        if (ImGui::IsItemDeactivatedAfterEdit()) edit(app, MoveVertices{{vertices[0]}, {p}});
    } else if (std::optional<TransformFrame> frame = selectionFrame(app)) {
        ImGui::Text("Pivot (centroid) %.3f, %.3f, %.3f", frame->pivot.x, frame->pivot.y, frame->pivot.z);
    }
    ToolSettings& t = app.tools;
    ImGui::SetNextItemWidth(170);
    inputFloat3(app, "##moveby", &t.moveBy, "Offset along the axes above (world or local)");
    ImGui::SameLine();
    if (button(app, "Move by", "Move the selection by this offset (one undo entry)"))
        transformSelection(app, NumericTransform::Move, glm::vec4(t.moveBy, 0.0f));
    ImGui::SetNextItemWidth(170);
    inputFloat3(app, "##rotateaxis", &t.rotateAxis, "Rotation axis, in the axes above");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(55);
    ImGui::InputFloat("##degrees", &t.rotateDegrees, 0, 0, "%.1f");
    recordWidget(app, "##degrees");
    tooltip(app, "##degrees", "Degrees, counter-clockwise about the axis (right hand)");
    ImGui::SameLine();
    if (button(app, "Rotate", "Rotate the selection about its centroid (one undo entry)"))
        transformSelection(app, NumericTransform::Rotate, glm::vec4(t.rotateAxis, t.rotateDegrees));
    ImGui::SetNextItemWidth(170);
    inputFloat3(app, "##scaleby", &t.scaleBy, "Factors along the axes above (0 flattens)");
    ImGui::SameLine();
    if (button(app, "Scale", "Scale the selection about its centroid (one undo entry)"))
        transformSelection(app, NumericTransform::Scale, glm::vec4(t.scaleBy, 0.0f));
    ImGui::EndDisabled();
}


void historySection(EditorApp& app) {
    if (!app.ui.showHistory) return;
    if (!ImGui::CollapsingHeader("History", ImGuiTreeNodeFlags_DefaultOpen)) return;
    Document& doc = *app.doc;
    const EditHistory& h = doc.history;
    ImGui::BeginDisabled(app.loader.busy() || !doc.planned);
    actionButton(app, "Undo", "edit.undo");
    ImGui::SameLine();
    actionButton(app, "Redo", "edit.redo");
    ImGui::SameLine();
    ImGui::Text("%zu of %zu, %.1f KB", h.position(), h.size(), double(h.bytes()) / 1024.0);
    ImGui::BeginChild("historylist", ImVec2(0, 130), true);
    std::optional<size_t> jump;
    if (ImGui::Selectable("(as opened)", h.position() == 0)) jump = 0;
    for (size_t i = 0; i < h.size(); ++i) {
        const HistoryEntryInfo entry = h.entry(i);
        char label[256];
        std::snprintf(label, sizeof label, "%zu %s  (%u faces, %.2f ms)##h%zu", i + 1, entry.name.c_str(),
                      entry.report.replannedFaces, entry.report.milliseconds, i);
        if (i >= h.position()) ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        if (ImGui::Selectable(label, i + 1 == h.position())) jump = i + 1;
        if (i >= h.position()) ImGui::PopStyleColor();
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Click to go to the state after this edit (undone edits are greyed; they can be redone)");
        if (i + 1 == h.position() && ImGui::IsWindowAppearing()) ImGui::SetScrollHereY();
    }
    ImGui::EndChild();
    ImGui::EndDisabled();
    if (jump) jumpHistoryTool(app, *jump);
}
}  // namespace qp::editor
