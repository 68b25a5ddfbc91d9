#include "panels.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "actions.h"
#include "editor_app.h"
#include "schemes.h"

namespace qp::editor {

namespace fs = std::filesystem;

namespace {

constexpr float kSidePanelWidth = 340.0f;

std::string visibleText(const char* label) {
    std::string text(label);
    return text.substr(0, text.find("##"));
}

void recordWidget(EditorApp& app, const char* label) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    app.ui.widgets.push_back({visibleText(label), {a.x, a.y, b.x - a.x, b.y - a.y}});
}

// Whether automation's `click-button` names this widget (consumed once).
bool pressedByAutomation(EditorApp& app, const char* label) {
    if (app.ui.pressLabel.empty() || app.ui.pressConsumed || visibleText(label) != app.ui.pressLabel) return false;
    app.ui.pressConsumed = true;
    return true;
}

void tooltip(const char* text) {
    if (text && text[0] && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

bool button(EditorApp& app, const char* label, const char* help = nullptr) {
    bool pressed = ImGui::Button(label);
    recordWidget(app, label);
    tooltip(help);
    return pressed || pressedByAutomation(app, label);
}

bool checkbox(EditorApp& app, const char* label, bool* value, const char* help = nullptr) {
    bool changed = ImGui::Checkbox(label, value);
    recordWidget(app, label);
    tooltip(help);
    if (!changed && pressedByAutomation(app, label)) {
        *value = !*value;
        changed = true;
    }
    return changed;
}

bool radio(EditorApp& app, const char* label, bool active, const char* help = nullptr) {
    bool pressed = ImGui::RadioButton(label, active);
    recordWidget(app, label);
    tooltip(help);
    return pressed || pressedByAutomation(app, label);
}

void menuAction(EditorApp& app, const char* id, bool enabled = true) {
    const ActionInfo* action = findAction(id);
    bool pressed = ImGui::MenuItem(action->label, action->shortcut, false, enabled);
    recordWidget(app, action->label);
    tooltip(action->help);
    if ((pressed || pressedByAutomation(app, action->label)) && enabled) runAction(app, id);
}

void menuBar(EditorApp& app) {
    if (!ImGui::BeginMainMenuBar()) return;
    const bool idle = !app.loader.busy();
    const bool undoAvailable = false;  // comes with the editing core's history
    if (ImGui::BeginMenu("File")) {
        menuAction(app, "file.open", idle);
        menuAction(app, "file.save", idle && app.doc->planned.has_value());
        menuAction(app, "file.save_as", idle && app.doc->planned.has_value());
        ImGui::Separator();
        menuAction(app, "file.quit");
        ImGui::EndMenu();
    }
    recordWidget(app, "File");
    if (ImGui::BeginMenu("Edit")) {
        menuAction(app, "edit.undo", undoAvailable);
        menuAction(app, "edit.redo", undoAvailable);
        ImGui::Separator();
        menuAction(app, "select.none");
        ImGui::EndMenu();
    }
    recordWidget(app, "Edit");
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
    if (!doc.path.empty()) tooltip(doc.path.c_str());
    if (doc.planned)
        ImGui::Text("%u vertices, %u faces", doc.planned->cage().vertexCount(), doc.planned->cage().faceCount());
    float seconds = float(app.options.autosaveSeconds);
    if (ImGui::SliderFloat("Autosave (s)", &seconds, 1.0f, 600.0f, "%.0f", ImGuiSliderFlags_Logarithmic))
        app.options.autosaveSeconds = seconds;
    tooltip(("While there are unsaved changes, they are written this often to\n" + app.recoveryDir +
             "/autosave.json and offered back after a crash.")
                .c_str());
}

void displaySection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const uint32_t n = uint32_t(app.viewports.size());
    ImGui::TextUnformatted("Viewports");
    ImGui::SameLine();
    if (radio(app, "1##views", n == 1, "One viewport (Ctrl+1)")) setViewportCount(app, 1);
    ImGui::SameLine();
    if (radio(app, "2##views", n == 2, "Two viewports side by side (Ctrl+2)")) setViewportCount(app, 2);
    ImGui::SameLine();
    if (radio(app, "4##views", n == 4, "Four viewports (Ctrl+4)")) setViewportCount(app, 4);

    Tessellation& t = app.tessellation;
    if (radio(app, "Uniform", t.mode == TessellationMode::Uniform, "The same number of segments on every face edge"))
        t.mode = TessellationMode::Uniform;
    ImGui::SameLine();
    if (radio(app, "Adaptive", t.mode == TessellationMode::Adaptive, "Segments sized to a target length on screen"))
        t.mode = TessellationMode::Adaptive;
    if (t.mode == TessellationMode::Uniform) {
        ImGui::SliderInt("Factor", &t.factor, 1, 64);
        tooltip("Segments per face edge");
    } else {
        ImGui::SliderFloat("Pixels", &t.pixelsPerEdge, 2.0f, 64.0f, "%.0f px");
        tooltip("Target on-screen length of one tessellation segment");
    }
    const char* paths[] = {"auto", "tessellated", "grid"};
    int path = int(app.requestedPath);
    if (ImGui::Combo("Draw path", &path, paths, 3)) {
        app.requestedPath = DrawPath(path);
        app.drawPath = resolveDrawPath(app.requestedPath, app.ctx);
    }
    tooltip("tessellated: one patch per sub-face through the tessellator (true adaptive factors);\n"
            "grid: a compute pass evaluates a uniform grid per sub-face (faster on CPU devices;\n"
            "adaptive mode then picks one factor per frame). auto: grid on CPU devices.");
    ImGui::Text("Drawing: %s path%s", drawPathName(app.drawPath),
                app.drawPath == DrawPath::Grid ? (", factor " + std::to_string(app.gridFactor)).c_str() : "");
    checkbox(app, "Cage overlay", &t.showCage, "The cage's edges; creases from yellow (soft) to red (infinitely sharp) (C)");
    checkbox(app, "Tessellation wireframe", &t.showWireframe, "Lines along the tessellated triangles (W)");
}

void selectionSection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Selection", ImGuiTreeNodeFlags_DefaultOpen)) return;
    Document& doc = *app.doc;
    if (!doc.planned) return;
    ImGui::BeginDisabled(app.loader.busy());
    const Cage& cage = doc.planned->cage();
    if (doc.selection.vertices.size() == 1) {
        const uint32_t v = doc.selection.vertices[0];
        ImGui::Text("Vertex %u", v);
        glm::vec3 p = cage.positions[v];
        ImGui::InputFloat3("Position", &p.x, "%.4f");
        tooltip("Type a new position; Enter applies it");
        if (ImGui::IsItemDeactivatedAfterEdit()) edit(app, MoveVertices{{v}, {p}});
    } else if (!doc.selection.vertices.empty()) {
        ImGui::Text("%zu vertices (drag one of them to move all)", doc.selection.vertices.size());
    }
    if (doc.selection.edge) {
        auto [a, b] = *doc.selection.edge;
        const float current = cage.edgeSharpness(a, b);
        ImGui::Text("Edge %u - %u, sharpness %s", a, b,
                    current >= kInfiniteSharpness ? "infinite" : std::to_string(current).substr(0, 4).c_str());
        ImGui::SliderFloat("Sharpness", &app.ui.sharpness, 0.0f, kInfiniteSharpness, "%.2f");
        tooltip("Semi-sharp crease value; 10 or more is infinitely sharp");
        if (button(app, "Apply sharpness", "Set the selected edge's sharpness to the slider's value"))
            edit(app, SetEdgeSharpness{a, b, app.ui.sharpness});
        ImGui::SameLine();
        if (button(app, "Infinite", "Make the selected edge infinitely sharp"))
            edit(app, SetEdgeSharpness{a, b, kInfiniteSharpness});
        ImGui::SameLine();
        if (button(app, "Clear crease", "Remove the selected edge's crease")) edit(app, SetEdgeSharpness{a, b, 0.0f});
    }
    if (doc.selection.empty()) ImGui::TextWrapped("Click near a vertex or an edge in a viewport to select it.");
    ImGui::EndDisabled();
}

void statsSection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Stats", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const Document& doc = *app.doc;
    if (doc.planned)
        ImGui::Text("Faces %u, sub-faces %u, unique plans %u", doc.planned->cage().faceCount(),
                    doc.planned->subfaceCount(), doc.database->size());
    if (doc.lastEdit) {
        const EditReport& r = doc.lastEdit->report;
        ImGui::TextWrapped("Last edit: %s", doc.lastEdit->description.c_str());
        ImGui::Text("  re-planned %u faces, %u new plans", r.replannedFaces, r.newPlans);
        ImGui::Text("  %u sub-faces updated, %.2f ms", r.updatedSubfaces, r.milliseconds);
    } else {
        ImGui::TextUnformatted("Last edit: none");
    }
    const Summary cpu = summarize(app.stats, FrameField::Cpu, 120);
    const Summary drawn = summarize(app.stats, FrameField::Gpu, 120, FrameFilter::SceneDrawn);
    const Summary copied = summarize(app.stats, FrameField::Gpu, 120, FrameFilter::SceneCopied);
    ImGui::Text("Frame CPU %.1f ms (median of %zu)", cpu.median, cpu.count);
    ImGui::Text("GPU %.1f ms with 3D (%zu), %.1f ms UI only (%zu)", drawn.median, drawn.count, copied.median, copied.count);
    tooltip("CPU: input, UI and recording up to submission. GPU: device time from timestamps, for frames\n"
            "that drew the viewports and for frames that only redrew the interface over the cached 3D.");
    for (size_t i = 0; i < app.stats.viewportCounts.size() && i < app.viewports.size(); ++i)
        ImGui::Text("View %zu: %llu triangles, %llu patches", i + 1,
                    (unsigned long long)app.stats.viewportCounts[i].triangles,
                    (unsigned long long)app.stats.viewportCounts[i].patches);
    ImGui::TextDisabled("%s", app.ctx.deviceName.c_str());
}

