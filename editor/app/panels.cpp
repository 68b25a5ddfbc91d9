#include "panels.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "actions.h"
#include "document_objects.h"
#include "editor_app.h"
#include "panel_sections.h"
#include "panel_widgets.h"

namespace qp::editor {

namespace fs = std::filesystem;

namespace {

constexpr float kSidePanelWidth = 380.0f;


void menuBar(EditorApp& app) {
    if (!ImGui::BeginMainMenuBar()) return;
    const bool idle = !app.loader.busy() && !app.job.busy();
    const bool haveCage = idle && app.doc->planned.has_value();
    if (ImGui::BeginMenu("File")) {
        menuAction(app, "file.open", idle);
        menuAction(app, "file.save", haveCage);
        menuAction(app, "file.save_as", haveCage);
        ImGui::Separator();
        menuAction(app, "file.import", haveCage);
        menuAction(app, "file.export", haveCage);
        menuAction(app, "file.bake", haveCage);
        ImGui::Separator();
        menuAction(app, "file.quit");
        ImGui::EndMenu();
    }
    recordWidget(app, "File");
    if (ImGui::BeginMenu("Edit")) {
        menuAction(app, "edit.undo", haveCage && app.doc->history.canUndo());
        menuAction(app, "edit.redo", haveCage && app.doc->history.canRedo());
        menuAction(app, "edit.history");
        ImGui::EndMenu();
    }
    recordWidget(app, "Edit");
    if (ImGui::BeginMenu("Select")) {
        for (const char* id : {"select.vertex_mode", "select.edge_mode", "select.face_mode"}) menuAction(app, id, haveCage);
        ImGui::Separator();
        for (const char* id : {"select.all", "select.none", "select.invert", "select.grow", "select.shrink"})
            menuAction(app, id, haveCage);
        ImGui::Separator();
        for (const char* id : {"tool.select", "tool.move", "tool.rotate", "tool.scale", "tool.sculpt", "tool.space"})
            menuAction(app, id);
        ImGui::EndMenu();
    }
    recordWidget(app, "Select");
    if (ImGui::BeginMenu("Mesh")) {
        for (const char* id : {"mesh.extrude", "mesh.delete", "mesh.split", "mesh.loop_tool", "mesh.loop", "mesh.merge",
                               "mesh.make_face", "mesh.hole", "mesh.hide", "mesh.unhide", "crease.apply", "crease.clear"})
            menuAction(app, id, haveCage);
        ImGui::EndMenu();
    }
    recordWidget(app, "Mesh");
    if (ImGui::BeginMenu("Object")) {
        menuAction(app, "mode.toggle", haveCage);
        ImGui::Separator();
        const bool objectMode = haveCage && app.mode == EditorMode::Object;
        for (const char* id : {"object.duplicate", "object.instance", "object.delete", "object.hide", "object.unhide",
                               "object.deselect"})
            menuAction(app, id, objectMode);
        ImGui::EndMenu();
    }
    recordWidget(app, "Object");
    if (ImGui::BeginMenu("Animation")) {
        for (const char* id : {"anim.play", "anim.prev_frame", "anim.next_frame", "anim.first_frame", "anim.last_frame",
                               "anim.prev_key", "anim.next_key", "anim.loop"})
            menuAction(app, id, haveCage);
        ImGui::Separator();
        menuAction(app, "anim.insert_key", haveCage);
        menuAction(app, "anim.delete_keys", haveCage);
        menuAction(app, "anim.interpolation", haveCage);
        ImGui::EndMenu();
    }
    recordWidget(app, "Animation");
    if (ImGui::BeginMenu("View")) {
        for (const char* id : {"view.front", "view.back", "view.right", "view.left", "view.top", "view.bottom",
                               "view.projection"})
            menuAction(app, id);
        ImGui::Separator();
        menuAction(app, "view.frame");
        menuAction(app, "view.frame_all");
        ImGui::Separator();
        menuAction(app, "layout.one");
        menuAction(app, "layout.two");
        menuAction(app, "layout.four");
        ImGui::EndMenu();
    }
    recordWidget(app, "View");
    if (ImGui::BeginMenu("Display")) {
        menuAction(app, "display.cage");
        menuAction(app, "display.wireframe");
        menuAction(app, "view.heatmap");
        ImGui::EndMenu();
    }
    recordWidget(app, "Display");
    if (ImGui::BeginMenu("Help")) {
        menuAction(app, "help.toggle");
        ImGui::EndMenu();
    }
    recordWidget(app, "Help");
    ImGui::EndMainMenuBar();
}


void documentSection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Document", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const Document& doc = *app.doc;
    ImGui::Text("%s%s", doc.path.empty() ? "untitled" : fs::path(doc.path).filename().c_str(),
                doc.dirty ? "  (unsaved changes)" : "");
    if (!doc.path.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", doc.path.c_str());
    if (doc.planned)
        ImGui::Text("%u vertices, %u faces", doc.planned->cage().vertexCount(), doc.planned->cage().faceCount());
    float seconds = float(app.options.autosaveSeconds);
    if (sliderFloat(app, "Autosave (s)", &seconds, 1.0f, 600.0f, "%.0f",
                    "While there are unsaved changes, they are written this often to the recovery\n"
                    "directory (autosave.json) and offered back after a crash.",
                    ImGuiSliderFlags_Logarithmic))
        app.options.autosaveSeconds = seconds;
}


// Which mode the editor is in and what it acts on, whatever tab is open.
void modeLine(const EditorApp& app) {
    const Document& doc = *app.doc;
    if (!doc.planned) return;
    const ImVec4 colour(1.0f, 0.75f, 0.35f, 1.0f);
    if (app.mode == EditorMode::Object) {
        const uint32_t object = selectedObject(doc);
        ImGui::TextColored(colour, "Object mode: %s (Tab edits its cage)",
                           object == kNoObject ? "no object selected" : doc.scene.objects[object].name.c_str());
    } else if (doc.scene.objects.size() > 1) {
        ImGui::TextColored(colour, "Edit mode: %s (Tab: object mode)", activeObject(doc).name.c_str());
    }
}

void sidePanel(EditorApp& app) {
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - kSidePanelWidth, menuBarHeight()));
    ImGui::SetNextWindowSize(ImVec2(kSidePanelWidth, io.DisplaySize.y - menuBarHeight()));
    // NoNavInputs: Tab belongs to the editor (object / edit mode), not to ImGui's focus tabbing,
    // which would otherwise put the keyboard into the panel's first text field.
    ImGui::Begin("##side", nullptr,
                 ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                     ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoNavInputs);
    ImGui::PushItemWidth(-90.0f);
    documentSection(app);
    ImGui::Separator();
    ImGui::TextWrapped("%s", app.ui.status.c_str());
    modeLine(app);
    // Tabs, so that every section is reachable at 1280x800 without scrolling past the others.
    if (ImGui::BeginTabBar("##sidetabs")) {
        if (tabItem(app, "Model", "Select and transform, mesh edits, creases and corners")) {
            toolsSection(app);
            meshSection(app);
            creaseSection(app);
            ImGui::EndTabItem();
        }
        if (tabItem(app, "Scene##tab", "Object and edit mode (Tab), the outliner, the selected object's transform")) {
            sceneSection(app);
            ImGui::EndTabItem();
        }
        if (tabItem(app, "Sculpt##tab", "The sculpt brush and the displacement")) {
            sculptSection(app);
            ImGui::EndTabItem();
        }
        if (tabItem(app, "View##tab", "Viewports, shading, up axis, grid, tessellation; statistics")) {
            displaySection(app);
            statsSection(app);
            ImGui::EndTabItem();
        }
        if (app.ui.showHistory && tabItem(app, "History##tab", "Undo, redo and the list of edits (Ctrl+H shows or hides this tab)")) {
            historySection(app);
            ImGui::EndTabItem();
        }
        ImGui::EndTabBar();
    }
    app.ui.selectTab.clear();
    ImGui::PopItemWidth();
    ImGui::End();
}


