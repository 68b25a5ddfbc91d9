#include "panel_sections.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "actions.h"
#include "editor_app.h"
#include "panel_widgets.h"
#include "panels.h"

namespace qp::editor {

namespace fs = std::filesystem;

namespace {


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

}  // namespace



void helpWindow(EditorApp& app) {
    if (!app.ui.showHelp) return;
    ImGui::SetNextWindowSize(ImVec2(720, 600), ImGuiCond_FirstUseEver);
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
    ImGui::TextWrapped("Selection: Shift adds, Ctrl removes, Ctrl+Shift toggles (clicks and boxes). Only what the limit "
                       "surface leaves visible is picked unless 'Select hidden' is on. In face mode a click picks the face "
                       "whose limit patch is under the cursor.");
    ImGui::TextWrapped("Handles (W, E, R): drag an axis (red x, green y, blue z) or the white centre handle; hold Ctrl to "
                       "snap (moves to a power of ten, 15 degrees, scale steps of 0.1); right click or Esc cancels. One drag "
                       "is one undo entry. Numeric entry is in the side panel, in world or local axes (L).");
    ImGui::TextWrapped("Every edit re-plans only the faces it affects; the Stats panel shows how many and how long. "
                       "The heat map (Error check box, Shift+H) colours a viewport's scheme by its distance from the exact "
                       "limit surface relative to the cage's bounding-box diagonal, on the log scale shown.");
    ImGui::Spacing();
    ImGui::TextWrapped("Unsaved work is autosaved to %s/autosave.json and offered back at the next start "
                       "after a crash. Automation commands and file details: docs/editor.md.",
                       app.recoveryDir.c_str());
    ImGui::End();
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
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();  // type the path at once
        ImGui::InputText("##openpath", &app.ui.openPath);
        fileList(app.ui.openPath);
        if (button(app, "Open", "Open this scene or cage (Enter)") || takeDialogKey(app, DialogKey::Confirm)) {
            ImGui::CloseCurrentPopup();
            requestOpen(app, app.ui.openPath);
        }
        ImGui::SameLine();
        if (button(app, "Cancel", "Close without opening (Esc)") || takeDialogKey(app, DialogKey::Cancel))
            ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Save As", nullptr, modal)) {
        app.ui.openPopups.push_back("Save As");
        ImGui::SetNextItemWidth(520);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        ImGui::InputText("##savepath", &app.ui.saveAsPath);
        ImGui::TextDisabled(".json saves the scene (settings and cage); .obj or .om saves the cage alone");
        std::error_code error;
        const bool exists = fs::exists(app.ui.saveAsPath, error);
        if (button(app, exists ? "Overwrite" : "Save", "Write the file (atomically: a crash never leaves half a file; Enter)") ||
            takeDialogKey(app, DialogKey::Confirm)) {
            if (saveTo(app, app.ui.saveAsPath)) {
                ImGui::CloseCurrentPopup();
                if (app.ui.continuePendingAfterSave) continuePending(app);
            }
        }
        ImGui::SameLine();
        if (button(app, "Cancel", "Close without saving (Esc)") || takeDialogKey(app, DialogKey::Cancel)) {
            ImGui::CloseCurrentPopup();
            app.ui.pending = PendingAction{};
            app.ui.continuePendingAfterSave = false;
        }
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Export", nullptr, modal)) {
        app.ui.openPopups.push_back("Export");
        ImGui::SetNextItemWidth(520);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        ImGui::InputText("##exportpath", &app.ui.exportPath);
        ImGui::TextDisabled("The exact limit surface, welded (watertight where the cage is closed): .glb / .gltf (a node per\nobject, instances share a mesh), or .obj, .ply, .off, .stl (objects merged)");
        ExportOptions& options = app.ui.exportOptions;
        int factor = int(options.factor);
        ImGui::SetNextItemWidth(120);
        if (ImGui::InputInt("Segments per sub-face edge", &factor)) options.factor = uint32_t(std::clamp(factor, 1, 64));
        checkbox(app, "Displaced", &options.displaced, "Apply the sculpted displacement");
        ImGui::SameLine();
        checkbox(app, "One file per object", &options.split, "NAME_OBJECT.EXT for each visible object (formats without nodes)");
        int uv = int(options.uv);
        ImGui::SetNextItemWidth(120);
        if (ImGui::Combo("Texture coordinates", &uv, "None\0Linear\0Smooth\0")) options.uv = UvMode(uv);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("The cage's UVs, split along seams: Linear bilinear over each face, Smooth OpenSubdiv's face-varying limit");
        if (button(app, "Export##dialog", "Write the file (atomically; Enter)") || takeDialogKey(app, DialogKey::Confirm)) {
            if (exportTo(app, app.ui.exportPath)) ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (button(app, "Cancel", "Close without exporting (Esc)") || takeDialogKey(app, DialogKey::Cancel))
            ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Import", nullptr, modal)) {
        app.ui.openPopups.push_back("Import");
        ImGui::SetNextItemWidth(520);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        ImGui::InputText("##importpath", &app.ui.importPath);
        fileList(app.ui.importPath);
        ImGui::TextDisabled("A cage (.obj, .om, .ply, .off, .stl) becomes one object; a scene (.json) adds all of its objects");
        if (button(app, "Import##dialog", "Add the file's objects to this scene (one undo step; Enter)") ||
            takeDialogKey(app, DialogKey::Confirm)) {
            if (addObjectFromFile(app, app.ui.importPath)) ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (button(app, "Cancel", "Close without importing (Esc)") || takeDialogKey(app, DialogKey::Cancel))
            ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Bake", nullptr, modal)) {
        app.ui.openPopups.push_back("Bake");
        ImGui::SetNextItemWidth(520);
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        ImGui::InputText("##bakepath", &app.ui.bakePath);
        ImGui::TextDisabled("The sculpted displacement as a 32-bit float OpenEXR map (.exr) in the cage's UV space;\n"
                            "several sculpted objects give NAME_OBJECT.exr each");
        BakeOptions& options = app.ui.bakeOptions;
        int sizeIndex = options.size <= 512 ? 0 : options.size <= 1024 ? 1 : options.size <= 2048 ? 2 : 3;
        ImGui::SetNextItemWidth(120);
        if (ImGui::Combo("Size", &sizeIndex, "512\0" "1024\0" "2048\0" "4096\0")) options.size = 512u << sizeIndex;
        ImGui::SameLine();
        int uv = options.uv == UvMode::Smooth ? 1 : 0;
        ImGui::SetNextItemWidth(120);
        if (ImGui::Combo("UVs", &uv, "Linear\0Smooth\0")) options.uv = uv ? UvMode::Smooth : UvMode::Linear;
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Linear: the cage's UVs bilinear over each face; Smooth: OpenSubdiv's face-varying limit");
        int padding = int(options.padding);
        ImGui::SetNextItemWidth(120);
        if (ImGui::InputInt("Padding (texels)", &padding)) options.padding = uint32_t(std::clamp(padding, 0, 64));
        ImGui::SetNextItemWidth(520);
        ImGui::InputText("Normal map (.png, optional)", &app.ui.bakeNormalMapPath);
        recordWidget(app, "Normal map (.png, optional)");
        if (button(app, "Bake##dialog", "Write the map (atomically; Enter)") || takeDialogKey(app, DialogKey::Confirm)) {
            if (bakeTo(app, app.ui.bakePath)) ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (button(app, "Cancel", "Close without baking (Esc)") || takeDialogKey(app, DialogKey::Cancel))
            ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Unsaved changes", nullptr, modal)) {
        app.ui.openPopups.push_back("Unsaved changes");
        ImGui::Text("%s has unsaved changes.", documentTitle(*app.doc).c_str());
        ImGui::TextUnformatted(app.ui.pending.kind == PendingAction::Quit ? "Save them before quitting?"
                                                                          : "Save them before opening another file?");
        if (button(app, "Save", "Save, then continue (Enter)") || takeDialogKey(app, DialogKey::Confirm)) {
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
        if (button(app, "Cancel", "Go back to the document (Esc)") || takeDialogKey(app, DialogKey::Cancel)) {
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
        if (button(app, "Restore", "Open the autosaved work (still unsaved: save it to keep it; Enter)") ||
            takeDialogKey(app, DialogKey::Confirm)) {
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
        if (button(app, "OK", "Close (Enter or Esc)") || takeDialogKey(app, DialogKey::Confirm) ||
            takeDialogKey(app, DialogKey::Cancel))
            ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    app.ui.dialogKey = DialogKey::None;  // a key no dialog took (the dialog closed meanwhile)
}

void loadingWindow(EditorApp& app) {
    if (!app.loader.busy()) return;
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2((io.DisplaySize.x - sidePanelWidth()) * 0.5f, io.DisplaySize.y * 0.5f),
                            ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Loading", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse);
    ImGui::Text("%s", app.loader.request().fromRecovery ? "recovered work" : app.loader.request().path.c_str());
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%s... %.1f s", app.loader.stage().c_str(), app.loader.secondsRunning());
    ImGui::ProgressBar(app.loader.fraction(), ImVec2(360, 0), overlay);
    ImGui::End();
}

void jobWindow(EditorApp& app) {
    if (!app.job.busy()) return;
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2((io.DisplaySize.x - sidePanelWidth()) * 0.5f, io.DisplaySize.y * 0.5f),
                            ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Working", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse);
    ImGui::TextUnformatted(app.job.title().c_str());
    char overlay[160];
    std::snprintf(overlay, sizeof overlay, "%s... %.1f s", app.job.stage().c_str(), app.job.secondsRunning());
    ImGui::ProgressBar(app.job.fraction(), ImVec2(420, 0), overlay);
    ImGui::TextDisabled("Edits wait until it is done");
    ImGui::SameLine();
    if (button(app, "Cancel##job", "Stop it: nothing is written (a file being written is finished first)")) app.job.cancel();
    ImGui::End();
}
}  // namespace qp::editor
