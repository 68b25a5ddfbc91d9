#include "object_mode.h"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "document_objects.h"
#include "editor_app.h"
#include "tools.h"

namespace qp::editor {

namespace {

const CageRaycaster& raycasterOf(EditorApp& app, uint32_t cage) {
    Document& doc = *app.doc;
    ObjectPickCache& cache = app.objectPicking;
    // Vertex moves change only the edited cage; adding, removing or switching cages any, and an
    // animation frame the animated ones.
    if (cache.generation != app.documentGeneration || cache.objectsRevision != doc.objectsRevision ||
        cache.otherPositionRevision != doc.otherPositionRevision) {
        cache.others.assign(doc.otherCages.size(), std::nullopt);
        cache.edited.reset();
        cache.generation = app.documentGeneration;
        cache.objectsRevision = doc.objectsRevision;
        cache.otherPositionRevision = doc.otherPositionRevision;
    }
    if (cache.positionRevision != doc.positionRevision) {
        cache.edited.reset();
        cache.positionRevision = doc.positionRevision;
    }
    if (cage == kActiveCage) {
        if (!cache.edited) cache.edited.emplace(doc.planned->cage());
        return *cache.edited;
    }
    if (!cache.others[cage]) cache.others[cage].emplace(doc.otherCages[cage].cage());
    return *cache.others[cage];
}

std::string objectName(const EditorApp& app, uint32_t object) { return "\"" + app.doc->scene.objects[object].name + "\""; }

bool haveObject(EditorApp& app, uint32_t object) {
    if (object != kNoObject) return true;
    app.ui.status = "No object is selected: click one (object mode) or pick it in the Outliner.";
    return false;
}

bool report(EditorApp& app, const Status& done, const std::string& what) {
    if (!done) {
        showError(app, what + " failed: " + done.error().message);
        return false;
    }
    app.ui.status = what;
    return true;
}

}  // namespace

uint32_t pickObjectAt(EditorApp& app, uint32_t viewport, glm::vec2 cursor) {
    const Document& doc = *app.doc;
    if (!doc.planned || viewport >= app.viewports.size()) return kNoObject;
    const ViewportState& v = app.viewports[viewport];
    const PickView view{v.worldViewProjection, glm::vec2(float(v.rect.extent.width), float(v.rect.extent.height))};
    const Ray ray = view.rayThrough(cursor - glm::vec2(float(v.rect.offset.x), float(v.rect.offset.y)));
    uint32_t best = kNoObject;
    float nearest = kNoDistance;
    for (uint32_t i = 0; i < doc.scene.objects.size(); ++i) {
        const SceneObject& object = doc.scene.objects[i];
        if (!object.visible) continue;
        const glm::mat4 matrix = object.transform.matrix(), inverse = glm::inverse(matrix);
        const glm::vec3 direction = glm::vec3(inverse * glm::vec4(ray.direction, 0.0f));
        if (!(glm::length(direction) > 0.0f)) continue;
        const Ray local{glm::vec3(inverse * glm::vec4(ray.origin, 1.0f)), glm::normalize(direction)};
        const CageRaycaster::Hit hit = raycasterOf(app, doc.otherCageOfObject[i]).intersect(local);
        if (hit.face == kNoHit) continue;
        const float distance = glm::length(glm::vec3(matrix * glm::vec4(hit.position, 1.0f)) - ray.origin);
        if (distance < nearest) nearest = distance, best = i;
    }
    return best;
}

void clickObject(EditorApp& app, uint32_t viewport, glm::vec2 cursor) {
    const uint32_t object = pickObjectAt(app, viewport, cursor);
    selectObject(*app.doc, object);
    app.ui.status = object == kNoObject ? "Nothing selected" : "Selected " + objectName(app, object);
}

std::optional<TransformFrame> objectFrame(const EditorApp& app) {
    const Document& doc = *app.doc;
    const uint32_t object = doc.planned ? selectedObject(doc) : kNoObject;
    if (object == kNoObject) return std::nullopt;
    const ObjectTransform& t = doc.scene.objects[object].transform;
    TransformFrame frame;
    frame.pivot = t.translation;
    if (app.tools.space == TransformSpace::Local || app.tools.tool == Tool::Scale) {
        ObjectTransform rotationOnly;
        rotationOnly.rotationDegrees = t.rotationDegrees;
        frame.axes = glm::mat3(rotationOnly.matrix());
    }
    return frame;
}

std::optional<ObjectTransform> draggedTransform(const ObjectTransform& start, const GizmoShape& shape, const GizmoDrag& drag) {
    ObjectTransform t = start;
    switch (shape.mode) {
    case GizmoMode::Move: t.translation = glm::vec3(drag.matrix * glm::vec4(start.translation, 1.0f)); return t;
    case GizmoMode::Scale: t.scale = start.scale * drag.values; break;
    case GizmoMode::Rotate: {
        Result<ObjectTransform> turned = decomposeTransform(drag.matrix * start.matrix());
        if (!turned) return std::nullopt;
        t = *turned;
        t.translation = start.translation;  // the pivot is the origin: keep it exact
        break;
    }
    }
    for (int i = 0; i < 3; ++i)
        if (!(std::abs(t.scale[i]) > 1e-6f) || !std::isfinite(t.scale[i])) return std::nullopt;
    return t;
}

void enterObjectMode(EditorApp& app) {
    if (app.mode == EditorMode::Object) return;
    cancelDrag(app);
    app.tools.loopTool = false;
    if (app.tools.tool == Tool::Sculpt) app.tools.tool = Tool::Select;
    app.mode = EditorMode::Object;
    app.ui.selectTab = "Scene";
    if (selectedObject(*app.doc) == kNoObject) selectObject(*app.doc, app.doc->activeObject);
    app.ui.status = "Object mode: click an object to select it, W / E / R to place it, Tab to edit its cage";
}

bool enterEditMode(EditorApp& app) {
    Document& doc = *app.doc;
    if (!doc.planned) return false;
    uint32_t object = selectedObject(doc);
    if (object == kNoObject) object = doc.activeObject;
    cancelDrag(app);
    if (Status moved = editObjectCage(doc, object); !moved) return report(app, moved, "Edit mode");
    selectObject(doc, object);
    if (app.mode != EditorMode::Edit) app.ui.selectTab = "Model";
    app.mode = EditorMode::Edit;
    const uint32_t owner = doc.activeObject;
    app.ui.status = "Edit mode: the cage of " + objectName(app, owner) +
                    (owner != object ? " (" + objectName(app, object) + " is an instance of it)" : "");
    return true;
}

void toggleEditMode(EditorApp& app) {
    if (app.mode == EditorMode::Edit) enterObjectMode(app);
    else enterEditMode(app);
}

bool deleteSelectedObject(EditorApp& app) {
    const uint32_t object = selectedObject(*app.doc);
    if (!haveObject(app, object)) return false;
    const std::string name = objectName(app, object);
    return report(app, deleteObject(*app.doc, object, app.frame), "Deleted " + name);
}

bool duplicateSelectedObject(EditorApp& app, bool linked) {
    const uint32_t object = selectedObject(*app.doc);
    if (!haveObject(app, object)) return false;
    Result<uint32_t> added = duplicateObject(*app.doc, object, linked, app.frame);
    if (!added) return report(app, added.error(), linked ? "Instance" : "Duplicate");
    app.ui.status = (linked ? "Made instance " : "Duplicated as ") + objectName(app, *added) + " (beside it; move it with W)";
    return true;
}

bool hideSelectedObject(EditorApp& app) {
    const uint32_t object = selectedObject(*app.doc);
    if (!haveObject(app, object)) return false;
    return report(app, setObjectVisible(*app.doc, object, false, app.frame), "Hid " + objectName(app, object));
}

void unhideAllObjects(EditorApp& app) {
    Document& doc = *app.doc;
    for (uint32_t i = 0; i < doc.scene.objects.size(); ++i)
        if (!doc.scene.objects[i].visible) (void)report(app, setObjectVisible(doc, i, true, app.frame), "Showed every object");
}

bool addObjectFromFile(EditorApp& app, const std::string& path) {
    Result<uint32_t> added = addObjectsFromFile(*app.doc, path, app.frame);
    if (!added) return report(app, added.error(), "Adding " + path);
    app.ui.status = "Added " + objectName(app, *added) + " from " + path;
    return true;
}

}  // namespace qp::editor
