#include "panel_widgets.h"

#include <string>

#include "actions.h"
#include "editor_app.h"

namespace qp::editor {

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

// Every tool widget goes through these: a tooltip, its rectangle for tests, automation presses.
void tooltip(EditorApp& app, const char* label, const char* text) {
    if (!text || !text[0]) return;
    app.ui.tooltips.push_back(visibleText(label));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

bool button(EditorApp& app, const char* label, const char* help) {
    bool pressed = ImGui::Button(label);
    recordWidget(app, label);
    tooltip(app, label, help);
    return pressed || pressedByAutomation(app, label);
}

bool checkbox(EditorApp& app, const char* label, bool* value, const char* help) {
    bool changed = ImGui::Checkbox(label, value);
    recordWidget(app, label);
    tooltip(app, label, help);
    if (!changed && pressedByAutomation(app, label)) {
        *value = !*value;
        changed = true;
    }
    return changed;
}

bool radio(EditorApp& app, const char* label, bool active, const char* help) {
    bool pressed = ImGui::RadioButton(label, active);
    recordWidget(app, label);
    tooltip(app, label, help);
    return pressed || pressedByAutomation(app, label);
}

bool sliderFloat(EditorApp& app, const char* label, float* value, float lo, float hi, const char* format, const char* help,
                 ImGuiSliderFlags flags) {
    bool changed = ImGui::SliderFloat(label, value, lo, hi, format, flags);
    recordWidget(app, label);
    tooltip(app, label, help);
    return changed;
}

bool inputFloat3(EditorApp& app, const char* label, glm::vec3* value, const char* help) {
    bool changed = ImGui::InputFloat3(label, &value->x, "%.4g");
    recordWidget(app, label);
    tooltip(app, label, help);
    return changed;
}

bool combo(EditorApp& app, const char* label, int* current, const char* const items[], int count, const char* help) {
    bool changed = ImGui::Combo(label, current, items, count);
    recordWidget(app, label);
    tooltip(app, label, help);
    return changed;
}

void menuAction(EditorApp& app, const char* id, bool enabled) {
    const ActionInfo* action = findAction(id);
    bool pressed = ImGui::MenuItem(action->label, action->shortcut, false, enabled);
    recordWidget(app, action->label);
    tooltip(app, action->label, action->help);
    if ((pressed || pressedByAutomation(app, action->label)) && enabled) runAction(app, id);
}

// A button running an action: its label and the action's shortcut and help.
bool actionButton(EditorApp& app, const char* label, const char* id) {
    const ActionInfo* action = findAction(id);
    std::string help = action->help;
    if (action->shortcut[0]) help += std::string(" (") + action->shortcut + ")";
    if (!button(app, label, help.c_str())) return false;
    runAction(app, id);
    return true;
}

bool tabItem(EditorApp& app, const char* label, const char* help) {
    const bool pressed = pressedByAutomation(app, label) || (!app.ui.selectTab.empty() && visibleText(label) == app.ui.selectTab);
    const bool open = ImGui::BeginTabItem(label, nullptr, pressed ? ImGuiTabItemFlags_SetSelected : 0);
    recordWidget(app, label);
    tooltip(app, label, help);
    return open;
}

bool takeDialogKey(EditorApp& app, DialogKey key) {
    if (app.ui.dialogKey != key) return false;
    app.ui.dialogKey = DialogKey::None;
    return true;
}

}  // namespace qp::editor
