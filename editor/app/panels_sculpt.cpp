#include "panel_sections.h"

#include <algorithm>

#include <imgui.h>

#include "editor_app.h"
#include "panel_widgets.h"
#include "tools.h"

namespace qp::editor {

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
        {"Raise", BrushKind::Raise, "Push the surface out along its normal (strength: height per dab, in radii; Ctrl: lower)"},
        {"Lower", BrushKind::Lower, "Push the surface in along its normal (Ctrl: raise)"},
        {"Smooth", BrushKind::Smooth, "Even out the displacement towards its neighbours' mean (Shift with any brush)"},
        {"Flatten", BrushKind::Flatten, "Pull the displaced surface towards the plane under the brush"},
        {"Erase", BrushKind::Erase, "Take the displacement back towards zero (strength 1, constant falloff: exactly 0)"},
        {"Inflate", BrushKind::Inflate, "Swell the displaced surface along its own normal: slopes move out too, so bumps grow fatter (Shift+I)"},
        {"Crease", BrushKind::Crease, "Cut a sharp V-shaped crease and pinch its sides together (strength: depth per dab, in radii; Shift+C)"},
        {"Mask", BrushKind::Mask, "Paint the mask: masked samples (dark dots) keep their displacement under every brush (M; Ctrl: unmask)"},
        {"Unmask", BrushKind::Unmask, "Take the mask away where you paint (Ctrl: mask)"}};
    for (size_t k = 0; k < std::size(kinds); ++k) {
        if (k % 5 != 0) ImGui::SameLine();  // two rows: the height brushes, then the rest
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
                "Raise, lower, inflate, crease: height per dab in brush radii; smooth, flatten, erase, mask, unmask: how far each dab blends (0..1)",
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
    if (button(app, "Invert mask", "Mask what is not masked and the other way round (Ctrl+I with the sculpt tool; one undo entry)"))
        invertMaskTool(app);
    ImGui::SameLine();
    if (button(app, "Clear mask", "Unmask everything (Alt+M; one undo entry)")) clearMaskTool(app);
    ImGui::SameLine();
    checkbox(app, "Show mask", &app.ui.showMask, "Dark dots where samples are masked (the darker, the more), while sculpting");
    const Displacement& d = displacementOf(doc);
    if (d.empty()) {
        ImGui::TextDisabled("No displacement yet: the first stroke makes one.");
    } else {
        ImGui::Text("%zu samples, %u cells per quad side", d.samples.size(), d.resolution());
    }
    if (!app.renderer.views.empty() && app.renderer.views[0].updatedSamples > 0)
        ImGui::Text("Last update: %u samples, %.2f ms", app.renderer.views[0].updatedSamples, app.renderer.views[0].displacementMs);
    ImGui::EndDisabled();
}
}  // namespace qp::editor
