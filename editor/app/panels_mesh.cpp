#include <cstdio>
#include <string>

#include <imgui.h>

#include "editor_app.h"
#include "panel_sections.h"
#include "panel_widgets.h"
#include "tools.h"

namespace qp::editor {

void meshSection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Mesh", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ToolSettings& t = app.tools;
    ImGui::BeginDisabled(app.loader.busy() || !app.doc->planned);
    actionButton(app, "Extrude", "mesh.extrude");
    ImGui::SameLine();
    if (button(app, "Extrude by", "Extrude the selected faces by this distance at once (no mouse)")) extrudeSelection(app);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(90);
    ImGui::InputFloat("##extrude", &t.extrudeDistance, 0, 0, "%.3f");
    recordWidget(app, "##extrude");
    tooltip(app, "##extrude", "Distance of 'Extrude by' along each region's normal (the interactive extrude remembers its last)");
    actionButton(app, "Delete", "mesh.delete");
    ImGui::SameLine();
    actionButton(app, "Hole", "mesh.hole");
    ImGui::SameLine();
    actionButton(app, "Hide", "mesh.hide");
    ImGui::SameLine();
    actionButton(app, "Unhide all", "mesh.unhide");
    if (!app.doc->hiddenFaces.empty()) {
        ImGui::SameLine();
        ImGui::Text("%zu hidden", app.doc->hiddenFaces.size());
    }
    ImGui::SetNextItemWidth(120);
    sliderFloat(app, "##loopfraction", &t.loopFraction, 0.05f, 0.95f, "at %.2f", "Where the loop cuts the selected edge, from its first vertex");
    ImGui::SameLine();
    actionButton(app, "Loop on edge", "mesh.loop");
    ImGui::SameLine();
    bool loopTool = t.loopTool;
    if (checkbox(app, "Loop tool", &loopTool, "Ctrl+R: click an edge to cut a loop where the cursor is (Shift+click: keep cutting)"))
        t.loopTool = loopTool;
    actionButton(app, "Split face", "mesh.split");
    ImGui::SameLine();
    actionButton(app, "Make face", "mesh.make_face");
    ImGui::SameLine();
    actionButton(app, "Merge", "mesh.merge");
    ImGui::SameLine();
    bool atLast = t.mergeTarget == MergeTarget::Last;
    if (checkbox(app, "at last", &atLast, "Merge at the last selected vertex (highest number) instead of the centre"))
        t.mergeTarget = atLast ? MergeTarget::Last : MergeTarget::Centroid;
    ImGui::EndDisabled();
}

void creaseSection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Creases and corners", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ToolSettings& t = app.tools;
    ImGui::BeginDisabled(app.loader.busy() || !app.doc->planned);
    const Document& doc = *app.doc;
    if (doc.planned && doc.selection.mode == SelectionMode::Edge && doc.selection.edges.size() == 1) {
        const EdgeKey e = doc.selection.edges[0];
        const float s = doc.planned->cage().edgeSharpness(e.v0, e.v1);
        ImGui::Text("Edge %u-%u: sharpness %s", e.v0, e.v1, s >= kInfiniteSharpness ? "infinite" : std::to_string(s).substr(0, 5).c_str());
    }
    // The sliders and Inf act on the selection at once in their mode (edges in edge mode,
    // corners in vertex mode); a drag is one history entry.
    const bool edgeMode = doc.planned && doc.selection.mode == SelectionMode::Edge && !doc.selection.edges.empty();
    const bool vertexMode = doc.planned && doc.selection.mode == SelectionMode::Vertex && !doc.selection.vertices.empty();
    ImGui::SetNextItemWidth(150);
    if (sliderFloat(app, "Edge sharpness", &t.edgeSharpness, 0.0f, kInfiniteSharpness,
                    t.edgeSharpness >= kInfiniteSharpness ? "infinite" : "%.2f",
                    "Semi-sharp crease value (fractional; 10 is infinitely sharp); in edge mode the selected edges follow it") &&
        edgeMode)
        creaseSelectionLive(app, t.edgeSharpness);
    if (ImGui::IsItemDeactivated()) endLiveEdit(app);
    ImGui::SameLine();
    if (button(app, "Inf##edge", "Infinitely sharp (10); in edge mode the selected edges at once")) {
        t.edgeSharpness = kInfiniteSharpness;
        if (edgeMode) creaseSelection(app, t.edgeSharpness);
    }
    if (button(app, "Crease edges", "Set the selected edges' sharpness to the value (Shift+E in edge mode)"))
        creaseSelection(app, t.edgeSharpness);
    ImGui::SameLine();
    if (button(app, "Clear##edges", "Remove the selected edges' creases (Alt+E in edge mode)")) creaseSelection(app, 0.0f);
    ImGui::SetNextItemWidth(150);
    if (sliderFloat(app, "Corner sharpness", &t.cornerSharpness, 0.0f, kInfiniteSharpness,
                    t.cornerSharpness >= kInfiniteSharpness ? "infinite" : "%.2f",
                    "Corner sharpness; in vertex mode the selected vertices follow it") &&
        vertexMode)
        cornerSelectionLive(app, t.cornerSharpness);
    if (ImGui::IsItemDeactivated()) endLiveEdit(app);
    ImGui::SameLine();
    if (button(app, "Inf##corner", "Infinitely sharp (10); in vertex mode the selected vertices at once")) {
        t.cornerSharpness = kInfiniteSharpness;
        if (vertexMode) cornerSelection(app, t.cornerSharpness);
    }
    if (button(app, "Set corners", "Set the selected vertices' corner sharpness (Shift+E in vertex mode)"))
        cornerSelection(app, t.cornerSharpness);
    ImGui::SameLine();
    if (button(app, "Clear##corners", "Remove the selected vertices' corners (Alt+E in vertex mode)")) cornerSelection(app, 0.0f);
    const bool chaikin = doc.planned && doc.planned->cage().options.creaseMethod == CreaseMethod::Chaikin;
    ImGui::TextUnformatted("Crease method");
    ImGui::SameLine();
    if (radio(app, "Normal##method", !chaikin, "OpenSubdiv's uniform crease rule (re-plans every face)"))
        setCreaseMethodTool(app, CreaseMethod::Normal);
    ImGui::SameLine();
    if (radio(app, "Chaikin##method", chaikin, "Chaikin: sharpness averaged along crease chains (re-plans every face)"))
        setCreaseMethodTool(app, CreaseMethod::Chaikin);
    if (button(app, "Make holes", "The selected faces get no surface (K toggles)")) setSelectionHoles(app, true);
    ImGui::SameLine();
    if (button(app, "Fill holes", "The selected hole faces get their surface back")) setSelectionHoles(app, false);
    ImGui::EndDisabled();
}

}  // namespace qp::editor
