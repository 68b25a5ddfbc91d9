// The parts of the editor's interface (panels.h), one concept per file: the side panel's
// sections (panels_model.cpp: selection, transforms, history; panels_mesh.cpp: mesh edits
// (interactive extrude, hide) and creases (live sliders);
// panels_sculpt.cpp; panels_scene.cpp: modes and the outliner; panels_display.cpp: display settings and statistics), the
// timeline strip (panels_timeline.cpp) and the windows and
// dialogs (panels_dialogs.cpp). Each draws into the current ImGui window.
#pragma once

namespace qp::editor {

struct EditorApp;

void toolsSection(EditorApp& app);
// Mesh: extrude (interactive), delete, holes, hide, loops, split, make face, merge.
void meshSection(EditorApp& app);
// Creases and corners: the sliders apply live to the selection (one entry per drag).
void creaseSection(EditorApp& app);
void historySection(EditorApp& app);
// Object and edit mode, the outliner, the selected object's transform (panels_scene.cpp).
void sceneSection(EditorApp& app);
void sculptSection(EditorApp& app);
void displaySection(EditorApp& app);
void statsSection(EditorApp& app);
// The timeline strip under the viewports (panels_timeline.cpp).
void timelineStrip(EditorApp& app);

void helpWindow(EditorApp& app);
void loadingWindow(EditorApp& app);
void jobWindow(EditorApp& app);  // an export or bake's progress
// Open, Save As, unsaved changes, restore after a crash, errors: modal popups opened through
// UiState::requestPopup. Enter answers with the first button, Esc with Cancel.
void dialogs(EditorApp& app);

}  // namespace qp::editor
