// The editor's Dear ImGui interface: menu bar, side panel (document, display, selection and
// crease tool, stats), a small settings bar in each viewport, the help window and the dialogs
// (open, save as, unsaved changes, restore after a crash, errors, loading progress).
//
// Buttons, check boxes and menu items go through wrappers that also answer the automation
// hook's `click-button LABEL` (so a replayed click runs the widget's own code) and record each
// widget's rectangle, which `dump-state` reports for tests that click with real X events.
#pragma once

namespace qp::editor {

struct EditorApp;

float menuBarHeight();    // window pixels
float sidePanelWidth();   // window pixels
float timelineHeight();   // window pixels: the strip under the viewports (panels_timeline.cpp)

void drawPanels(EditorApp& app);

}  // namespace qp::editor
