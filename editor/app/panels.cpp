#include "panels.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "actions.h"
#include "editor_app.h"
#include "panel_sections.h"
#include "panel_widgets.h"
#include "tools.h"

namespace qp::editor {

namespace fs = std::filesystem;

namespace {

constexpr float kSidePanelWidth = 380.0f;

void menuBar(EditorApp& app) {
    if (!ImGui::BeginMainMenuBar()) return;
    const bool idle = !app.loader.busy();
    const bool haveCage = idle && app.doc->planned.has_value();
    if (ImGui::BeginMenu("File")) {
        menuAction(app, "file.open", idle);
        menuAction(app, "file.save", haveCage);
        menuAction(app, "file.save_as", haveCage);
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

const char* modeName(SelectionMode mode) {
    return mode == SelectionMode::Vertex ? "vertices" : mode == SelectionMode::Edge ? "edges" : "faces";
}

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


void sculptSection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Sculpt", ImGuiTreeNodeFlags_DefaultOpen)) return;
    SculptSettings& s = app.tools.sculpt;
    Document& doc = *app.doc;
    ImGui::BeginDisabled(app.loader.busy() || !doc.planned);
    if (radio(app, "Sculpt tool", app.tools.tool == Tool::Sculpt,
              "Left drag on the surface paints with this brush (B); Ctrl: raise <-> lower, Shift: smooth"))
        app.tools.tool = Tool::Sculpt;
    struct KindButton {
        const char* label;
        BrushKind kind;
        const char* help;
    };
    const KindButton kinds[] = {
        {"Raise", BrushKind::Raise, "Push the surface out along its normal (strength: height per dab, in radii)"},
        {"Lower", BrushKind::Lower, "Push the surface in along its normal"},
        {"Smooth", BrushKind::Smooth, "Even out the displacement towards its neighbours' mean"},
        {"Flatten", BrushKind::Flatten, "Pull the displaced surface towards the plane under the brush"},
        {"Erase", BrushKind::Erase, "Take the displacement back towards zero (strength 1, constant falloff: exactly 0)"}};
    for (size_t k = 0; k < std::size(kinds); ++k) {
        if (k > 0) ImGui::SameLine();
        if (radio(app, kinds[k].label, s.kind == kinds[k].kind, kinds[k].help)) s.kind = kinds[k].kind;
    }
    float percent = s.radius * 100.0f;
    ImGui::SetNextItemWidth(200);
    if (sliderFloat(app, "Radius", &percent, 0.1f, 50.0f, "%.1f%% of size",
                    "Brush radius, in percent of the model's bounding-box diagonal ([ and ] change it)",
                    ImGuiSliderFlags_Logarithmic))
        s.radius = std::clamp(percent, 0.1f, 50.0f) / 100.0f;
    ImGui::SetNextItemWidth(200);
    sliderFloat(app, "Strength", &s.strength, 0.001f, 1.0f, "%.3f",
                "Raise / lower: height per dab in brush radii; smooth, flatten, erase: how far each dab blends (0..1)",
                ImGuiSliderFlags_Logarithmic);
    const char* falloffs[] = {"smooth", "linear", "constant", "sphere"};
    int falloff = int(s.falloff);
    ImGui::SetNextItemWidth(200);
    if (combo(app, "Falloff", &falloff, falloffs, 4, "How the brush's weight fades from the centre to the rim"))
        s.falloff = Falloff(falloff);
    const char* mirrors[] = {"none", "x", "y", "z"};
    int mirror = int(s.mirror);
    ImGui::SetNextItemWidth(200);
    if (combo(app, "Mirror", &mirror, mirrors, 4,
              "Each dab also acts at its mirror image across this axis's plane through the model's centre"))
        s.mirror = MirrorAxis(mirror);
    const char* resolutions[] = {"1", "2", "4", "8", "16", "32", "64"};
    int level = 0;
    while ((1u << level) < s.resolution && level < 6) ++level;
    ImGui::SetNextItemWidth(80);
    if (combo(app, "##resolution", &level, resolutions, 7,
              "Samples per sub-face edge: of a new displacement (the first stroke makes one), and what Apply sets"))
        s.resolution = 1u << std::clamp(level, 0, 6);
    ImGui::SameLine();
    if (button(app, "Apply resolution",
               "Resample every tile at this resolution (the shape stays; the tessellation follows it; one undo entry)"))
        applyDisplacementResolution(app);
    ImGui::SameLine();
    if (button(app, "Clear##displacement", "Remove the displacement (one undo entry)")) clearDisplacementTool(app);
    const Displacement& d = doc.scene.displacement;
    if (d.empty()) {
        ImGui::TextDisabled("No displacement yet: the first stroke makes one.");
    } else {
        uint32_t lo = UINT32_MAX, hi = 0;
        for (const DisplacementSubface& t : d.layout.subfaces) lo = std::min(lo, t.resolution), hi = std::max(hi, t.resolution);
        ImGui::Text("%zu samples, tiles %u..%u", d.samples.size(), lo, hi);
    }
    if (!app.renderer.views.empty() && app.renderer.views[0].updatedSamples > 0)
        ImGui::Text("Last update: %u samples, %.2f ms", app.renderer.views[0].updatedSamples, app.renderer.views[0].displacementMs);
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
        recordWidget(app, "Factor");
        tooltip(app, "Factor", "Segments per face edge");
    } else {
        sliderFloat(app, "Pixels", &t.pixelsPerEdge, 2.0f, 64.0f, "%.0f px", "Target on-screen length of one tessellation segment");
    }
    const char* paths[] = {"auto", "tess", "grid", "cpu"};
    int path = int(std::find(std::begin(paths), std::end(paths), app.plansPath) - std::begin(paths));
    if (ImGui::Combo("Plans path", &path, paths, 4)) app.plansPath = paths[std::clamp(path, 0, 3)];
    recordWidget(app, "Plans path");
    tooltip(app, "Plans path",
            "How the plans scheme draws: tess: one patch per sub-face through the tessellator (per-edge adaptive);\n"
            "grid: a compute pass evaluates a grid every frame; cpu: the CPU evaluator fills a grid on every core once\n"
            "per edit (camera moves only draw, drags re-evaluate only the sub-faces they touch).\n"
            "auto: cpu on a CPU device (lavapipe: fastest, docs/editor.md), tess on a GPU.");
    std::string factors;
    for (const ViewportState& v : app.viewports) factors += (factors.empty() ? "" : ", ") + std::to_string(v.factor);
    ImGui::Text("Factor per view: %s", factors.c_str());
    checkbox(app, "Cage overlay", &t.showCage, "The cage's edges; creases from yellow (soft) to red (infinitely sharp) (C)");
    checkbox(app, "Tessellation wireframe", &t.showWireframe, "Lines along the tessellated triangles (Shift+W)");
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
        ImGui::Text("  re-planned %u faces in %.2f ms", r.replannedFaces, r.milliseconds);
        ImGui::Text("  %u new plans, %u sub-faces updated", r.newPlans, r.updatedSubfaces);
    } else {
        ImGui::TextUnformatted("Last edit: none");
    }
    ImGui::Text("Scheme updates %.1f ms (last change)", app.renderer.lastSyncMs);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Scheme rebuilds or updates after the last change, heat maps and cage lines, on the UI thread");
    const Summary cpu = summarize(app.stats, FrameField::Cpu, 120);
    const Summary drawn = summarize(app.stats, FrameField::Gpu, 120, FrameFilter::SceneDrawn);
    const Summary copied = summarize(app.stats, FrameField::Gpu, 120, FrameFilter::SceneCopied);
    ImGui::Text("Frame CPU %.1f ms (median of %zu)", cpu.median, cpu.count);
    ImGui::Text("GPU %.1f ms with 3D (%zu), %.1f ms UI only (%zu)", drawn.median, drawn.count, copied.median, copied.count);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("CPU: input, UI, scheme updates and recording up to submission. GPU: device time from timestamps,\n"
                          "for frames that drew the viewports and for frames that only redrew the interface.");
    for (size_t i = 0; i < app.viewports.size(); ++i) {
        const SchemeView* view = i < app.renderer.views.size() ? &app.renderer.views[i] : nullptr;
        const ViewportCounts counts = i < app.stats.viewportCounts.size() ? app.stats.viewportCounts[i] : ViewportCounts{};
        ImGui::Text("View %zu %s: %llu triangles, %llu patches", i + 1, app.viewports[i].scheme.c_str(),
                    (unsigned long long)counts.triangles, (unsigned long long)counts.patches);
        if (view && view->instance)
            ImGui::TextDisabled("  setup %.0f ms, update %.1f ms%s", view->setupMs, view->updateMs,
                                view->heat.valid ? (", heat map " + std::to_string(int(view->heat.lastMs)) + " ms").c_str() : "");
    }
    ImGui::TextDisabled("%s", app.ctx.deviceName.c_str());
}

void sidePanel(EditorApp& app) {
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - kSidePanelWidth, menuBarHeight()));
    ImGui::SetNextWindowSize(ImVec2(kSidePanelWidth, io.DisplaySize.y - menuBarHeight()));
    ImGui::Begin("##side", nullptr,
                 ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                     ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
    ImGui::PushItemWidth(-90.0f);
    documentSection(app);
    toolsSection(app);
    sculptSection(app);
    meshSection(app);
    creaseSection(app);
    historySection(app);
    displaySection(app);
    statsSection(app);
    ImGui::PopItemWidth();
    ImGui::Separator();
    ImGui::TextWrapped("%s", app.ui.status.c_str());
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
        if (view)
            for (const std::string& warning : view->support.approximations)
                ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "! %s", warning.c_str());
        ImGui::PopTextWrapPos();
        ImGui::End();
    }
}

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
    app.ui.tooltips.clear();
    app.ui.openPopups.clear();
    menuBar(app);
    viewportBars(app);
    sidePanel(app);
    helpWindow(app);
    loadingWindow(app);
    dialogs(app);
}

}  // namespace qp::editor
