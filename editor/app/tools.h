// The editing tools: picking and selecting in a viewport, transforms, topology edits, creases,
// holes, undo and redo. Key shortcuts (actions.cpp), panel buttons, mouse input and the
// automation hook all call these, so every way in drives the same code. Each reports a failure
// in the UI (status line and error dialog) and returns whether it changed anything.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "edit/selection.h"
#include "edit/transform.h"

namespace qp::editor {

struct EditorApp;

// ---- picking (cursor and corners in framebuffer pixels) --------------------------------------

struct PickHit {
    SelectionMode mode = SelectionMode::Vertex;
    uint32_t element = UINT32_MAX;  // vertex or face
    EdgeKey edge;
    float edgeT = 0.5f;             // edges: where along v0 -> v1 the cursor is
    bool hit = false;
};
// The element of the current selection mode under the cursor (vertices within 12 px, edges
// within 8 px, faces: the face whose limit patch is under the cursor, or the cage face),
// skipping what the limit surface hides unless ToolSettings::visibleOnly is off.
PickHit pickAt(EditorApp& app, uint32_t viewport, glm::vec2 cursor);
// The edge under the cursor whatever the mode (the loop tool).
PickHit pickEdgeAt(EditorApp& app, uint32_t viewport, glm::vec2 cursor);
void applyPickHit(EditorApp& app, const PickHit& hit, SelectOp op);
// Per cage vertex: whether a click can pick it in the viewport (in front of the camera and, with
// ToolSettings::visibleOnly, not hidden by the limit surface). For the automation's state dump.
std::vector<bool> pickableVertices(EditorApp& app, uint32_t viewport);
// Alt+click (Blender): the edge loop (or ring) through the edge under the cursor in edge mode,
// its vertices in vertex mode, the face loop across it in face mode; hidden elements left out.
enum class LoopKind { Loop, Ring };
bool selectLoopAt(EditorApp& app, uint32_t viewport, glm::vec2 cursor, LoopKind kind, SelectOp op);
void boxSelectIn(EditorApp& app, uint32_t viewport, glm::vec2 cornerA, glm::vec2 cornerB, SelectOp op);

void setMode(EditorApp& app, SelectionMode mode);
void selectAllElements(EditorApp& app);
void invertSelectedElements(EditorApp& app);
void growSelected(EditorApp& app);
void shrinkSelected(EditorApp& app);

// ---- transforms ------------------------------------------------------------------------------

// The frame a transform of the selection uses: its centroid, world or local axes.
std::optional<TransformFrame> selectionFrame(const EditorApp& app);
enum class NumericTransform { Move, Rotate, Scale };
// Moves by `values` (in the frame's axes), rotates by values.w degrees about the axis
// values.xyz (in the frame's axes), or scales by `values` (factors), about the centroid.
bool transformSelection(EditorApp& app, NumericTransform kind, const glm::vec4& values);

// ---- topology, tags, history -----------------------------------------------------------------

bool extrudeSelection(EditorApp& app);       // selected faces, by ToolSettings::extrudeDistance
bool deleteSelection(EditorApp& app);        // selected faces (vertices/edges: the faces they span)
bool splitSelection(EditorApp& app);         // two selected vertices of one face
bool insertLoop(EditorApp& app, uint32_t a, uint32_t b, float t);
bool loopOnSelectedEdge(EditorApp& app);     // at ToolSettings::loopFraction
bool mergeSelection(EditorApp& app);         // selected vertices (or the ends of selected edges)
bool makeFaceFromSelection(EditorApp& app);  // selected vertices, ordered around their centre
bool creaseSelection(EditorApp& app, float sharpness);  // selected edges
bool cornerSelection(EditorApp& app, float sharpness);  // selected vertices
// The same from a slider being dragged: the first change makes an entry, later ones (until
// endLiveEdit, when the drag ends) replace it, so one drag is one undo entry.
bool creaseSelectionLive(EditorApp& app, float sharpness);
bool cornerSelectionLive(EditorApp& app, float sharpness);
void endLiveEdit(EditorApp& app);
bool setSelectionHoles(EditorApp& app, bool hole);      // selected faces
bool toggleSelectionHoles(EditorApp& app);
// H / Alt+H: hide the selected faces (vertex and edge modes: the faces they span) / show all.
bool hideSelection(EditorApp& app);
void unhideAllFaces(EditorApp& app);
bool setCreaseMethodTool(EditorApp& app, CreaseMethod method);
bool undoTool(EditorApp& app);
bool redoTool(EditorApp& app);
bool jumpHistoryTool(EditorApp& app, size_t position);

}  // namespace qp::editor
