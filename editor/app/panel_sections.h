// Side panel sections that live in their own files (panels.cpp draws the panel around them).
#pragma once

namespace qp::editor {

struct EditorApp;

// Mesh: extrude (interactive), delete, holes, hide, loops, split, make face, merge.
void meshSection(EditorApp& app);
// Creases and corners: the sliders apply live to the selection (one entry per drag).
void creaseSection(EditorApp& app);

}  // namespace qp::editor
