// The interactive extrude (Ctrl+E, the Mesh panel's Extrude): the selected faces are extruded
// in place at once and then follow the mouse along their regions' normals; the distance shows
// beside the cursor and in the status line. Typing digits, '.' and '-' enters the distance
// instead (Backspace edits; the mouse no longer counts while there is text). A left click or
// Enter confirms, Esc or a right click cancels.
//
// History: while it runs the preview is an "extrude by 0" entry plus one merged move (a move
// re-plans nothing, so following the mouse is cheap). Confirming goes back before both and
// applies ExtrudeFaces with the final distance: ONE entry, "extrude N faces by D". Cancelling
// goes back before both and forgets them: the cage is exactly as before and the history has no
// trace of it. Anything else that changes the history meanwhile (a menu's undo, a new file)
// ends the session where it is.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace qp::editor {

struct EditorApp;
struct KeyPress;

struct ExtrudeSession {
    size_t historyBefore = 0;          // entries applied before the preview
    uint64_t documentGeneration = 0;
    std::vector<uint32_t> faces;       // the extruded faces
    std::vector<uint32_t> vertices;    // the vertices the distance moves (new numbering)
    std::vector<glm::vec3> base;       // their positions at distance 0
    std::vector<glm::vec3> direction;  // their offset per unit of distance
    glm::vec3 anchor{0.0f}, normal{0.0f, 0.0f, 1.0f};  // the regions' centre and mean direction
    std::optional<glm::vec2> startCursor;  // framebuffer pixels where the mouse took over
    uint32_t viewport = 0;
    float distance = 0.0f;             // as previewed
    std::string typed;                 // the numeric entry; empty: the mouse sets the distance
    bool moved = false;                // a preview move follows the extrude entry
};

bool startInteractiveExtrude(EditorApp& app);
bool extrudeActive(const EditorApp& app);
// Per frame while active: the mouse (cursor, clicks) and the preview.
void updateInteractiveExtrude(EditorApp& app);
// A key press while active: always consumed (digits and editing keys change the entry; Enter,
// Esc confirm or cancel; the rest is ignored so no shortcut acts mid-extrude).
void extrudeKey(EditorApp& app, const KeyPress& press);
bool confirmInteractiveExtrude(EditorApp& app);
void cancelInteractiveExtrude(EditorApp& app);
// "extrude 0.250" (or "extrude 0.25_" while typing), for the overlay beside the cursor.
std::string extrudeReadout(const ExtrudeSession& session);

}  // namespace qp::editor
