#include "extrude_tool.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <GLFW/glfw3.h>
#include <imgui.h>

#include "editor_app.h"
#include "mesh/topology_edits.h"
#include "viewport_input.h"

namespace qp::editor {

namespace {


std::string number(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", double(value));
    return text;
}

// The typed distance; what is not a number yet ("", "-", ".") counts as 0.
float typedDistance(const std::string& typed) {
    char* end = nullptr;
    const float value = std::strtof(typed.c_str(), &end);
    return end == typed.c_str() ? 0.0f : value;
}

// The distance the cursor asks for: its offset from where the mouse took over, along the
// screen direction of the regions' normal, in world units.
float mouseDistance(const EditorApp& app, const ExtrudeSession& s, glm::vec2 cursor) {
    const ViewportState& v = app.viewports[std::min<size_t>(s.viewport, app.viewports.size() - 1)];
    const PickView view{v.viewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
    const float length = 0.1f * std::max(cageExtent(*app.doc).bounds.diagonal(), 1e-3f);
    const PickView::Projected a = view.project(s.anchor), b = view.project(s.anchor + length * s.normal);
    glm::vec2 perUnit = (b.pixel - a.pixel) / length;
    // Seen end-on (or from behind the near plane) the normal has no usable screen direction:
    // then up the screen counts, at the scale of the view.
    if (!a.inFront || !b.inFront || glm::length(perUnit) < 20.0f)
        perUnit = glm::vec2(0.0f, -float(v.rect.extent.height) / (10.0f * length));
    return glm::dot(cursor - *s.startCursor, perUnit) / glm::dot(perUnit, perUnit);
}

void preview(EditorApp& app, float distance) {
    ExtrudeSession& s = *app.extrude;
    if (s.moved && distance == s.distance) return;
    std::vector<glm::vec3> positions = s.base;
    for (size_t i = 0; i < positions.size(); ++i) positions[i] += distance * s.direction[i];
    if (!edit(app, MoveVertices{s.vertices, std::move(positions), s.moved, "extrude preview"})) {
        cancelInteractiveExtrude(app);
        return;
    }
    s.moved = true;
    s.distance = distance;
    app.ui.status = "Extrude: " + number(distance) + " (type a distance; click or Enter confirms, Esc or right click cancels)";
}

}  // namespace

bool startInteractiveExtrude(EditorApp& app) {
    if (app.extrude) return false;
    if (!app.doc->planned || app.loader.busy()) {
        app.ui.status = "No cage is open (or a file is still loading).";
        return false;
    }
    Document& doc = *app.doc;
    std::vector<uint32_t> faces = selectedFaces(doc);
    if (faces.empty()) {
        showError(app, "Extrude needs selected faces (face mode, 3).");
        return false;
    }
    const Cage& cage = doc.planned->cage();
    // The same operation at distance 0 and 1: what each vertex does per unit of distance.
    Result<TopologyEdit> zero = extrudeFaces(cage, doc.planned->topology(), faces, 0.0f);
    Result<TopologyEdit> unit = extrudeFaces(cage, doc.planned->topology(), faces, 1.0f);
    if (!zero || !unit) {
        showError(app, "Edit failed: " + (zero ? unit : zero).error().message);
        return false;
    }
    ExtrudeSession s;
    s.historyBefore = doc.history.position();
    s.documentGeneration = app.documentGeneration;
    s.viewport = app.activeViewport;
    glm::vec3 sum(0.0f);
    for (uint32_t v = 0; v < zero->cage.vertexCount(); ++v) {
        const glm::vec3 step = unit->cage.positions[v] - zero->cage.positions[v];
        if (step == glm::vec3(0.0f)) continue;
        s.vertices.push_back(v);
        s.base.push_back(zero->cage.positions[v]);
        s.direction.push_back(step);
        s.anchor += zero->cage.positions[v];
        sum += step;
    }
    if (s.vertices.empty()) {
        showError(app, "Extrude: the selected faces have no normal to follow.");
        return false;
    }
    s.anchor /= float(s.vertices.size());
    s.normal = glm::length(sum) > 0.0f ? glm::normalize(sum) : glm::vec3(0.0f, 0.0f, 1.0f);
    s.faces = std::move(faces);
    if (!edit(app, ExtrudeFaces{s.faces, 0.0f})) return false;
    app.drag = Drag{};
    app.extrude = std::move(s);
    preview(app, 0.0f);
    return true;
}

bool extrudeActive(const EditorApp& app) { return app.extrude.has_value(); }

void updateInteractiveExtrude(EditorApp& app) {
    if (!app.extrude) return;
    ExtrudeSession& s = *app.extrude;
    // Something else changed the history or the document: the session is over, as it is.
    if (app.documentGeneration != s.documentGeneration || !app.doc->planned ||
        app.doc->history.position() != s.historyBefore + 1 + (s.moved ? 1 : 0)) {
        app.extrude.reset();
        app.ui.status = "Extrude ended (the history changed)";
        return;
    }
    const ImGuiIO& io = ImGui::GetIO();
    const glm::vec2 cursor = cursorInFramebuffer();
    const int hovered = io.WantCaptureMouse ? -1 : viewportAt(app, cursor);
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Right)) return cancelInteractiveExtrude(app);
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left) && hovered >= 0) {
        confirmInteractiveExtrude(app);
        return;
    }
    if (!s.typed.empty()) return preview(app, typedDistance(s.typed));
    if (hovered < 0) return;
    if (!s.startCursor) {  // the mouse takes over where it first is over a viewport
        s.startCursor = cursor;
        s.viewport = uint32_t(hovered);
        return;
    }
    preview(app, mouseDistance(app, s, cursor));
}

