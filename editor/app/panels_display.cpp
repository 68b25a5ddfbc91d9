#include "panel_sections.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <imgui.h>

#include "editor_app.h"
#include "panel_widgets.h"

namespace qp::editor {

void displaySection(EditorApp& app) {
    if (!ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const uint32_t n = uint32_t(app.viewports.size());
    ImGui::TextUnformatted("Viewports");
    ImGui::SameLine();
    if (radio(app, "1##views", n == 1, "One viewport (Ctrl+1)")) runAction(app, "layout.one");
    ImGui::SameLine();
    if (radio(app, "2##views", n == 2, "Two viewports side by side (Ctrl+2)")) runAction(app, "layout.two");
    ImGui::SameLine();
    if (radio(app, "4##views", n == 4, "Four viewports (Ctrl+4)")) runAction(app, "layout.four");

    DisplaySettings& d = app.display;
    ImGui::TextUnformatted("Shading");
    ImGui::SameLine();
    if (radio(app, "Studio", d.shading == Shading::Studio, "Fixed key and fill lights (saved in the scene)"))
        d.shading = Shading::Studio;
    ImGui::SameLine();
    if (radio(app, "Matcap", d.shading == Shading::Matcap,
              "A clay material lit from the viewer's upper left: the light turns with the camera (saved in the scene)"))
        d.shading = Shading::Matcap;
    const UpAxis up = upAxisOf(app);
    ImGui::TextUnformatted("Up axis");
    ImGui::SameLine();
    if (radio(app, "Y up", up == UpAxis::Y, "+Y is up: the grid lies in the xz plane, Numpad 1 looks along -z") &&
        up != UpAxis::Y)
        setUpAxis(app, UpAxis::Y);
    ImGui::SameLine();
    if (radio(app, "Z up", up == UpAxis::Z, "+Z is up (Blender): the grid lies in the xy plane, Numpad 1 looks along +y") &&
        up != UpAxis::Z)
        setUpAxis(app, UpAxis::Z);
    ImGui::SameLine();
    checkbox(app, "Grid", &d.showGrid, "The ground grid under the model (x axis red, y green, z blue)");

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
    ImGui::SameLine();
    checkbox(app, "Dense edges", &app.display.denseCageLines,
             "Draw the uncreased edges however short: by default a view leaves them out while they would draw\n"
             "shorter than 8 pixels near the camera (a dense cage seen whole), where they hide the surface\n"
             "and cost more to draw than it does; creases always show (saved in the scene)");
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
        // The whole cost side by side: the plan engine, then the frame that showed the edit.
        const EditorApp::EditFrame& shown = app.lastEditFrame;
        if (shown.frame == doc.lastEdit->frame) {
            ImGui::Text("  plan engine %.2f ms | its frame %.1f ms CPU%s", r.milliseconds, shown.cpuMs,
                        shown.intervalMs >= 0.0 ? (", " + std::to_string(int(std::lround(shown.intervalMs))) + " ms to the next").c_str() : "");
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("Plan engine: re-planning the faces the edit affects. Its frame: the CPU time of the frame\n"
                                  "that applied and drew the edit (input, UI, plan engine, every viewport's scheme update,\n"
                                  "recording), and the interval until the next frame started.");
        }
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
        if (counts.sampleCulled) {
            ImGui::TextDisabled("  %llu of them cover no pixel centre: left out", (unsigned long long)counts.sampleCulled);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("The CPU grid leaves out triangles that cannot make a pixel: the picture is the same,\n"
                                  "the rasteriser does less (docs/renderer.md, sample culling).");
        }
        if (counts.facingAway) {
            ImGui::TextDisabled("  %llu of them face away behind the front: left out", (unsigned long long)counts.facingAway);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("With a back-patch cull method on a closed surface seen from outside, the CPU grid also\n"
                                  "leaves out triangles facing away that no outline touches (docs/culling.md).");
        }
        // After the triangle lines, whose "of them" reads the line above.
        if (i < kMaxViewports && app.renderer.plainLinesHidden[i]) {
            ImGui::TextDisabled("  uncreased cage edges left out: under %.0f px here", double(kReadableEdgePixels));
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("Zoom in to see them, or tick Display > Dense edges to draw them however short.");
        }
        if (app.viewports[i].cull != CullMethod::None) {
            const CullCounts& c = counts.cull;
            ImGui::Text("  culled %llu of %llu: %llu off view, %llu facing away",
                        (unsigned long long)(c.frustum + c.backFacing), (unsigned long long)c.tested,
                        (unsigned long long)c.frustum, (unsigned long long)c.backFacing);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("%s: %llu patches could only be tested against the view (open or inside-out cage, eye inside,\n"
                                  "near plane through the surface, displaced or semi-sharp). Tests took %.2f ms on the CPU.",
                                  cullMethodName(app.viewports[i].cull), (unsigned long long)c.frustumOnly, counts.cullMilliseconds);
        }
        if (view && view->instance)
            ImGui::TextDisabled("  setup %.0f ms, update %.1f ms%s", view->setupMs, view->updateMs,
                                view->heat.valid ? (", heat map " + std::to_string(int(view->heat.lastMs)) + " ms").c_str() : "");
        if (view && !view->planUpdateNote.empty())
            ImGui::TextDisabled("  last edit: %s, %.1f ms", view->planUpdateNote.c_str(), view->planUpdateMs);
    }
    // What culling saves, measured: the frames drawn with and without it, side by side.
    const Summary culled = summarize(app.stats, FrameField::Gpu, 0, FrameFilter::SceneDrawnCulled);
    const Summary unculled = summarize(app.stats, FrameField::Gpu, 0, FrameFilter::SceneDrawnUnculled);
    if (culled.count > 0 && unculled.count > 0) {
        ImGui::Text("GPU %.1f ms culled, %.1f ms not", culled.median, unculled.median);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Medians of the GPU time of frames that drew the viewports, with some viewport culling (%zu frames)\n"
                              "and with none (%zu), over the last %zu frames: orbit with culling on and off to compare like with like.",
                              culled.count, unculled.count, FrameStats::kKept);
    } else if (culled.count + unculled.count > 0) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("What culling saves: orbit with culling on, then off, to measure it");
        ImGui::PopTextWrapPos();
    }
    ImGui::TextDisabled("%s", app.ctx.deviceName.c_str());
}
}  // namespace qp::editor