void sidePanel(EditorApp& app) {
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - kSidePanelWidth, menuBarHeight()));
    ImGui::SetNextWindowSize(ImVec2(kSidePanelWidth, io.DisplaySize.y - menuBarHeight()));
    ImGui::Begin("##side", nullptr,
                 ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                     ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
    documentSection(app);
    displaySection(app);
    selectionSection(app);
    statsSection(app);
    ImGui::Separator();
    ImGui::TextWrapped("%s", app.ui.status.c_str());
    ImGui::End();
}

void viewportBars(EditorApp& app) {
    const float scale = ImGui::GetIO().DisplayFramebufferScale.x > 0 ? ImGui::GetIO().DisplayFramebufferScale.x : 1.0f;
    for (size_t i = 0; i < app.viewports.size(); ++i) {
        ViewportState& v = app.viewports[i];
        ImGui::SetNextWindowPos(ImVec2(float(v.rect.offset.x) / scale + 6.0f, float(v.rect.offset.y) / scale + 6.0f));
        ImGui::SetNextWindowBgAlpha(0.55f);
        const std::string id = std::to_string(i);
        ImGui::Begin(("##viewport" + id).c_str(), nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                         ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove);
        ImGui::SetNextItemWidth(80.0f);
        if (ImGui::BeginCombo(("##scheme" + id).c_str(), v.scheme.c_str())) {
            for (const char* s : availableSchemes())
                if (ImGui::Selectable(s, v.scheme == s)) v.scheme = s;
            ImGui::EndCombo();
        }
        tooltip("Patching scheme drawn in this viewport");
        ImGui::SameLine();
        ImGui::SetNextItemWidth(100.0f);
        if (ImGui::BeginCombo(("##color" + id).c_str(), v.colorBy.c_str())) {
            for (const char* c : colorModeNames())
                if (ImGui::Selectable(c, v.colorBy == c)) v.colorBy = c;
            ImGui::EndCombo();
        }
        tooltip("Colour by: shading, node kind, plan depth or crease sharpness");
        // Narrow viewports get the bar on two lines, so it never covers its neighbour.
        if (float(v.rect.extent.width) / scale > 360.0f) ImGui::SameLine();
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
        if (!isSchemeAvailable(v.scheme))
            ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "Scheme '%s' is not available in this build", v.scheme.c_str());
        ImGui::End();
    }
}

