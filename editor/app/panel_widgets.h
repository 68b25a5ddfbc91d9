// The side panel's widgets: every tool widget goes through these, so each has a tooltip, its
// rectangle recorded for tests (UiState::widgets) and can be pressed by automation's
// `click-button` (by its visible label, the text before "##").
#pragma once

#include <string>

#include <glm/vec3.hpp>
#include <imgui.h>

namespace qp::editor {

struct EditorApp;

std::string visibleText(const char* label);
void recordWidget(EditorApp& app, const char* label);
// Whether automation's `click-button` names this widget (consumed once).
bool pressedByAutomation(EditorApp& app, const char* label);
void tooltip(EditorApp& app, const char* label, const char* text);

bool button(EditorApp& app, const char* label, const char* help = nullptr);
bool checkbox(EditorApp& app, const char* label, bool* value, const char* help);
bool radio(EditorApp& app, const char* label, bool active, const char* help);
bool sliderFloat(EditorApp& app, const char* label, float* value, float lo, float hi, const char* format, const char* help,
                 ImGuiSliderFlags flags = 0);
bool inputFloat3(EditorApp& app, const char* label, glm::vec3* value, const char* help);
bool combo(EditorApp& app, const char* label, int* current, const char* const items[], int count, const char* help);
// A menu item running an action (its label, shortcut and help from the action table).
void menuAction(EditorApp& app, const char* id, bool enabled = true);
// A button running an action: its label and the action's shortcut and help.
bool actionButton(EditorApp& app, const char* label, const char* id);

}  // namespace qp::editor
