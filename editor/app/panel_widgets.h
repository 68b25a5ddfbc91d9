// The widgets every panel draws through (panels.h): each records its rectangle for tests
// (`dump-state` widgets), shows its tooltip and answers automation's `click-button LABEL`, so
// a replayed click runs the widget's own code. Labels follow ImGui: "Text##id" shows "Text".
#pragma once

#include <cstdint>
#include <string>

#include <glm/vec3.hpp>
#include <imgui.h>

namespace qp::editor {

struct EditorApp;
enum class DialogKey : uint8_t;

std::string visibleText(const char* label);
void recordWidget(EditorApp& app, const char* label);  // the last item's rectangle under `label`
bool pressedByAutomation(EditorApp& app, const char* label);  // consumed once
void tooltip(EditorApp& app, const char* label, const char* text);

bool button(EditorApp& app, const char* label, const char* help = nullptr);
bool checkbox(EditorApp& app, const char* label, bool* value, const char* help);
bool radio(EditorApp& app, const char* label, bool active, const char* help);
bool sliderFloat(EditorApp& app, const char* label, float* value, float lo, float hi, const char* format, const char* help,
                 ImGuiSliderFlags flags = 0);
bool inputFloat3(EditorApp& app, const char* label, glm::vec3* value, const char* help);
bool combo(EditorApp& app, const char* label, int* current, const char* const items[], int count, const char* help);
void menuAction(EditorApp& app, const char* id, bool enabled = true);  // a menu item running an action
bool actionButton(EditorApp& app, const char* label, const char* id);  // a button running an action
// A tab of the side panel (between ImGui::BeginTabBar and EndTabBar); `click-button` selects it.
// True while it is the open tab: then call ImGui::EndTabItem.
bool tabItem(EditorApp& app, const char* label, const char* help);
// Whether the key queue answered the dialog drawn now with `key` (consumed).
bool takeDialogKey(EditorApp& app, DialogKey key);

}  // namespace qp::editor
