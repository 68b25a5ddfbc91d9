// dump-state (automation.h): the editor's state as JSON for tests and measurements; the fields
// are listed in docs/editor.md.
#include <algorithm>
#include <cmath>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <nlohmann/json.hpp>

#include "automation.h"
#include "document_animation.h"
#include "document_objects.h"
#include "editor_app.h"
#include "mesh/file_io.h"
#include "overlays.h"
#include "playback.h"
#include "recovery.h"
#include "scene/scene_names.h"
#include "tools.h"

namespace qp::editor {

namespace {

using json = nlohmann::json;

json vec(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }
json vec2(const glm::vec2& v) { return json::array({v.x, v.y}); }

json summaryJson(const Summary& s) { return {{"median", s.median}, {"p90", s.p90}, {"max", s.max}, {"count", s.count}}; }

// "linear" or "catmull-rom" as the scene file writes it; null without an object.
json interpolationName(std::optional<Interpolation> interpolation) {
    if (!interpolation) return nullptr;
    return scene_names::enumName<Interpolation>(scene_names::kInterpolationNames, *interpolation);
}

}  // namespace

// The scene's objects for dump-state: each one's transform, visibility, which is selected and
// whose cage edit mode is on, and where the centre of its box lands in the first viewport
// (window pixels; null when behind the camera), for tests that click objects.
namespace {

json objectsState(EditorApp& app) {
    const Document& doc = *app.doc;
    json objects = json::array();
    if (!doc.planned || app.viewports.empty()) return objects;
    const ViewportState& v = app.viewports[0];
    const float scale = ImGui::GetIO().DisplayFramebufferScale.x > 0 ? ImGui::GetIO().DisplayFramebufferScale.x : 1.0f;
    const PickView view{v.worldViewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
    for (uint32_t i = 0; i < doc.scene.objects.size(); ++i) {
        const SceneObject& o = doc.scene.objects[i];
        const Bounds b = objectCageBounds(doc, i);
        const PickView::Projected centre = view.project(glm::vec3(o.transform.matrix() * glm::vec4(0.5f * (b.min + b.max), 1.0f)));
        const glm::vec2 window = (glm::vec2(float(v.rect.offset.x), float(v.rect.offset.y)) + centre.pixel) / scale;
        objects.push_back({{"name", o.name},
                           {"instance_of", o.instanceOf},
                           {"translation", vec(o.transform.translation)},
                           {"rotation_degrees", vec(o.transform.rotationDegrees)},
                           {"scale", vec(o.transform.scale)},
                           {"visible", o.visible},
                           {"selected", selectedObject(doc) == i},
                           {"edited", i == doc.activeObject},
                           {"faces", plannedCageOf(doc, i).cage().faceCount()},
                           {"bounds", {vec(b.min), vec(b.max)}},  // of the cage as shown, in its own coordinates
                           {"screen", centre.inFront ? json(vec2(window)) : json(nullptr)}});
    }
    return objects;
}

}  // namespace

void Automation::dumpState(EditorApp& app, const AutomationCommand& c) {
    const Document& doc = *app.doc;
    const bool autosaveWriting = app.autosaver.busy();  // before the slow parts of the dump below
    json state;
    state["frame"] = app.frame;
    // Whether the last frame drew the 3D coarse while the camera moved (progressive refinement).
    state["coarse_frame"] = !app.stats.samples.empty() && app.stats.samples.back().coarse;
    state["dirty"] = doc.dirty;
    state["title"] = app.ui.title;
    state["path"] = doc.path;
    state["loading"] = app.loader.busy();
    if (app.loader.busy()) state["loading_stage"] = app.loader.stage(), state["loading_fraction"] = app.loader.fraction();
    state["status"] = app.ui.status;
    json vertices = json::array(), creases = json::array(), corners = json::array();
    if (doc.planned) {
        const Cage& cage = doc.planned->cage();
        for (const glm::vec3& p : cage.positions) vertices.push_back(vec(p));
        for (const EdgeCrease& e : cage.creases) creases.push_back({e.v0, e.v1, e.sharpness});
        for (const VertexCorner& k : cage.corners) corners.push_back({k.vertex, k.sharpness});
        state["faces"] = cage.faceCount();
        state["subfaces"] = doc.planned->subfaceCount();
        state["unique_plans"] = doc.database->size();
    }
    state["vertices"] = vertices;
    state["creases"] = creases;
    state["corners"] = corners;
    json edges = json::array();
    for (const EdgeKey& e : doc.selection.edges) edges.push_back({e.v0, e.v1});
    state["selection"] = {{"mode", selectionModeWord(doc.selection.mode)},
                          {"vertices", doc.selection.vertices},
                          {"edges", edges},
                          {"faces", doc.selection.faces}};
    if (doc.planned) {
        const Cage& cage = doc.planned->cage();
        state["holes"] = cage.holes;
        state["crease_method"] = cage.options.creaseMethod == CreaseMethod::Chaikin ? "chaikin" : "normal";
        if (cage.faceCount() <= 5000) {
            json faces = json::array();
            for (uint32_t f = 0; f < cage.faceCount(); ++f)
                faces.push_back(std::vector<uint32_t>(cage.faceBegin(f), cage.faceBegin(f) + cage.faceSize(f)));
            state["face_vertices"] = faces;
        }
        state["selected_vertices"] = selectedVertices(doc.selection, cage);
    }
    if (doc.lastEdit) {
        const EditReport& r = doc.lastEdit->report;
        state["last_edit"] = {{"description", doc.lastEdit->description}, {"replanned_faces", r.replannedFaces},
                              {"updated_subfaces", r.updatedSubfaces}, {"new_plans", r.newPlans},
                              {"milliseconds", r.milliseconds}, {"frame", doc.lastEdit->frame},
                              {"topology_changed", r.topologyChanged}};
        if (app.lastEditFrame.frame == doc.lastEdit->frame)
            state["last_edit"]["shown_in_frame"] = {{"cpu_ms", app.lastEditFrame.cpuMs},
                                                    {"interval_ms", app.lastEditFrame.intervalMs},
                                                    {"scheme_updates_ms", app.lastEditFrame.syncMs}};
    } else {
        state["last_edit"] = nullptr;
    }
    json entries = json::array();
    for (size_t i = 0; i < doc.history.size(); ++i) {
        const HistoryEntryInfo e = doc.history.entry(i);
        entries.push_back({{"name", e.name}, {"replanned_faces", e.report.replannedFaces},
                           {"milliseconds", e.report.milliseconds}, {"bytes", e.bytes}});
    }
    state["history"] = {{"position", doc.history.position()}, {"size", doc.history.size()},
                        {"bytes", doc.history.bytes()}, {"entries", entries}};
    const char* tools[] = {"select", "move", "rotate", "scale", "sculpt"};
    state["tool"] = {{"tool", tools[int(app.tools.tool)]},
                     {"space", app.tools.space == TransformSpace::World ? "world" : "local"},
                     {"loop_tool", app.tools.loopTool},
                     {"visible_only", app.tools.visibleOnly},
                     {"extrude_distance", app.tools.extrudeDistance}};
    const SculptSettings& brush = app.tools.sculpt;
    state["brush"] = {{"kind", brushKindName(brush.kind)}, {"radius", brush.radius}, {"strength", brush.strength},
                      {"falloff", falloffName(brush.falloff)}, {"resolution", brush.resolution},
                      {"hover", app.ui.brushHover ? json(vec(app.ui.brushHover->position)) : json(nullptr)}};
    if (const std::optional<SurfaceHit>& hover = app.ui.brushHover) {  // on the displaced surface; `limit` beneath it
        state["brush"]["hover_normal"] = vec(hover->normal);
        state["brush"]["hover_limit"] = vec(hover->limit);
        state["brush"]["hover_site"] = {{"subface", hover->subface}, {"u", hover->u}, {"v", hover->v}};
    }
    const Displacement& displacement = displacementOf(doc);
    if (displacement.empty()) {
        state["displacement"] = nullptr;
    } else {
        uint32_t nonzero = 0;
        float largest = 0.0f;
        for (float x : displacement.samples) nonzero += x != 0.0f, largest = std::max(largest, std::fabs(x));
        uint32_t masked = 0;
        for (float m : displacement.mask) masked += m > 0.0f;
        state["displacement"] = {{"samples", displacement.samples.size()}, {"nonzero", nonzero}, {"max_abs", largest},
                                 {"revision", doc.displacementRevision}, {"sample_revision", doc.sampleRevision},
                                 {"masked", masked}, {"mask_revision", doc.maskRevision},
                                 {"mask_dots", app.ui.maskDots.positions.size()}};
    }
    const Timeline timeline = documentTimeline(doc);
    const EditReport& shown = doc.lastFrameChange;
    state["animation"] = {{"frame", doc.currentFrame},
                          {"playing", doc.playing},
                          {"loop", doc.loopPlayback},
                          {"animated", isAnimated(doc.scene)},
                          {"first_frame", timeline.firstFrame},
                          {"last_frame", timeline.lastFrame},
                          {"fps", timeline.framesPerSecond},
                          {"fps_achieved", app.playback.fpsAchieved},
                          {"key_frames", keyMarks(app)},
                          {"interpolation", interpolationName(timelineInterpolation(app))},
                          {"last_frame_change", {{"replanned_faces", shown.replannedFaces},
                                                 {"updated_subfaces", shown.updatedSubfaces},
                                                 {"milliseconds", shown.milliseconds}}}};
    state["mode"] = app.mode == EditorMode::Object ? "object" : "edit";
    state["objects"] = objectsState(app);
    state["drag"] = app.drag.kind == DragKind::None ? json(nullptr) : json(app.drag.readout);
    state["hidden_faces"] = doc.hiddenFaces;
    state["hidden_subfaces"] = app.renderer.hiddenSubfaces;  // what the viewports pass their schemes
    state["extrude"] = app.extrude ? json{{"distance", app.extrude->distance},
                                          {"typed", app.extrude->typed},
                                          {"faces", app.extrude->faces},
                                          {"readout", extrudeReadout(*app.extrude)}}
                                   : json(nullptr);
    const ImGuiIO& io = ImGui::GetIO();
    const float scale = io.DisplayFramebufferScale.x > 0 ? io.DisplayFramebufferScale.x : 1.0f;
    json viewports = json::array();
    for (size_t i = 0; i < app.viewports.size(); ++i) {
        ViewportState& v = app.viewports[i];
        const ViewCamera& camera = cameraOf(app, uint32_t(i));
        json entry = {{"scheme", v.scheme},
                      {"color_by", v.colorBy},
                      {"cull", cullMethodName(v.cull)},
                      {"linked", v.linked},
                      {"factor", v.factor},
                      {"rect", {v.rect.offset.x / scale, v.rect.offset.y / scale, v.rect.extent.width / scale,
                                v.rect.extent.height / scale}},
                      {"camera", {{"eye", vec(eyePosition(camera))}, {"target", vec(camera.target)},
                                  {"up", vec(upVector(camera))}, {"orthographic", camera.orthographic}}}};
        const AxisTriad triad = axisTriad(v.worldViewProjection);
        entry["axis_triad"] = {{"screen", {{triad.screen[0].x, triad.screen[0].y}, {triad.screen[1].x, triad.screen[1].y},
                                           {triad.screen[2].x, triad.screen[2].y}}},
                               {"toward_viewer", triad.towardViewer}};
        if (i < app.stats.viewportCounts.size()) {
            const ViewportCounts& counts = app.stats.viewportCounts[i];
            entry["triangles"] = counts.triangles, entry["patches"] = counts.patches;
            entry["sample_culled"] = counts.sampleCulled;
            entry["facing_away"] = counts.facingAway;
            entry["culled"] = {{"tested", counts.cull.tested}, {"frustum", counts.cull.frustum},
                               {"back_facing", counts.cull.backFacing}, {"frustum_only", counts.cull.frustumOnly},
                               {"cull_ms", counts.cullMilliseconds}};
        }
        if (i < app.renderer.views.size()) {
            const SchemeView& view = app.renderer.views[i];
            entry["drawn"] = view.instance.has_value();
            entry["problem"] = view.problem;
            entry["draw_problem"] = view.drawProblem;
            entry["warnings"] = view.support.approximations;
            entry["color_modes"] = view.colorModes;
            entry["setup_ms"] = view.setupMs;
            entry["plan_update"] = {{"milliseconds", view.planUpdateMs}, {"in_place", view.planUpdateInPlace},
                                    {"note", view.planUpdateNote}};
            entry["update_ms"] = view.updateMs;
            entry["updated_vertices"] = view.updatedVertices;
            entry["displacement_ms"] = view.displacementMs;
            entry["updated_samples"] = view.updatedSamples;
            entry["heatmap"] = {{"on", v.heatMap},
                                {"valid", view.heat.valid},
                                {"max", view.heat.maxRelError},
                                {"rms", view.heat.rmsRelError},
                                {"samples", view.heat.relError.size()},
                                {"milliseconds", view.heat.lastMs},
                                {"subfaces_evaluated", view.heat.lastSubfaces}};
            const SceneHeat scene = sceneHeat(app.renderer, uint32_t(i));
            entry["heatmap"]["scene"] = {{"cages", scene.cages}, {"max", scene.maxRelError}, {"rms", scene.rmsRelError},
                                         {"samples", scene.samples}};
        }
        if (std::optional<GizmoShape> gizmo = gizmoIn(app, uint32_t(i))) {
            const glm::vec2 origin(float(v.rect.offset.x), float(v.rect.offset.y));
            auto window = [&](glm::vec2 p) { return vec2((origin + p) / scale); };
            entry["gizmo"] = {{"centre", window(gizmo->centre)},
                              {"x", window(gizmo->axisEnd[0])},
                              {"y", window(gizmo->axisEnd[1])},
                              {"z", window(gizmo->axisEnd[2])},
                              {"view_ring_radius", gizmo->viewRingRadius / scale},
                              {"pivot", vec(gizmo->frame.pivot)}};
        }
        entry["plain_cage_lines_hidden"] = i < kMaxViewports && app.renderer.plainLinesHidden[i];
        // Where each cage vertex appears (window pixels), so tests can click real vertices.
        if (doc.planned && doc.planned->cage().vertexCount() <= 5000) {
            json projected = json::array();
            json pickable = json::array();
            for (bool visible : pickableVertices(app, uint32_t(i))) pickable.push_back(visible);
            entry["pickable_vertices"] = pickable;
            for (const glm::vec3& p : doc.planned->cage().positions) {
                const glm::vec4 clip = v.viewProjection * glm::vec4(p, 1.0f);
                if (clip.w <= 0) {
                    projected.push_back(nullptr);
                    continue;
                }
                const glm::vec2 ndc = glm::vec2(clip) / clip.w;
                projected.push_back({(v.rect.offset.x + (0.5f * ndc.x + 0.5f) * v.rect.extent.width) / scale,
                                     (v.rect.offset.y + (0.5f * ndc.y + 0.5f) * v.rect.extent.height) / scale,
                                     clip.z / clip.w});
            }
            entry["projected_vertices"] = projected;
        }
        viewports.push_back(entry);
    }
    state["viewports"] = viewports;
    state["active_viewport"] = app.activeViewport;
    state["display"] = {{"mode", app.tessellation.mode == TessellationMode::Uniform ? "uniform" : "adaptive"},
                        {"factor", app.tessellation.factor},
                        {"pixels_per_edge", app.tessellation.pixelsPerEdge},
                        {"cage", app.tessellation.showCage},
                        {"wireframe", app.tessellation.showWireframe},
                        {"plans_path", app.plansPath},
                        {"shading", app.display.shading == Shading::Matcap ? "matcap" : "studio"},
                        {"up_axis", upAxisOf(app) == UpAxis::Z ? "z" : "y"},
                        {"grid", app.display.showGrid},
                        {"dense_cage_lines", app.display.denseCageLines},
                        {"grid_lines", app.renderer.gridLineCount / 2},
                        {"crease_lines", app.renderer.creaseLineCount / 2},
                        {"crease_line_width", std::min(kCreaseLineWidth, app.renderer.lines.maxLineWidth)}};
    state["renderer"] = {{"last_sync_ms", app.renderer.lastSyncMs}};
    // The displaced-surface picker's last update (a dab's sub-faces, or a whole build) and builds.
    state["picking"] = {{"displaced_ms", app.picking.lastDisplacedMs}, {"displaced_builds", app.picking.displacedBuilds},
                        {"displaced_updated_subfaces", app.picking.displaced ? app.picking.displaced->lastUpdated().size() : 0}};
    json schemes = json::array();
    for (const auto& plugin : app.catalog.plugins) schemes.push_back(plugin->name);
    state["schemes"] = schemes;
    state["frame_times_ms"] = {{"cpu", summaryJson(summarize(app.stats, FrameField::Cpu, 120))},
                               {"gpu", summaryJson(summarize(app.stats, FrameField::Gpu, 120))},
                               {"interval", summaryJson(summarize(app.stats, FrameField::Interval, 120))},
                               {"gpu_scene_drawn", summaryJson(summarize(app.stats, FrameField::Gpu, 120, FrameFilter::SceneDrawn))}};
    int wx = 0, wy = 0, ww = 0, wh = 0, fw = 0, fh = 0;
    glfwGetWindowPos(app.window, &wx, &wy);
    glfwGetWindowSize(app.window, &ww, &wh);
    glfwGetFramebufferSize(app.window, &fw, &fh);
    state["window"] = {{"x", wx}, {"y", wy}, {"width", ww}, {"height", wh}, {"framebuffer", {fw, fh}}};
    json widgets = json::object();
    for (const auto& [label, rect] : app.ui.widgets)
        if (!widgets.contains(label)) widgets[label] = {rect[0], rect[1], rect[2], rect[3]};
    state["widgets"] = widgets;
    // Tools without a tooltip (menus and dialog buttons explain themselves).
    json untipped = json::array();
    for (const auto& [label, rect] : app.ui.widgets)
        if (std::find(app.ui.tooltips.begin(), app.ui.tooltips.end(), label) == app.ui.tooltips.end()) untipped.push_back(label);
    state["widgets_without_tooltip"] = untipped;
    state["open_popups"] = app.ui.openPopups;
    // Any ImGui popup (a menu, a drop-down or a dialog), and whether a text field has the keyboard.
    state["popup_open"] = ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId);
    state["text_input"] = ImGui::GetIO().WantTextInput;
    state["save_as_path"] = app.ui.saveAsPath;
    state["show_help"] = app.ui.showHelp;
    state["recovery"] = {{"directory", app.recoveryDir},
                         {"offered", app.ui.recovery.has_value()},
                         {"file_exists", findRecovery(app.recoveryDir).has_value()},
                         {"writing", autosaveWriting}};
    state["validation_messages"] = validationMessageCount(app.ctx);
    state["device"] = app.ctx.deviceName;
    if (Status s = writeFileAtomically(c.args[0], state.dump(1) + "\n"); !s) fail(c, s.error().message);
}

}  // namespace qp::editor
