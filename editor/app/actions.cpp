#include "actions.h"

#include <algorithm>

#include <GLFW/glfw3.h>

namespace qp::editor {

namespace {

// Component modes, select all/none/invert and grow/shrink follow Blender; the transform tools
// (Q, W, E, R) and frame (F) follow Maya. docs/editor.md lists them too.
const ActionInfo kActions[] = {
    {"file.open", "Open...", "Ctrl+O", {GLFW_KEY_O, true}, "Open a scene (.json) or a cage (.obj, .om, .ply, .off, .stl)"},
    {"file.save", "Save", "Ctrl+S", {GLFW_KEY_S, true}, "Save to the current file (asks for a name when untitled)"},
    {"file.save_as", "Save As...", "Ctrl+Shift+S", {GLFW_KEY_S, true, true}, "Save to a new file (.json scene, or the cage as .obj or .om)"},
    {"file.import", "Import...", "", {}, "Add the objects of a scene (.json) or a cage file (.obj, .om, .ply, .off, .stl) to this scene"},
    {"file.export", "Export...", "", {}, "Export the limit surface as a welded, watertight mesh (.glb, .gltf, .obj, .ply, .off, .stl)"},
    {"file.bake", "Bake Displacement...", "", {}, "Bake the sculpted displacement into an OpenEXR map in UV space (and a normal map)"},
    {"file.quit", "Quit", "Ctrl+Q", {GLFW_KEY_Q, true}, "Close the editor (asks before losing unsaved changes)"},
    {"edit.undo", "Undo", "Ctrl+Z", {GLFW_KEY_Z, true}, "Undo the last edit (camera changes are not edits)"},
    {"edit.redo", "Redo", "Ctrl+Shift+Z / Ctrl+Y", {GLFW_KEY_Z, true, true}, "Redo the edit undone last", {GLFW_KEY_Y, true}},
    {"edit.history", "History panel", "Ctrl+H", {GLFW_KEY_H, true}, "Show or hide the list of edits (click one to go back or forward to it)"},
    {"select.vertex_mode", "Vertex mode", "1 / F9", {GLFW_KEY_1}, "Select vertices (the selection is converted)", {GLFW_KEY_F9}},
    {"select.edge_mode", "Edge mode", "2 / F10", {GLFW_KEY_2}, "Select edges (the selection is converted)", {GLFW_KEY_F10}},
    {"select.face_mode", "Face mode", "3 / F11", {GLFW_KEY_3}, "Select faces (the selection is converted)", {GLFW_KEY_F11}},
    {"select.all", "Select all", "A", {GLFW_KEY_A}, "Select every vertex, edge or face (of the current mode)"},
    {"select.none", "Deselect all", "Alt+A / Esc", {GLFW_KEY_A, false, false, true}, "Clear the selection (Esc also cancels a drag or the loop tool)", {GLFW_KEY_ESCAPE}},
    {"select.invert", "Invert selection", "Ctrl+I", {GLFW_KEY_I, true}, "Select what is not selected, and the other way round"},
    {"select.grow", "Grow selection", "Ctrl+Numpad + / >", {GLFW_KEY_KP_ADD, true}, "Add the neighbours of the selection", {GLFW_KEY_PERIOD, false, true}},
    {"select.shrink", "Shrink selection", "Ctrl+Numpad - / <", {GLFW_KEY_KP_SUBTRACT, true}, "Drop the selection's border", {GLFW_KEY_COMMA, false, true}},
    {"tool.select", "Select tool", "Q", {GLFW_KEY_Q}, "Left button selects: click, or drag a box (also from on the surface; nothing moves)"},
    {"tool.move", "Move tool", "W", {GLFW_KEY_W}, "Show the move handle: drag an arrow along its axis, the centre square or any element in the view plane"},
    {"tool.rotate", "Rotate tool", "E", {GLFW_KEY_E}, "Show the rotate handle: drag a ring about its axis, the outer ring about the view direction"},
    {"tool.scale", "Scale tool", "R", {GLFW_KEY_R}, "Show the scale handle: drag a box along its axis, the centre box to scale evenly"},
    {"tool.sculpt", "Sculpt tool", "B", {GLFW_KEY_B}, "Left drag paints with the brush of the Sculpt panel on the displaced surface (Ctrl: raise <-> lower, mask <-> unmask; Shift: smooth)"},
    {"sculpt.smaller", "Smaller brush", "[", {GLFW_KEY_LEFT_BRACKET}, "Shrink the sculpt brush's radius by a fifth"},
    {"sculpt.larger", "Larger brush", "]", {GLFW_KEY_RIGHT_BRACKET}, "Grow the sculpt brush's radius by a quarter"},
    // With the sculpt tool these keys win over the same keys' edit-mode actions (merge, invert
    // selection), which they serve with any other tool.
    {"brush.mask", "Mask brush", "M (sculpt tool)", {GLFW_KEY_M}, "Paint the mask: masked samples keep their displacement under every brush (Ctrl: unmask)"},
    {"brush.invert_mask", "Invert mask", "Ctrl+I (sculpt tool)", {GLFW_KEY_I, true}, "Mask what is not masked and the other way round (one undo entry)"},
    {"brush.clear_mask", "Clear mask", "Alt+M", {GLFW_KEY_M, false, false, true}, "Unmask everything (one undo entry)"},
    {"brush.inflate", "Inflate brush", "Shift+I (sculpt tool)", {GLFW_KEY_I, false, true}, "Swell the displaced surface along its own normal (its slopes move out too, so bumps grow fatter)"},
    {"brush.crease", "Crease brush", "Shift+C (sculpt tool)", {GLFW_KEY_C, false, true}, "Cut a sharp V-shaped crease, pinching its sides together"},
    {"tool.space", "World / local axes", "L", {GLFW_KEY_L}, "Toggle the handle's and the numeric entry's axes: world, or local (the selection's normal is z)"},
    {"mesh.extrude", "Extrude faces", "Ctrl+E", {GLFW_KEY_E, true}, "Extrude the selected faces interactively: the mouse sets the distance along their normal (or type it), click or Enter confirms, Esc or right click cancels"},
    {"mesh.delete", "Delete faces", "Delete / Backspace", {GLFW_KEY_DELETE}, "Delete the selected faces (vertices no other face uses go too)", {GLFW_KEY_BACKSPACE}},
    {"mesh.split", "Split face", "J", {GLFW_KEY_J}, "Split a face along a new edge between the two selected vertices"},
    {"mesh.loop_tool", "Insert edge loop", "Ctrl+R", {GLFW_KEY_R, true}, "Loop tool: the next click on an edge cuts a loop across its quads there (Esc cancels)"},
    {"mesh.loop", "Loop on selected edge", "", {}, "Insert an edge loop across the selected edge at the fraction in the Mesh panel"},
    {"mesh.merge", "Merge vertices", "M", {GLFW_KEY_M}, "Merge the selected vertices into one (at their centre, or at the last one)"},
    {"mesh.make_face", "Make face", "Shift+F", {GLFW_KEY_F, false, true}, "Make a face through the selected vertices (ordered around their centre)"},
    {"mesh.hole", "Toggle holes", "K", {GLFW_KEY_K}, "Make the selected faces holes (no surface), or fill them when all are holes"},
    {"mesh.hide", "Hide faces", "H", {GLFW_KEY_H}, "Hide the selected faces (not drawn, not pickable; a view only: not an edit, not saved)"},
    {"mesh.unhide", "Unhide all", "Alt+H", {GLFW_KEY_H, false, false, true}, "Show every hidden face again"},
    {"crease.apply", "Crease", "Shift+E", {GLFW_KEY_E, false, true}, "Edge mode: set the selected edges' sharpness; vertex mode: the corner sharpness (values in the Creases panel)"},
    {"crease.clear", "Clear crease", "Alt+E", {GLFW_KEY_E, false, false, true}, "Remove the creases of the selected edges, or the corners of the selected vertices"},
    {"view.frame", "Frame selection", "F", {GLFW_KEY_F}, "Frame the selection, or the whole model when nothing is selected"},
    {"view.frame_all", "Frame all", "Home", {GLFW_KEY_HOME}, "Frame the whole model"},
    {"view.front", "Front", "Numpad 1", {GLFW_KEY_KP_1}, "Look at the front (from +Z)"},
    {"view.back", "Back", "Ctrl+Numpad 1", {GLFW_KEY_KP_1, true}, "Look at the back (from -Z)"},
    {"view.right", "Right", "Numpad 3", {GLFW_KEY_KP_3}, "Look at the right side (from +X)"},
    {"view.left", "Left", "Ctrl+Numpad 3", {GLFW_KEY_KP_3, true}, "Look at the left side (from -X)"},
    {"view.top", "Top", "Numpad 7", {GLFW_KEY_KP_7}, "Look down from above (from +Y)"},
    {"view.bottom", "Bottom", "Ctrl+Numpad 7", {GLFW_KEY_KP_7, true}, "Look up from below (from -Y)"},
    {"view.projection", "Perspective / orthographic", "Numpad 5", {GLFW_KEY_KP_5}, "Toggle the projection of the active viewport"},
    {"view.heatmap", "Error heat map", "Shift+H", {GLFW_KEY_H, false, true}, "Show the active viewport's scheme coloured by its distance from the exact limit surface"},
    {"layout.one", "One viewport", "Ctrl+1", {GLFW_KEY_1, true}, "Show one viewport"},
    {"layout.two", "Two viewports", "Ctrl+2", {GLFW_KEY_2, true}, "Show two viewports side by side"},
    {"layout.four", "Four viewports", "Ctrl+4", {GLFW_KEY_4, true}, "Show four viewports in a 2x2 grid"},
    {"display.cage", "Cage overlay", "C", {GLFW_KEY_C}, "Show or hide the cage (creases coloured yellow to red by sharpness, corners as stars)"},
    {"display.dense_cage", "Dense cage edges", "", {}, "Draw uncreased cage edges however short (by default a view leaves them out while under 8 pixels near the camera)"},
    {"display.wireframe", "Tessellation wireframe", "Shift+W", {GLFW_KEY_W, false, true}, "Show or hide the tessellation wireframe"},
    {"help.toggle", "Help", "F1", {GLFW_KEY_F1}, "Show or hide this help"},
    {"mode.toggle", "Object / edit mode", "Tab", {GLFW_KEY_TAB}, "Object mode places whole objects; edit mode edits the selected object's cage (an instance's: its source's)"},
    {"object.delete", "Delete object", "X / Delete", {GLFW_KEY_X}, "Object mode: delete the selected object (refused while other objects instance it)", {GLFW_KEY_DELETE}},
    {"object.duplicate", "Duplicate object", "Shift+D", {GLFW_KEY_D, false, true}, "Object mode: a copy of the selected object with a cage of its own, beside it"},
    {"object.instance", "Instance object", "Alt+D", {GLFW_KEY_D, false, false, true}, "Object mode: an instance sharing the selected object's cage (edits of one show in both), beside it"},
    {"object.hide", "Hide object", "H", {GLFW_KEY_H}, "Object mode: hide the selected object (saved with the scene; undoable)"},
    {"object.unhide", "Show all objects", "Alt+H", {GLFW_KEY_H, false, false, true}, "Object mode: show every hidden object"},
    {"object.deselect", "Deselect object", "Alt+A / Esc", {GLFW_KEY_A, false, false, true}, "Object mode: select no object", {GLFW_KEY_ESCAPE}},
    // Blender's timeline keys, except play: its Alt+A is Deselect all here.
    {"anim.play", "Play / pause", "Space", {GLFW_KEY_SPACE}, "Play the animation at the timeline's frame rate (frames are skipped when drawing is slower), or pause it"},
    {"anim.prev_frame", "Previous frame", "Left", {GLFW_KEY_LEFT}, "Show the frame before this one (pauses)"},
    {"anim.next_frame", "Next frame", "Right", {GLFW_KEY_RIGHT}, "Show the frame after this one (pauses)"},
    {"anim.first_frame", "First frame", "Shift+Left", {GLFW_KEY_LEFT, false, true}, "Show the timeline's first frame"},
    {"anim.last_frame", "Last frame", "Shift+Right", {GLFW_KEY_RIGHT, false, true}, "Show the timeline's last frame"},
    {"anim.prev_key", "Previous key", "Down", {GLFW_KEY_DOWN}, "Show the previous frame with a key (of the edited cage, or the selected object in object mode)"},
    {"anim.next_key", "Next key", "Up", {GLFW_KEY_UP}, "Show the next frame with a key (of the edited cage, or the selected object in object mode)"},
    {"anim.loop", "Loop playback", "", {}, "Start again at the first frame after the last, or stop there"},
    {"anim.insert_key", "Insert key", "I", {GLFW_KEY_I}, "Key the selected vertices (all when none is selected) where they are, at this frame; object mode: the selected object's transform"},
    {"anim.delete_keys", "Delete keys at frame", "Alt+I", {GLFW_KEY_I, false, false, true}, "Remove the edited cage's vertex keys at this frame (object mode: the selected object's transform key)"},
    {"anim.interpolation", "Linear / Catmull-Rom", "", {}, "Switch how the edited cage's keys (object mode: the selected object's) are interpolated between keys: linearly or by Catmull-Rom (one undoable entry)"},
};

const MouseBinding kMouse[] = {
    {"Left click (object mode)", "Select the object under the cursor; empty space selects none"},
    {"Left drag on a handle (object mode, W / E / R)", "Move, rotate or scale the selected object (scale along its own axes); one undo entry per drag"},
    {"Left click (select tool)", "Select the vertex, edge or face under the cursor (mode 1/2/3); empty space clears"},
    {"Shift / Ctrl / Ctrl+Shift + left click", "Add to / remove from / toggle in the selection"},
    {"Left drag (select, rotate, scale tools)", "Box select, wherever it starts (same modifiers); only what is visible unless 'Select hidden' is on"},
    {"Alt + left click / Shift+Alt", "Edge loop through the edge under the cursor (face mode: the face loop across it) / add it"},
    {"Ctrl+Alt + left click", "Edge ring across the quads beside the edge under the cursor"},
    {"Double click on an edge (edge mode)", "Its edge loop"},
    {"Left drag on an element (move tool)", "Select it if it is not, then move the selection in the view plane"},
    {"Left drag on a handle (move, rotate, scale tools)", "Transform along / about that axis; the centre handle works in the view plane; Ctrl snaps"},
    {"Right click or Esc during a drag", "Cancel the drag (the selection goes back)"},
    {"Left drag (sculpt tool, B)", "Paint on the displaced surface under the cursor (one undo entry per stroke); Ctrl: raise <-> lower, mask <-> unmask; Shift: smooth"},
    {"Mouse (extrude, Ctrl+E)", "Sets the distance along the faces' normal (or type digits . -, Backspace); left click or Enter confirms, right click or Esc cancels"},
    {"Left click (loop tool, Ctrl+R)", "Insert an edge loop across the edge under the cursor, where the cursor is"},
    {"Alt + left drag, or middle drag", "Orbit (an Alt+click without a drag selects a loop)"},
    {"Alt + middle drag, or Shift + middle drag", "Pan"},
    {"Alt + right drag, Ctrl + middle drag, or wheel", "Zoom (dolly)"},
};

}  // namespace

std::span<const ActionInfo> actions() { return kActions; }

const ActionInfo* findAction(std::string_view id) {
    auto it = std::find_if(std::begin(kActions), std::end(kActions), [&](const ActionInfo& a) { return id == a.id; });
    return it == std::end(kActions) ? nullptr : &*it;
}

std::span<const MouseBinding> mouseBindings() { return kMouse; }

ActionScope scopeOf(std::string_view id) {
    if (id.starts_with("brush.")) return ActionScope::SculptTool;
    for (std::string_view prefix : {"select.", "mesh.", "crease.", "sculpt.", "tool.sculpt"})
        if (id.starts_with(prefix)) return ActionScope::EditMode;
    if (id.starts_with("object.")) return ActionScope::ObjectMode;
    return ActionScope::Both;
}

}  // namespace qp::editor