void extrudeKey(EditorApp& app, const KeyPress& press) {
    if (!app.extrude) return;
    ExtrudeSession& s = *app.extrude;
    const int k = press.key;
    if (k == GLFW_KEY_ESCAPE) return cancelInteractiveExtrude(app);
    if (k == GLFW_KEY_ENTER || k == GLFW_KEY_KP_ENTER) {
        confirmInteractiveExtrude(app);
        return;
    }
    if (k >= GLFW_KEY_0 && k <= GLFW_KEY_9 && !press.shift) s.typed += char('0' + (k - GLFW_KEY_0));
    else if (k >= GLFW_KEY_KP_0 && k <= GLFW_KEY_KP_9) s.typed += char('0' + (k - GLFW_KEY_KP_0));
    else if ((k == GLFW_KEY_PERIOD || k == GLFW_KEY_KP_DECIMAL) && s.typed.find('.') == std::string::npos) s.typed += '.';
    else if (k == GLFW_KEY_MINUS || k == GLFW_KEY_KP_SUBTRACT) {
        // '-' flips the sign wherever it is typed (Blender does the same).
        if (!s.typed.empty() && s.typed[0] == '-') s.typed.erase(0, 1);
        else s.typed.insert(0, 1, '-');
    } else if (k == GLFW_KEY_BACKSPACE && !s.typed.empty()) s.typed.pop_back();
    else return;
    preview(app, s.typed.empty() ? s.distance : typedDistance(s.typed));
}

bool confirmInteractiveExtrude(EditorApp& app) {
    if (!app.extrude) return false;
    const ExtrudeSession s = std::move(*app.extrude);
    app.extrude.reset();
    const float distance = s.typed.empty() ? s.distance : typedDistance(s.typed);
    if (Result<EditReport> back = revertTo(*app.doc, s.historyBefore, app.frame); !back) {
        showError(app, "Extrude: " + back.error().message);
        return false;
    }
    app.tools.extrudeDistance = distance;
    return edit(app, ExtrudeFaces{s.faces, distance});
}

void cancelInteractiveExtrude(EditorApp& app) {
    if (!app.extrude) return;
    const size_t before = app.extrude->historyBefore;
    app.extrude.reset();
    if (Result<EditReport> back = revertTo(*app.doc, before, app.frame); !back)
        showError(app, "Extrude: " + back.error().message);
    else app.ui.status = "Extrude cancelled";
}

std::string extrudeReadout(const ExtrudeSession& s) {
    return "extrude " + (s.typed.empty() ? number(s.distance) : s.typed + "_");
}

}  // namespace qp::editor
