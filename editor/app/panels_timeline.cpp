// The timeline strip under the viewports (issue 22): transport buttons, the frame slider with the
// key marks of the object the timeline follows (playback.h keyMarks), the frame range and rate
// (stored in the scene, one history entry per change), the rate achieved while playing, Insert
// key / Delete keys, and the interpolation of the object the timeline follows (one history entry
// per change). Always shown, so that a scene without keys can start an animation.
#include <algorithm>
#include <cmath>
#include <optional>

#include <imgui.h>

#include "document_animation.h"
#include "editor_app.h"
#include "panel_sections.h"
#include "panel_widgets.h"
#include "panels.h"
#include "playback.h"

namespace qp::editor {

namespace {

const ImU32 kKeyMarkColour = IM_COL32(255, 200, 60, 255);

// Small yellow diamonds under the slider where the keys are, at the grab's centre for that
// value (ImGui 1.86's SliderBehavior geometry: 2 px padding, a grab of GrabMinSize or larger).
void drawKeyMarks(const std::vector<int32_t>& keys, int first, int last) {
    const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    const float padding = 2.0f, size = hi.x - lo.x - 2.0f * padding;
    const int frames = last - first + 1;
    const float grab = std::max(size / float(std::max(frames, 1)), ImGui::GetStyle().GrabMinSize);
    const float usable = size - grab, start = lo.x + padding + 0.5f * grab;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (int32_t k : keys) {
        if (k < first || k > last) continue;
        const float along = float(k - first) / float(frames - 1);
        const float x = start + along * usable, y = hi.y - 4.0f;
        draw->AddQuadFilled(ImVec2(x, y - 3.5f), ImVec2(x + 3.5f, y), ImVec2(x, y + 3.5f), ImVec2(x - 3.5f, y), kKeyMarkColour);
    }
}

void transportRow(EditorApp& app, const Timeline& t) {
    Document& doc = *app.doc;
    if (button(app, "|<##anim", "First frame (Shift+Left)")) runAction(app, "anim.first_frame");
    ImGui::SameLine();
    if (button(app, "<##anim", "Previous frame (Left); Down: the previous key")) runAction(app, "anim.prev_frame");
    ImGui::SameLine();
    if (button(app, doc.playing ? "Pause##anim" : "Play##anim", "Play or pause at the timeline's frame rate (Space)"))
        runAction(app, "anim.play");
    ImGui::SameLine();
    if (button(app, ">##anim", "Next frame (Right); Up: the next key")) runAction(app, "anim.next_frame");
    ImGui::SameLine();
    if (button(app, ">|##anim", "Last frame (Shift+Right)")) runAction(app, "anim.last_frame");
    ImGui::SameLine();
    checkbox(app, "Loop##anim", &doc.loopPlayback, "Playback starts again at the first frame after the last (else it stops there)");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1.0f);
    int frame = int(std::lround(doc.currentFrame));
    const int last = std::max(t.lastFrame, t.firstFrame + 1);  // a slider needs two values
    // A scene without keys says so on the slider (the row below has no room left at 1280 px).
    const bool scrubbed =
        ImGui::SliderInt("##frame", &frame, t.firstFrame, last, isAnimated(doc.scene) ? "frame %d" : "frame %d (no keys yet)");
    recordWidget(app, "Timeline");  // under a visible name: dump-state's widgets are keyed by it
    tooltip(app, "Timeline", "Drag to scrub; the marks are the keys of the edited cage (object mode: the selected object)");
    drawKeyMarks(keyMarks(app), t.firstFrame, last);
    if (scrubbed) {
        pausePlayback(app);
        showFrameAt(app, frame);
    }
}

// A whole number typed into the range fields; Enter applies it as a history entry. The caption
// goes before the field, so that each number reads with its own name.
void rangeField(EditorApp& app, const char* caption, const char* label, int value, bool first, const char* help) {
    ImGui::TextUnformatted(caption);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(52.0f);
    ImGui::InputInt(label, &value, 0, 0);
    recordWidget(app, caption);
    tooltip(app, caption, help);
    if (!ImGui::IsItemDeactivatedAfterEdit()) return;
    Timeline t = documentTimeline(*app.doc);
    (first ? t.firstFrame : t.lastFrame) = value;
    if (Status done = setTimeline(*app.doc, t, app.frame); !done) app.ui.status = "Timeline: " + done.error().message;
}

// Linear or Catmull-Rom between the keys of the object the timeline follows (edit mode: the
// edited cage; object mode: the selected object, disabled without one).
void interpolationCombo(EditorApp& app) {
    static const char* const kNames[] = {"Linear", "Catmull-Rom"};
    const std::optional<Interpolation> now = timelineInterpolation(app);
    int current = now == Interpolation::CatmullRom ? 1 : 0;
    ImGui::TextUnformatted("Interpolation");
    ImGui::SameLine();
    ImGui::BeginDisabled(!now);
    ImGui::SetNextItemWidth(ImGui::CalcTextSize("Catmull-Rom").x + ImGui::GetFrameHeight() + 2.0f * ImGui::GetStyle().FramePadding.x);
    const bool changed = ImGui::Combo("##interpolation", &current, kNames, 2);
    ImGui::EndDisabled();
    recordWidget(app, "Interpolation");
    tooltip(app, "Interpolation",
            "How keys are interpolated between their frames: linearly, or by Catmull-Rom (a smooth curve through "
            "the keys). The edited cage's vertex and transform keys (object mode: the selected object's); saved "
            "with the scene, undoable");
    if (changed && now) setInterpolationTool(app, current == 1 ? Interpolation::CatmullRom : Interpolation::Linear);
}

void settingsRow(EditorApp& app, const Timeline& t) {
    Document& doc = *app.doc;
    ImGui::AlignTextToFramePadding();
    ImGui::Text("Frame %-5g", doc.currentFrame);
    ImGui::SameLine();
    rangeField(app, "Start", "##start", t.firstFrame, true, "The first frame played (Enter applies; saved with the scene, undoable)");
    ImGui::SameLine();
    rangeField(app, "End", "##end", t.lastFrame, false, "The last frame played (Enter applies; saved with the scene, undoable)");
    ImGui::SameLine();
    float fps = float(t.framesPerSecond);
    ImGui::TextUnformatted("FPS");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(52.0f);
    ImGui::InputFloat("##fps", &fps, 0, 0, "%g");
    recordWidget(app, "FPS");
    tooltip(app, "FPS", "Frames per second played (Enter applies; saved with the scene, undoable)");
    if (ImGui::IsItemDeactivatedAfterEdit()) {
        Timeline changed = t;
        changed.framesPerSecond = fps;
        if (Status done = setTimeline(doc, changed, app.frame); !done) app.ui.status = "Timeline: " + done.error().message;
    }
    ImGui::SameLine();
    if (app.playback.fpsAchieved > 0.0) ImGui::Text("%5.1f fps", app.playback.fpsAchieved);
    else ImGui::TextDisabled("  -- fps");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Frames shown per second while playing (the last second; kept after a pause)");
    ImGui::SameLine();
    const bool objectMode = app.mode == EditorMode::Object;
    if (button(app, "Insert key##anim",
               objectMode ? "Key the selected object's transform at this frame (I)"
                          : "Key the selected vertices (all when none) where they are, at this frame (I)"))
        runAction(app, "anim.insert_key");
    ImGui::SameLine();
    if (button(app, "Delete keys##anim", "Remove the keys at this frame (Alt+I)")) runAction(app, "anim.delete_keys");
    ImGui::SameLine();
    interpolationCombo(app);
}

}  // namespace

float timelineHeight() {
    const ImGuiStyle& style = ImGui::GetStyle();
    return 2.0f * ImGui::GetFrameHeight() + style.ItemSpacing.y + 2.0f * style.WindowPadding.y;
}

void timelineStrip(EditorApp& app) {
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0.0f, io.DisplaySize.y - timelineHeight()));
    ImGui::SetNextWindowSize(ImVec2(std::max(io.DisplaySize.x - sidePanelWidth(), 1.0f), timelineHeight()));
    // NoNavInputs: the arrows belong to the timeline's shortcuts, not to ImGui's focus.
    ImGui::Begin("##timeline", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                     ImGuiWindowFlags_NoNavInputs | ImGuiWindowFlags_NoFocusOnAppearing);
    if (app.doc->planned) {
        const Timeline t = documentTimeline(*app.doc);
        transportRow(app, t);
        settingsRow(app, t);
    }
    ImGui::End();
}

}  // namespace qp::editor