void viewportBars(EditorApp& app) {
    const float scale = ImGui::GetIO().DisplayFramebufferScale.x > 0 ? ImGui::GetIO().DisplayFramebufferScale.x : 1.0f;
    for (size_t i = 0; i < app.viewports.size(); ++i) {
        ViewportState& v = app.viewports[i];
        const SchemeView* view = i < app.renderer.views.size() ? &app.renderer.views[i] : nullptr;
        ImGui::SetNextWindowPos(ImVec2(float(v.rect.offset.x) / scale + 6.0f, float(v.rect.offset.y) / scale + 6.0f));
        ImGui::SetNextWindowBgAlpha(0.55f);
        const std::string id = std::to_string(i);
        ImGui::Begin(("##viewport" + id).c_str(), nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                         ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove);
        ImGui::PushTextWrapPos(std::max(200.0f, float(v.rect.extent.width) / scale - 30.0f));
        ImGui::SetNextItemWidth(90.0f);
        const std::string schemeCombo = "##scheme" + id;
        if (ImGui::BeginCombo(schemeCombo.c_str(), v.scheme.c_str())) {
            for (const auto& plugin : app.catalog.plugins) {
                if (ImGui::Selectable(plugin->name.c_str(), v.scheme == plugin->name)) v.scheme = plugin->name;
                if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", plugin->summary.c_str());
            }
            ImGui::EndCombo();
        }
        recordWidget(app, schemeCombo.c_str());
        tooltip(app, schemeCombo.c_str(), "Patching scheme drawn in this viewport (the loaded plugins)");
        ImGui::SameLine();
        ImGui::SetNextItemWidth(100.0f);
        const std::string colorCombo = "##color" + id;
        const std::vector<std::string> modes = view ? view->colorModes : std::vector<std::string>{"shading"};
        // What is drawn: the chosen mode when this scheme offers it, else its first.
        const bool offered = std::find(modes.begin(), modes.end(), v.colorBy) != modes.end();
        const std::string shown = offered ? v.colorBy : modes.front();
        if (ImGui::BeginCombo(colorCombo.c_str(), shown.c_str())) {
            for (const std::string& c : modes)
                if (ImGui::Selectable(c.c_str(), shown == c)) v.colorBy = c;
            ImGui::EndCombo();
        }
        recordWidget(app, colorCombo.c_str());
        tooltip(app, colorCombo.c_str(), "Colour by: the modes this scheme offers (plans on its GPU paths: node kind, plan depth, sharpness)");
        ImGui::SameLine();
        ImGui::SetNextItemWidth(80.0f);
        const std::string cullCombo = "##cull" + id;
        if (ImGui::BeginCombo(cullCombo.c_str(), v.cull == CullMethod::None ? "no cull" : cullMethodName(v.cull))) {
            for (CullMethod m : {CullMethod::None, CullMethod::Frustum, CullMethod::TCone, CullMethod::NCone, CullMethod::PPlane})
                if (ImGui::Selectable(m == CullMethod::None ? "no cull" : cullMethodName(m), v.cull == m)) v.cull = m;
            ImGui::EndCombo();
        }
        // Recorded under a name tests can find (the combo itself shows only the method).
        const std::string cullName = "Culling " + std::to_string(i + 1);
        recordWidget(app, cullName.c_str());
        tooltip(app, cullName.c_str(),
                "Culling: skip patches that cannot show a pixel (the picture stays the same). frustum: outside the view; "
                "tcone, ncone, pplane: also those facing away on a closed surface, each test tighter and costlier "
                "(docs/culling.md). The Stats panel shows what was culled.");
        ImGui::SameLine();
        checkbox(app, ("Error##heat" + id).c_str(), &v.heatMap,
                 "Heat map: this scheme's distance from the exact limit surface, relative to the cage's size (Shift+H)");
        // Narrow viewports get the bar on two lines, so it never covers its neighbour.
        if (float(v.rect.extent.width) / scale > 430.0f) ImGui::SameLine();
        bool linked = v.linked;
        if (checkbox(app, ("Linked##" + id).c_str(), &linked, "Share the camera with the other linked viewports")) {
            if (!linked) v.camera = app.sharedCamera;
            else app.sharedCamera = v.camera;
            v.linked = linked;
        }
        ImGui::SameLine();
        ViewCamera& camera = cameraOf(app, uint32_t(i));
        if (button(app, ((camera.orthographic ? "Ortho##" : "Persp##") + id).c_str(),
                   "Toggle perspective / orthographic (Numpad 5)"))
            camera.orthographic = !camera.orthographic;
        if (view && !view->problem.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", view->problem.c_str());
        if (view && !view->drawProblem.empty())
            ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", view->drawProblem.c_str());
        if (view)
            for (const std::string& warning : view->support.approximations)
                ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "! %s", warning.c_str());
        if (view && view->instance && !app.doc->hiddenFaces.empty() && !view->instance->hidesSubfaces())
            ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "! %s draws hidden faces too (only their cage is hidden)",
                               view->built.name.c_str());
        ImGui::PopTextWrapPos();
        ImGui::End();
    }
}
}  // namespace

float menuBarHeight() { return ImGui::GetFrameHeight(); }
float sidePanelWidth() { return kSidePanelWidth; }

void drawPanels(EditorApp& app) {
    app.ui.widgets.clear();
    app.ui.tooltips.clear();
    app.ui.openPopups.clear();
    // An export or bake reads the document's cages: nothing may change them until it is done.
    const bool working = app.job.busy();
    ImGui::BeginDisabled(working);
    menuBar(app);
    viewportBars(app);
    sidePanel(app);
    timelineStrip(app);
    ImGui::EndDisabled();
    helpWindow(app);
    loadingWindow(app);
    jobWindow(app);
    dialogs(app);
}

}  // namespace qp::editor
