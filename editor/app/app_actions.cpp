// The editor's commands (editor_app.h): actions from the table in actions.h, file handling
// with its confirmations, recovery, edits and framing. Menus, shortcuts and automation all
// land here.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "actions.h"
#include "document_export.h"
#include "document_objects.h"
#include "editor_app.h"
#include "object_mode.h"
#include "playback.h"
#include "recovery.h"
#include "sculpt_tool.h"
#include "tools.h"

namespace qp::editor {

namespace {

void storeViewState(EditorApp& app, Scene& scene) {
    scene.camera = toSceneCamera(app.sharedCamera);
    scene.viewports.clear();
    for (const ViewportState& v : app.viewports)
        scene.viewports.push_back({v.scheme, v.linked ? CameraLink::Linked : CameraLink::Independent, v.colorBy});
    scene.tessellation = app.tessellation;
    scene.display = app.display;
}

void startLoad(EditorApp& app, LoadRequest request) {
    request.options = PlanOptions{app.options.planDepth, true};
    app.loader.start(std::move(request));
    app.ui.status = "Opening " + app.loader.request().path;
}

}  // namespace

ViewCamera& cameraOf(EditorApp& app, uint32_t viewport) {
    ViewportState& v = app.viewports[std::min<size_t>(viewport, app.viewports.size() - 1)];
    return v.linked ? app.sharedCamera : v.camera;
}

void setViewportCount(EditorApp& app, uint32_t count) {
    count = count >= 4 ? 4 : count >= 2 ? 2 : 1;
    while (app.viewports.size() < count) {
        ViewportState added = app.viewports.back();
        added.linked = true;
        added.camera = app.sharedCamera;
        app.viewports.push_back(added);
    }
    app.viewports.resize(count);
    app.activeViewport = std::min(app.activeViewport, count - 1);
}

// The job reads a copy of the scene and the document's planned cages, which no action changes
// while it runs (runAction refuses them).
bool exportTo(EditorApp& app, const std::string& path) {
    if (app.job.busy() || !app.doc->planned) return false;
    if (Result<MeshFormat> format = meshFormatOf(path); !format) {
        showError(app, "Export refused: " + format.error().message);
        return false;
    }
    app.job.start("Exporting " + path, [scene = sceneToSave(*app.doc), cages = documentCages(*app.doc), path,
                                        options = app.ui.exportOptions, source = app.doc->path](const ExportProgress& progress)
                                           -> Result<std::string> {
        Result<ExportReport> report = exportScene(scene, cages, path, options, source.empty() ? "untitled" : source, nullptr, progress);
        if (!report) return Error{"Export failed: " + report.error().message};
        for (const std::string& note : report->notes) std::fprintf(stderr, "note: %s\n", note.c_str());
        char text[256];
        std::snprintf(text, sizeof text, "Exported %zu file(s): %llu vertices, %llu triangles, %s, ACMR %.2f -> %.2f, %.0f ms",
                      report->files.size(), (unsigned long long)report->vertices, (unsigned long long)report->triangles,
                      report->closure.watertight() ? "watertight" : "with open borders", report->order.acmrBefore,
                      report->order.acmrAfter, report->ms);
        return std::string(text);
    });
    app.ui.status = "Exporting " + path + "...";
    return true;
}

bool bakeTo(EditorApp& app, const std::string& path) {
    if (app.job.busy() || !app.doc->planned) return false;
    BakeOptions options = app.ui.bakeOptions;
    options.normalMap = !app.ui.bakeNormalMapPath.empty();
    app.job.start("Baking " + path, [scene = sceneToSave(*app.doc), cages = documentCages(*app.doc), path, options,
                                     normalMap = app.ui.bakeNormalMapPath, source = app.doc->path](const ExportProgress& progress)
                                        -> Result<std::string> {
        Result<BakeReport> report = bakeScene(scene, cages, path, normalMap, options, source.empty() ? "untitled" : source, progress);
        if (!report) return Error{"Bake failed: " + report.error().message};
        for (const std::string& note : report->notes) std::fprintf(stderr, "note: %s\n", note.c_str());
        char text[256];
        std::snprintf(text, sizeof text, "Baked %zu file(s): %u x %u texels, displacement %.4g to %.4g, %.0f ms", report->files.size(),
                      options.size, options.size, double(report->minValue), double(report->maxValue), report->ms);
        return std::string(text);
    });
    app.ui.status = "Baking " + path + "...";
    return true;
}

void finishAutosave(EditorApp& app) { app.autosaver.waitAndDiscard(); }

void adoptFinishedJob(EditorApp& app) {
    std::optional<Result<std::string>> done = app.job.take();
    if (!done) return;
    if (!*done && app.job.cancelled()) {  // the user's choice, not an error
        app.ui.status = app.job.title() + ": cancelled, nothing was written.";
        return;
    }
    if (!*done) return showError(app, done->error().message);
    app.ui.status = **done;
}

void showError(EditorApp& app, const std::string& message) {
    app.ui.errorMessage = message;
    app.ui.requestPopup = "Error";
    app.ui.status = message;
    std::fprintf(stderr, "error: %s\n", message.c_str());
}

void requestOpen(EditorApp& app, const std::string& path) {
    if (app.loader.busy()) return showError(app, "Another file is still loading; try again when it is done.");
    if (app.doc->dirty) {
        app.ui.pending = {PendingAction::Open, path};
        app.ui.requestPopup = "Unsaved changes";
        return;
    }
    startLoad(app, LoadRequest{path});
}

void requestQuit(EditorApp& app) {
    if (app.doc->dirty) {
        app.ui.pending = {PendingAction::Quit, {}};
        app.ui.requestPopup = "Unsaved changes";
        return;
    }
    app.running = false;
}

void continuePending(EditorApp& app) {
    PendingAction pending = std::exchange(app.ui.pending, PendingAction{});
    app.ui.continuePendingAfterSave = false;
    if (pending.kind == PendingAction::None) return;
    // The changes were saved or deliberately dropped: the autosave has nothing left to protect.
    finishAutosave(app);
    removeRecovery(app.recoveryDir);
    if (pending.kind == PendingAction::Quit) app.running = false;
    if (pending.kind == PendingAction::Open) startLoad(app, LoadRequest{pending.path});
}

bool saveTo(EditorApp& app, const std::string& path) {
    if (!app.doc->planned) {
        showError(app, "Nothing to save yet: the document is still loading.");
        return false;
    }
    storeViewState(app, app.doc->scene);
    if (Status saved = saveDocument(*app.doc, path); !saved) {
        // The document stays as it is (and marked unsaved); the user needs to know where to go.
        showError(app, "Saving failed: " + saved.error().message +
                           ". Your changes are kept (still unsaved): use File > Save As to save them somewhere else.");
        return false;
    }
    finishAutosave(app);
    removeRecovery(app.recoveryDir);
    app.ui.status = "Saved " + path;
    return true;
}

void stopOnFatalError(EditorApp& app, const std::string& message) {
    std::string rescued;
    finishAutosave(app);
    if (app.doc->dirty && app.doc->planned) {
        const Status written = writeRecovery(app.recoveryDir, sceneToSave(*app.doc), RecoveryInfo{app.doc->path, localTimeNow()});
        rescued = written ? "; the unsaved changes were written to " + app.recoveryDir +
                                "/autosave.json and are offered at the next start"
                          : "; writing the unsaved changes to the recovery directory failed too: " + written.error().message;
    }
    std::fprintf(stderr, "error: %s%s\n", message.c_str(), rescued.c_str());
    app.exitCode = 1;
    app.running = false;
}

void restoreRecovery(EditorApp& app) {
    if (!app.ui.recovery) return;
    if (app.loader.busy()) {
        app.ui.recovery->restoreWhenIdle = true;
        return;
    }
    finishAutosave(app);
    LoadRequest request{app.recoveryDir};
    request.fromRecovery = true;
    request.recoveredSource = app.ui.recovery->source;
    app.ui.recovery.reset();
    startLoad(app, std::move(request));
}

void discardRecovery(EditorApp& app) {
    finishAutosave(app);
    removeRecovery(app.recoveryDir);
    app.ui.recovery.reset();
    app.ui.status = "Discarded the recovered work";
}

bool edit(EditorApp& app, const Edit& e) {
    if (app.loader.busy()) {
        app.ui.status = "Wait for the file to finish loading before editing.";
        return false;
    }
    Result<EditReport> report = applyEdit(*app.doc, e, app.frame);
    if (!report) {
        showError(app, "Edit failed: " + report.error().message);
        return false;
    }
    if (!app.doc->animationNote.empty()) app.ui.status = describeEdit(e) + ": " + app.doc->animationNote;
    return true;
}

Bounds selectionBounds(const EditorApp& app) {
    const Document& doc = *app.doc;
    if (!doc.planned) return Bounds{};
    const Cage& cage = doc.planned->cage();
    const Bounds model = computeBounds(cage);
    const std::vector<uint32_t> vertices = selectedVertices(doc.selection, cage);
    if (vertices.empty()) return model;
    Bounds b{cage.positions[vertices[0]], cage.positions[vertices[0]]};
    for (uint32_t v : vertices) {
        b.min = glm::min(b.min, cage.positions[v]);
        b.max = glm::max(b.max, cage.positions[v]);
    }
    // A single vertex still gets some room around it.
    const glm::vec3 pad(0.05f * model.diagonal());
    b.min -= pad;
    b.max += pad;
    return b;
}

void frameSelection(EditorApp& app, uint32_t viewport, bool wholeModel) {
    if (!app.doc->planned) return;
    // In the world: every visible object, or the selection carried by the active object's transform.
    const Document& doc = *app.doc;
    const uint32_t object = app.mode == EditorMode::Object ? selectedObject(doc) : kNoObject;
    const Bounds b = wholeModel ? documentBounds(doc)
                     : app.mode == EditorMode::Object
                         ? (object == kNoObject ? documentBounds(doc)
                                                : transformBounds(objectCageBounds(doc, object), doc.scene.objects[object].transform.matrix()))
                         : transformBounds(selectionBounds(app), activeObject(doc).transform.matrix());
    const VkRect2D r = app.viewports[std::min<size_t>(viewport, app.viewports.size() - 1)].rect;
    const float aspect = r.extent.height ? float(r.extent.width) / float(r.extent.height) : 1.0f;
    frameBox(cameraOf(app, viewport), b.min, b.max, aspect);
}

UpAxis upAxisOf(const EditorApp& app) { return app.display.upAxis.value_or(UpAxis::Y); }

void setUpAxis(EditorApp& app, UpAxis up) {
    app.display.upAxis = up;
    ViewCamera camera;
    camera.up = up;
    camera.fovY = app.sharedCamera.fovY;
    camera.orthographic = app.sharedCamera.orthographic;
    camera.yaw = glm::radians(35.0f);
    camera.pitch = glm::radians(25.0f);
    app.sharedCamera = camera;
    for (ViewportState& v : app.viewports) v.camera = camera;
    app.frameAfterLayout = true;
}

namespace {

// Save As proposes a scene beside the file: NAME.json for a cage NAME.obj (saving the scene
// keeps the view and display settings; the .obj stays as it is unless chosen).
std::string proposedSaveAsPath(const std::string& path) {
    if (path.empty()) return (std::filesystem::current_path() / "untitled.json").string();
    return std::filesystem::path(path).replace_extension(".json").string();
}

// The timeline's actions (playback.h).
void runAnimationAction(EditorApp& app, std::string_view id) {
    if (id == "anim.play") togglePlayback(app);
    else if (id == "anim.prev_frame") stepFrame(app, -1);
    else if (id == "anim.next_frame") stepFrame(app, 1);
    else if (id == "anim.first_frame") jumpToEnd(app, false);
    else if (id == "anim.last_frame") jumpToEnd(app, true);
    else if (id == "anim.prev_key") jumpToKey(app, -1);
    else if (id == "anim.next_key") jumpToKey(app, 1);
    else if (id == "anim.loop") app.doc->loopPlayback = !app.doc->loopPlayback;
    else if (id == "anim.insert_key") insertKeyTool(app);
    else if (id == "anim.delete_keys") deleteKeysTool(app);
    else if (id == "anim.interpolation") toggleInterpolationTool(app);
    else showError(app, "unknown action '" + std::string(id) + "'");
}

}  // namespace

void runAction(EditorApp& app, std::string_view id) {
    const uint32_t active = app.activeViewport;
    auto standard = [&](StandardView v) { setStandardView(cameraOf(app, active), v); };
    const ActionScope scope = scopeOf(id);
    if ((scope == ActionScope::EditMode || scope == ActionScope::SculptTool) && app.mode == EditorMode::Object) {
        app.ui.status = "That works on a cage in edit mode: Tab edits the selected object's cage.";
        return;
    }
    if (scope == ActionScope::ObjectMode && app.mode == EditorMode::Edit) {
        app.ui.status = "That works on whole objects in object mode: Tab leaves edit mode.";
        return;
    }
    if (app.job.busy() && id != "file.quit") {
        app.ui.status = app.job.title() + " is still running: wait for it to finish.";
        return;
    }
    if (id == "file.open") {
        const std::filesystem::path parent = std::filesystem::path(app.doc->path).parent_path();
        std::error_code error;
        const std::filesystem::path dir = parent.empty() ? std::filesystem::current_path(error)
                                                         : std::filesystem::absolute(parent, error);
        app.ui.openPath = (dir / "").string();
        app.ui.requestPopup = "Open";
    } else if ((id == "file.save" || id == "file.save_as" || id == "file.export") && (!app.doc->planned || app.loader.busy())) {
        app.ui.status = "Nothing to save while no cage is open or a file is loading.";
    } else if ((id == "file.import" || id == "file.bake") && (!app.doc->planned || app.loader.busy())) {
        app.ui.status = "Open a scene first: Import adds objects to it, Bake writes its displacement.";
    } else if (id == "file.import") {
        app.ui.importPath = (std::filesystem::path(proposedExportPath(*app.doc)).parent_path() / "").string();
        app.ui.requestPopup = "Import";
    } else if (id == "file.bake") {
        app.ui.bakePath = std::filesystem::path(proposedExportPath(*app.doc)).replace_extension(".exr").string();
        app.ui.requestPopup = "Bake";
    } else if (id == "file.export") {
        app.ui.exportPath = proposedExportPath(*app.doc);
        app.ui.requestPopup = "Export";
    } else if (id == "file.save") {
        if (app.doc->path.empty()) runAction(app, "file.save_as");
        else saveTo(app, app.doc->path);
    } else if (id == "file.save_as") {
        app.ui.saveAsPath = proposedSaveAsPath(app.doc->path);
        app.ui.requestPopup = "Save As";
    } else if (id == "file.quit") {
        requestQuit(app);
    } else if (id == "edit.undo") {
        undoTool(app);
    } else if (id == "edit.redo") {
        redoTool(app);
    } else if (id == "edit.history") {
        app.ui.showHistory = !app.ui.showHistory;
    } else if (id == "select.vertex_mode") {
        setMode(app, SelectionMode::Vertex);
    } else if (id == "select.edge_mode") {
        setMode(app, SelectionMode::Edge);
    } else if (id == "select.face_mode") {
        setMode(app, SelectionMode::Face);
    } else if (id == "select.all") {
        selectAllElements(app);
    } else if (id == "select.none") {
        clearSelection(*app.doc);
    } else if (id == "select.invert") {
        invertSelectedElements(app);
    } else if (id == "select.grow") {
        growSelected(app);
    } else if (id == "select.shrink") {
        shrinkSelected(app);
    } else if (id == "tool.select") {
        app.tools.tool = Tool::Select;
    } else if (id == "tool.move") {
        app.tools.tool = Tool::Move;
    } else if (id == "tool.rotate") {
        app.tools.tool = Tool::Rotate;
    } else if (id == "tool.scale") {
        app.tools.tool = Tool::Scale;
    } else if (id == "tool.sculpt") {
        app.tools.tool = Tool::Sculpt;
    } else if (id == "sculpt.smaller") {
        scaleBrushRadius(app, 1.0f / 1.25f);
    } else if (id == "sculpt.larger") {
        scaleBrushRadius(app, 1.25f);
    } else if (id.starts_with("brush.")) {
        runBrushAction(app, id);
    } else if (id == "tool.space") {
        app.tools.space = app.tools.space == TransformSpace::World ? TransformSpace::Local : TransformSpace::World;
    } else if (id == "mesh.extrude") {
        startInteractiveExtrude(app);
    } else if (id == "mesh.hide") {
        hideSelection(app);
    } else if (id == "mesh.unhide") {
        unhideAllFaces(app);
    } else if (id == "mesh.delete") {
        deleteSelection(app);
    } else if (id == "mesh.split") {
        splitSelection(app);
    } else if (id == "mesh.loop_tool") {
        app.tools.loopTool = !app.tools.loopTool;
        app.ui.status = app.tools.loopTool ? "Loop tool: click an edge to cut a loop across it (Esc cancels)" : "Loop tool off";
    } else if (id == "mesh.loop") {
        loopOnSelectedEdge(app);
    } else if (id == "mesh.merge") {
        mergeSelection(app);
    } else if (id == "mesh.make_face") {
        makeFaceFromSelection(app);
    } else if (id == "mesh.hole") {
        toggleSelectionHoles(app);
    } else if (id == "crease.apply" || id == "crease.clear") {
        const bool clear = id == "crease.clear";
        if (app.doc->selection.mode == SelectionMode::Vertex) cornerSelection(app, clear ? 0.0f : app.tools.cornerSharpness);
        else creaseSelection(app, clear ? 0.0f : app.tools.edgeSharpness);
    } else if (id == "view.heatmap") {
        app.viewports[std::min<size_t>(active, app.viewports.size() - 1)].heatMap ^= true;
    } else if (id == "view.frame") {
        frameSelection(app, active, false);
    } else if (id == "view.frame_all") {
        frameSelection(app, active, true);
    } else if (id == "view.front") {
        standard(StandardView::Front);
    } else if (id == "view.back") {
        standard(StandardView::Back);
    } else if (id == "view.right") {
        standard(StandardView::Right);
    } else if (id == "view.left") {
        standard(StandardView::Left);
    } else if (id == "view.top") {
        standard(StandardView::Top);
    } else if (id == "view.bottom") {
        standard(StandardView::Bottom);
    } else if (id == "view.projection") {
        cameraOf(app, active).orthographic = !cameraOf(app, active).orthographic;
    } else if (id == "layout.one") {
        setViewportCount(app, 1);
        app.frameAfterLayout = true;
    } else if (id == "layout.two") {
        setViewportCount(app, 2);
        app.frameAfterLayout = true;
    } else if (id == "layout.four") {
        setViewportCount(app, 4);
        app.frameAfterLayout = true;
    } else if (id == "display.cage") {
        app.tessellation.showCage = !app.tessellation.showCage;
    } else if (id == "display.dense_cage") {
        app.display.denseCageLines = !app.display.denseCageLines;
    } else if (id == "display.wireframe") {
        app.tessellation.showWireframe = !app.tessellation.showWireframe;
    } else if (id == "help.toggle") {
        app.ui.showHelp = !app.ui.showHelp;
    } else if (id == "mode.toggle") {
        toggleEditMode(app);
    } else if (id == "object.delete") {
        deleteSelectedObject(app);
    } else if (id == "object.duplicate" || id == "object.instance") {
        duplicateSelectedObject(app, id == "object.instance");
    } else if (id == "object.hide") {
        hideSelectedObject(app);
    } else if (id == "object.unhide") {
        unhideAllObjects(app);
    } else if (id == "object.deselect") {
        selectObject(*app.doc, kNoObject);
    } else if (id.starts_with("anim.")) {
        runAnimationAction(app, id);
    } else {
        showError(app, "unknown action '" + std::string(id) + "'");
    }
}

}  // namespace qp::editor