void helpWindow(EditorApp& app) {
    if (!app.ui.showHelp) return;
    ImGui::SetNextWindowSize(ImVec2(620, 520), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowPos(ImVec2(60, 60), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Help", &app.ui.showHelp)) return ImGui::End();
    ImGui::TextUnformatted("Keyboard (when the pointer is not in a text field)");
    if (ImGui::BeginTable("keys", 3, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
        for (const ActionInfo& a : actions()) {
            if (!a.shortcut[0]) continue;
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(a.shortcut);
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(a.label);
            ImGui::TableNextColumn();
            ImGui::TextWrapped("%s", a.help);
        }
        ImGui::EndTable();
    }
    ImGui::Spacing();
    ImGui::TextUnformatted("Mouse, in a viewport");
    if (ImGui::BeginTable("mouse", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
        for (const MouseBinding& m : mouseBindings()) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(m.gesture);
            ImGui::TableNextColumn();
            ImGui::TextWrapped("%s", m.effect);
        }
        ImGui::EndTable();
    }
    ImGui::Spacing();
    ImGui::TextWrapped("Unsaved work is autosaved to %s/autosave.json and offered back at the next start "
                       "after a crash. Automation commands and file details: docs/editor.md.",
                       app.recoveryDir.c_str());
    ImGui::End();
}

void fileList(std::string& path) {
    fs::path dir = fs::path(path).has_filename() ? fs::path(path).parent_path() : fs::path(path);
    if (dir.empty()) dir = fs::current_path();
    std::error_code error;
    std::vector<fs::directory_entry> entries;
    for (const fs::directory_entry& e : fs::directory_iterator(dir, error)) {
        const std::string ext = e.path().extension().string();
        if (e.is_directory(error) || ext == ".json" || ext == ".obj") entries.push_back(e);
    }
    std::sort(entries.begin(), entries.end());
    ImGui::BeginChild("files", ImVec2(520, 220), true);
    if (ImGui::Selectable("..")) path = (dir.parent_path() / "").string();
    for (const fs::directory_entry& e : entries) {
        const bool isDir = e.is_directory(error);
        const std::string name = e.path().filename().string() + (isDir ? "/" : "");
        if (ImGui::Selectable(name.c_str(), path == e.path().string()))
            path = isDir ? (e.path() / "").string() : e.path().string();
    }
    ImGui::EndChild();
}

void dialogs(EditorApp& app) {
    if (!app.ui.requestPopup.empty()) {
        ImGui::OpenPopup(app.ui.requestPopup.c_str());
        app.ui.requestPopup.clear();
    }
    const ImVec2 centre(ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.5f);
    const ImGuiWindowFlags modal = ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings;

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Open", nullptr, modal)) {
        app.ui.openPopups.push_back("Open");
        ImGui::SetNextItemWidth(520);
        ImGui::InputText("##openpath", &app.ui.openPath);
        fileList(app.ui.openPath);
        if (button(app, "Open", "Open this scene or cage")) {
            ImGui::CloseCurrentPopup();
            requestOpen(app, app.ui.openPath);
        }
        ImGui::SameLine();
        if (button(app, "Cancel")) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Save As", nullptr, modal)) {
        app.ui.openPopups.push_back("Save As");
        ImGui::SetNextItemWidth(520);
        ImGui::InputText("##savepath", &app.ui.saveAsPath);
        ImGui::TextDisabled(".json saves the scene (settings and cage); .obj saves the cage alone");
        std::error_code error;
        const bool exists = fs::exists(app.ui.saveAsPath, error);
        if (button(app, exists ? "Overwrite" : "Save", "Write the file (atomically: a crash never leaves half a file)")) {
            if (saveTo(app, app.ui.saveAsPath)) {
                ImGui::CloseCurrentPopup();
                if (app.ui.continuePendingAfterSave) continuePending(app);
            }
        }
        ImGui::SameLine();
        if (button(app, "Cancel")) {
            ImGui::CloseCurrentPopup();
            app.ui.pending = PendingAction{};
            app.ui.continuePendingAfterSave = false;
        }
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Unsaved changes", nullptr, modal)) {
        app.ui.openPopups.push_back("Unsaved changes");
        ImGui::Text("%s has unsaved changes.", documentTitle(*app.doc).c_str());
        ImGui::TextUnformatted(app.ui.pending.kind == PendingAction::Quit ? "Save them before quitting?"
                                                                          : "Save them before opening another file?");
        if (button(app, "Save", "Save, then continue")) {
            ImGui::CloseCurrentPopup();
            if (app.doc->path.empty()) {
                app.ui.continuePendingAfterSave = true;
                runAction(app, "file.save_as");
            } else if (saveTo(app, app.doc->path)) {
                continuePending(app);
            }
        }
        ImGui::SameLine();
        if (button(app, "Discard changes", "Continue and lose the unsaved changes")) {
            ImGui::CloseCurrentPopup();
            continuePending(app);
        }
        ImGui::SameLine();
        if (button(app, "Cancel")) {
            ImGui::CloseCurrentPopup();
            app.ui.pending = PendingAction{};
        }
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Restore unsaved work?", nullptr, modal)) {
        app.ui.openPopups.push_back("Restore unsaved work?");
        if (app.ui.recovery) {
            ImGui::TextUnformatted("The last session ended without saving its changes.");
            ImGui::Text("Autosaved %s from %s.", app.ui.recovery->savedAt.c_str(),
                        app.ui.recovery->source.empty() ? "an untitled document" : app.ui.recovery->source.c_str());
        }
        if (button(app, "Restore", "Open the autosaved work (still unsaved: save it to keep it)")) {
            ImGui::CloseCurrentPopup();
            restoreRecovery(app);
        }
        ImGui::SameLine();
        if (button(app, "Discard", "Delete the autosaved work")) {
            ImGui::CloseCurrentPopup();
            discardRecovery(app);
        }
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Error", nullptr, modal)) {
        app.ui.openPopups.push_back("Error");
        ImGui::PushTextWrapPos(520);
        ImGui::TextUnformatted(app.ui.errorMessage.c_str());
        ImGui::PopTextWrapPos();
        if (button(app, "OK")) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
}

void loadingWindow(EditorApp& app) {
    if (!app.loader.busy()) return;
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2((io.DisplaySize.x - kSidePanelWidth) * 0.5f, io.DisplaySize.y * 0.5f),
                            ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Loading", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse);
    ImGui::Text("%s", app.loader.request().fromRecovery ? "recovered work" : app.loader.request().path.c_str());
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%s... %.1f s", app.loader.stage().c_str(), app.loader.secondsRunning());
    ImGui::ProgressBar(app.loader.fraction(), ImVec2(360, 0), overlay);
    ImGui::End();
}

}  // namespace

float menuBarHeight() { return ImGui::GetFrameHeight(); }
float sidePanelWidth() { return kSidePanelWidth; }

void drawPanels(EditorApp& app) {
    app.ui.widgets.clear();
    app.ui.openPopups.clear();
    menuBar(app);
    viewportBars(app);
    sidePanel(app);
    helpWindow(app);
    loadingWindow(app);
    dialogs(app);
}

}  // namespace qp::editor
