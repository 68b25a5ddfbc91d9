#include "tools.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "edit/edge_loops.h"
#include "editor_app.h"
#include "scheme_support.h"

namespace qp::editor {

namespace {

constexpr float kVertexPickPixels = 12.0f, kEdgePickPixels = 8.0f;
// A point is hidden when the limit surface lies this far (times the cage's diagonal) in front
// of it: cage vertices on the surface (boundaries, sharp corners) stay pickable.
constexpr float kVisibilityTolerance = 2e-3f;

PickView pickViewOf(const ViewportState& v) {
    return PickView{v.viewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
}

glm::vec2 inViewport(const ViewportState& v, glm::vec2 cursor) {
    return cursor - glm::vec2(float(v.rect.offset.x), float(v.rect.offset.y));
}

bool haveCage(EditorApp& app) {
    if (app.doc->planned && !app.loader.busy()) return true;
    app.ui.status = "No cage is open (or a file is still loading).";
    return false;
}

std::optional<Occluder> occluderFor(EditorApp& app) {
    if (!app.tools.visibleOnly) return std::nullopt;
    const LimitPicker& picker = limitPicker(app.picking, *app.doc, app.documentGeneration);
    return limitOccluder(picker, *app.doc->planned, kVisibilityTolerance * pickTolerance(*app.doc));
}

std::string millis(double ms) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f ms", ms);
    return text;
}

// Applies the edit; the status line says what it re-planned.
bool perform(EditorApp& app, const Edit& e) {
    Result<EditReport> report = applyEdit(*app.doc, e, app.frame);
    if (!report) {
        showError(app, "Edit failed: " + report.error().message);
        return false;
    }
    std::string text = describeEdit(e);
    text[0] = char(std::toupper(text[0]));
    app.ui.status = text + ": re-planned " + std::to_string(report->replannedFaces) + " faces in " +
                    millis(report->milliseconds);
    if (!app.doc->animationNote.empty()) app.ui.status += "; " + app.doc->animationNote;
    return true;
}

// perform() for a live slider: replaces the entry the same drag made, if it is still the newest.
bool performLive(EditorApp& app, const Edit& e) {
    Document& doc = *app.doc;
    const bool continuing = app.ui.liveEditEntry && *app.ui.liveEditEntry == doc.history.position() &&
                            doc.history.position() == doc.history.size();
    if (!continuing) {
        if (!perform(app, e)) return false;
    } else if (Result<EditReport> report = replaceLastEdit(doc, e, app.frame); !report) {
        showError(app, "Edit failed: " + report.error().message);
        return false;
    } else {
        app.ui.status = describeEdit(e) + ": re-planned " + std::to_string(report->replannedFaces) + " faces";
    }
    app.ui.liveEditEntry = doc.history.position();
    return true;
}

bool refuse(EditorApp& app, const std::string& message) {
    showError(app, message);
    return false;
}

std::vector<uint32_t> selectionVertices(const EditorApp& app) {
    return selectedVertices(app.doc->selection, app.doc->planned->cage());
}

bool historyStep(EditorApp& app, Result<EditReport> report, const char* what) {
    if (!report) {
        app.ui.status = std::string(what) + ": " + report.error().message;
        return false;
    }
    app.ui.status = app.doc->lastEdit->description + ": re-planned " + std::to_string(report->replannedFaces) +
                    " faces in " + millis(report->milliseconds);
    return true;
}

}  // namespace

PickHit pickAt(EditorApp& app, uint32_t viewport, glm::vec2 cursor) {
    PickHit hit;
    if (!app.doc->planned) return hit;
    const Document& doc = *app.doc;
    const ViewportState& v = app.viewports[viewport];
    const PickView view = pickViewOf(v);
    const glm::vec2 pixel = inViewport(v, cursor);
    hit.mode = doc.selection.mode;
    switch (hit.mode) {
    case SelectionMode::Vertex: {
        std::optional<Occluder> occluder = occluderFor(app);
        const VertexPick pick = pickVertex(doc.planned->cage(), view, pixel, kVertexPickPixels, occluder ? &*occluder : nullptr);
        hit.element = pick.vertex;
        hit.hit = pick.vertex != kNoHit && !isVertexHidden(doc, pick.vertex);
        break;
    }
    case SelectionMode::Edge:
        return pickEdgeAt(app, viewport, cursor);
    case SelectionMode::Face: {
        if (app.tools.facesOnSurface) {
            const LimitPicker& picker = limitPicker(app.picking, doc, app.documentGeneration);
            const LimitPicker::Hit onSurface = picker.intersect(*doc.planned, view.rayThrough(pixel));
            if (onSurface.subface != kNoHit && !isFaceHidden(doc, faceOfSubface(*doc.planned, onSurface.subface))) {
                hit.element = faceOfSubface(*doc.planned, onSurface.subface);
                hit.hit = true;
                break;
            }
        }
        const CageRaycaster::Hit onCage = pickFace(cageRaycaster(app.picking, doc, app.documentGeneration), view, pixel);
        hit.element = onCage.face;
        hit.hit = onCage.face != kNoHit && !isFaceHidden(doc, onCage.face);
        break;
    }
    }
    return hit;
}

std::vector<bool> pickableVertices(EditorApp& app, uint32_t viewport) {
    std::vector<bool> pickable;
    if (!app.doc->planned) return pickable;
    const PickView view = pickViewOf(app.viewports[viewport]);
    std::optional<Occluder> occluder = occluderFor(app);
    for (const glm::vec3& p : app.doc->planned->cage().positions)
        pickable.push_back(isVisible(view, p, occluder ? &*occluder : nullptr));
    return pickable;
}

PickHit pickEdgeAt(EditorApp& app, uint32_t viewport, glm::vec2 cursor) {
    PickHit hit;
    hit.mode = SelectionMode::Edge;
    if (!app.doc->planned) return hit;
    const ViewportState& v = app.viewports[viewport];
    std::optional<Occluder> occluder = occluderFor(app);
    const EdgePick pick = pickEdge(app.doc->planned->cage(), app.doc->planned->topology(), pickViewOf(v),
                                   inViewport(v, cursor), kEdgePickPixels, occluder ? &*occluder : nullptr);
    hit.hit = pick.hit && !isEdgeHidden(*app.doc, pick.edge);
    hit.edge = pick.edge;
    hit.edgeT = pick.t;
    return hit;
}

void applyPickHit(EditorApp& app, const PickHit& hit, SelectOp op) {
    Document& doc = *app.doc;
    if (!doc.planned) return;
    if (!hit.hit) {
        if (op == SelectOp::Replace) clearSelection(doc);
        return;
    }
    Status s = success();
    if (hit.mode == SelectionMode::Edge) {
        const EdgeKey edges[] = {hit.edge};
        s = selectEdges(doc, edges, op);
    } else {
        const uint32_t elements[] = {hit.element};
        s = selectElements(doc, hit.mode, elements, op);
    }
    if (!s) app.ui.status = s.error().message;
}

void boxSelectIn(EditorApp& app, uint32_t viewport, glm::vec2 cornerA, glm::vec2 cornerB, SelectOp op) {
    if (!app.doc->planned || viewport >= app.viewports.size()) return;
    Document& doc = *app.doc;
    const ViewportState& v = app.viewports[viewport];
    std::optional<Occluder> occluder = occluderFor(app);
    Selection boxed = boxSelect(doc.planned->cage(), doc.planned->topology(), doc.selection.mode, pickViewOf(v),
                                inViewport(v, cornerA), inViewport(v, cornerB), occluder ? &*occluder : nullptr);
    dropHidden(doc, boxed);
    if (boxed.mode == SelectionMode::Edge) applyPick(doc.selection, op, std::span<const EdgeKey>(boxed.edges));
    else applyPick(doc.selection, op, boxed.mode == SelectionMode::Vertex ? boxed.vertices : boxed.faces);
    app.ui.status = "Box: " + std::to_string(boxed.size()) + " elements; " + std::to_string(doc.selection.size()) + " selected";
}

bool selectLoopAt(EditorApp& app, uint32_t viewport, glm::vec2 cursor, LoopKind kind, SelectOp op) {
    if (!haveCage(app)) return false;
    const PickHit hit = pickEdgeAt(app, viewport, cursor);
    if (!hit.hit) {
        app.ui.status = "No edge under the cursor for a loop";
        return false;
    }
    Document& doc = *app.doc;
    const Cage& cage = doc.planned->cage();
    const Topology& topology = doc.planned->topology();
    Selection loop;
    loop.mode = doc.selection.mode;
    if (loop.mode == SelectionMode::Face) {
        loop.faces = faceLoop(cage, topology, hit.edge);
    } else {
        Selection edges;
        edges.mode = SelectionMode::Edge;
        edges.edges = kind == LoopKind::Ring ? edgeRing(cage, topology, hit.edge) : edgeLoop(cage, topology, hit.edge);
        loop = convertSelection(edges, loop.mode, cage, topology);
    }
    dropHidden(doc, loop);
    if (loop.mode == SelectionMode::Edge) applyPick(doc.selection, op, std::span<const EdgeKey>(loop.edges));
    else applyPick(doc.selection, op, loop.mode == SelectionMode::Vertex ? loop.vertices : loop.faces);
    const char* what = loop.mode == SelectionMode::Face ? "Face loop" : kind == LoopKind::Ring ? "Edge ring" : "Edge loop";
    app.ui.status = std::string(what) + ": " + std::to_string(loop.size()) + " elements; " +
                    std::to_string(doc.selection.size()) + " selected";
    return true;
}

void setMode(EditorApp& app, SelectionMode mode) { setSelectionMode(*app.doc, mode); }

void selectAllElements(EditorApp& app) {
    if (!app.doc->planned) return;
    Document& doc = *app.doc;
    doc.selection = selectAll(doc.planned->cage(), doc.planned->topology(), doc.selection.mode);
    dropHidden(doc, doc.selection);
}

void invertSelectedElements(EditorApp& app) {
    if (!app.doc->planned) return;
    Document& doc = *app.doc;
    doc.selection = invertSelection(doc.selection, doc.planned->cage(), doc.planned->topology());
    dropHidden(doc, doc.selection);
}

void growSelected(EditorApp& app) {
    if (!app.doc->planned) return;
    Document& doc = *app.doc;
    doc.selection = growSelection(doc.selection, doc.planned->cage(), doc.planned->topology());
    dropHidden(doc, doc.selection);
}

void shrinkSelected(EditorApp& app) {
    if (!app.doc->planned) return;
    Document& doc = *app.doc;
    doc.selection = shrinkSelection(doc.selection, doc.planned->cage(), doc.planned->topology());
}

std::optional<TransformFrame> selectionFrame(const EditorApp& app) {
    if (!app.doc->planned) return std::nullopt;
    const std::vector<uint32_t> vertices = selectionVertices(app);
    if (vertices.empty()) return std::nullopt;
    return makeTransformFrame(app.doc->planned->cage(), app.doc->planned->topology(), vertices, app.tools.space);
}

bool transformSelection(EditorApp& app, NumericTransform kind, const glm::vec4& values) {
    if (!haveCage(app)) return false;
    const std::optional<TransformFrame> frame = selectionFrame(app);
    if (!frame) return refuse(app, "Nothing to transform: select vertices, edges or faces first.");
    glm::mat4 matrix(1.0f);
    std::string name;
    switch (kind) {
    case NumericTransform::Move: matrix = translation(*frame, glm::vec3(values)), name = "move"; break;
    case NumericTransform::Rotate:
        if (!(glm::length(glm::vec3(values)) > 0.0f)) return refuse(app, "Rotate: the axis must not be zero.");
        matrix = rotation(*frame, glm::normalize(glm::vec3(values)), values.w), name = "rotate";
        break;
    case NumericTransform::Scale: matrix = scaling(*frame, glm::vec3(values)), name = "scale"; break;
    }
    const std::vector<uint32_t> vertices = selectionVertices(app);
    Result<std::vector<glm::vec3>> moved = transformPoints(positionsOf(app.doc->planned->cage(), vertices), matrix);
    if (!moved) return refuse(app, "Transform refused: " + moved.error().message);
    return perform(app, MoveVertices{vertices, std::move(moved).value(), false, name});
}

bool extrudeSelection(EditorApp& app) {
    if (!haveCage(app)) return false;
    std::vector<uint32_t> faces = selectedFaces(*app.doc);
    if (faces.empty()) return refuse(app, "Extrude needs selected faces (face mode, 3).");
    return perform(app, ExtrudeFaces{std::move(faces), app.tools.extrudeDistance});
}

bool deleteSelection(EditorApp& app) {
    if (!haveCage(app)) return false;
    std::vector<uint32_t> faces = selectedFaces(*app.doc);
    if (faces.empty()) return refuse(app, "Delete removes faces: select faces (or vertices or edges spanning whole faces).");
    return perform(app, DeleteFaces{std::move(faces)});
}

bool splitSelection(EditorApp& app) {
    if (!haveCage(app)) return false;
    const std::vector<uint32_t> vertices = selectionVertices(app);
    if (vertices.size() != 2) return refuse(app, "Split face needs exactly two selected vertices of one face.");
    const Cage& cage = app.doc->planned->cage();
    const Topology& topology = app.doc->planned->topology();
    const uint32_t a = vertices[0], b = vertices[1];
    for (uint32_t k = topology.vertexFaceOffsets[a]; k < topology.vertexFaceOffsets[a + 1]; ++k) {
        const uint32_t f = topology.vertexFaces[k];
        const uint32_t n = cage.faceSize(f);
        const uint32_t* fv = cage.faceBegin(f);
        for (uint32_t i = 0; i < n; ++i)
            if (fv[i] == b && fv[(i + 1) % n] != a && fv[(i + n - 1) % n] != a) return perform(app, SplitFace{f, a, b});
    }
    return refuse(app, "Vertices " + std::to_string(a) + " and " + std::to_string(b) +
                           " are not two non-adjacent corners of one face: nothing to split.");
}

bool insertLoop(EditorApp& app, uint32_t a, uint32_t b, float t) {
    if (!haveCage(app)) return false;
    return perform(app, InsertEdgeLoop{a, b, t});
}

bool loopOnSelectedEdge(EditorApp& app) {
    if (!haveCage(app)) return false;
    const std::vector<EdgeKey> edges = selectedEdges(*app.doc);
    if (edges.size() != 1) return refuse(app, "Insert loop needs exactly one selected edge (edge mode, 2), or use the loop tool (Ctrl+R).");
    return insertLoop(app, edges[0].v0, edges[0].v1, app.tools.loopFraction);
}

bool mergeSelection(EditorApp& app) {
    if (!haveCage(app)) return false;
    std::vector<uint32_t> vertices = selectionVertices(app);
    if (vertices.size() < 2) return refuse(app, "Merge needs at least two selected vertices.");
    return perform(app, MergeVertices{std::move(vertices), app.tools.mergeTarget});
}

bool makeFaceFromSelection(EditorApp& app) {
    if (!haveCage(app)) return false;
    std::vector<uint32_t> vertices = selectionVertices(app);
    if (vertices.size() < 3) return refuse(app, "Make face needs at least three selected vertices.");
    // Around their centre, in the plane of the faces around them (makeFace fixes the winding).
    const Cage& cage = app.doc->planned->cage();
    const glm::mat3 axes = localAxes(cage, app.doc->planned->topology(), vertices);
    const glm::vec3 centre = centroid(cage, vertices);
    std::vector<std::pair<float, uint32_t>> around;
    for (uint32_t v : vertices) {
        const glm::vec3 d = cage.positions[v] - centre;
        around.push_back({std::atan2(glm::dot(d, axes[1]), glm::dot(d, axes[0])), v});
    }
    std::sort(around.begin(), around.end());
    for (size_t i = 0; i < around.size(); ++i) vertices[i] = around[i].second;
    return perform(app, MakeFace{std::move(vertices)});
}

bool creaseSelection(EditorApp& app, float sharpness) {
    if (!haveCage(app)) return false;
    SetEdgeSharpness crease;
    for (const EdgeKey& e : selectedEdges(*app.doc)) crease.edges.push_back({e.v0, e.v1, sharpness});
    if (crease.edges.empty()) return refuse(app, "Crease needs selected edges (edge mode, 2).");
    return perform(app, crease);
}

bool cornerSelection(EditorApp& app, float sharpness) {
    if (!haveCage(app)) return false;
    SetVertexSharpness corner;
    for (uint32_t v : selectionVertices(app)) corner.corners.push_back({v, sharpness});
    if (corner.corners.empty()) return refuse(app, "Corner sharpness needs selected vertices (vertex mode, 1).");
    return perform(app, corner);
}

bool creaseSelectionLive(EditorApp& app, float sharpness) {
    if (!haveCage(app)) return false;
    SetEdgeSharpness crease;
    for (const EdgeKey& e : selectedEdges(*app.doc)) crease.edges.push_back({e.v0, e.v1, sharpness});
    return !crease.edges.empty() && performLive(app, crease);
}

bool cornerSelectionLive(EditorApp& app, float sharpness) {
    if (!haveCage(app)) return false;
    SetVertexSharpness corner;
    for (uint32_t v : selectionVertices(app)) corner.corners.push_back({v, sharpness});
    return !corner.corners.empty() && performLive(app, corner);
}

void endLiveEdit(EditorApp& app) { app.ui.liveEditEntry.reset(); }

bool setSelectionHoles(EditorApp& app, bool hole) {
    if (!haveCage(app)) return false;
    std::vector<uint32_t> faces = selectedFaces(*app.doc);
    if (faces.empty()) return refuse(app, "Holes are faces: select faces first (face mode, 3).");
    return perform(app, SetHoles{std::move(faces), hole});
}

bool toggleSelectionHoles(EditorApp& app) {
    if (!haveCage(app)) return false;
    const std::vector<uint32_t> faces = selectedFaces(*app.doc);
    const bool allHoles = !faces.empty() && std::all_of(faces.begin(), faces.end(), [&](uint32_t f) {
        return app.doc->planned->cage().isHole(f);
    });
    return setSelectionHoles(app, !allHoles);
}

bool hideSelection(EditorApp& app) {
    if (!haveCage(app)) return false;
    const std::vector<uint32_t> faces = selectedFaces(*app.doc);
    if (faces.empty()) return refuse(app, "Hide needs selected faces (or vertices or edges spanning whole faces).");
    if (Status s = hideFaces(*app.doc, faces); !s) return refuse(app, s.error().message);
    app.ui.status = "Hid " + std::to_string(faces.size()) + " faces (" + std::to_string(app.doc->hiddenFaces.size()) +
                    " hidden; Alt+H shows them)";
    return true;
}

void unhideAllFaces(EditorApp& app) {
    if (!app.doc->planned) return;
    const size_t hidden = app.doc->hiddenFaces.size();
    unhideAll(*app.doc);
    app.ui.status = "Showing " + std::to_string(hidden) + " hidden faces again";
}

bool setCreaseMethodTool(EditorApp& app, CreaseMethod method) {
    if (!haveCage(app)) return false;
    if (app.doc->planned->cage().options.creaseMethod == method) return false;
    return perform(app, SetCreaseMethod{method});
}

bool undoTool(EditorApp& app) {
    if (!haveCage(app)) return false;
    return historyStep(app, undoEdit(*app.doc, app.frame), "Undo");
}

bool redoTool(EditorApp& app) {
    if (!haveCage(app)) return false;
    return historyStep(app, redoEdit(*app.doc, app.frame), "Redo");
}

bool jumpHistoryTool(EditorApp& app, size_t position) {
    if (!haveCage(app)) return false;
    return historyStep(app, jumpToHistory(*app.doc, position, app.frame), "History");
}

}  // namespace qp::editor
