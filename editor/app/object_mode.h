// Object mode: what the left button, the transform handle and the object shortcuts do when
// whole objects are edited (document_objects.h holds the edits; this file turns clicks, drags
// and keys into them). Picking finds the visible object whose cage the cursor's ray meets first;
// the handle sits at the picked object's origin in world axes or the object's own (L), and a
// drag shows the object's new transform live and makes one history entry when it ends.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "edit/picking.h"
#include "edit/transform.h"
#include "gizmo.h"
#include "scene/scene_objects.h"

namespace qp::editor {

struct EditorApp;

// A raycaster per cage (the edited one and every other), remade when objects or the edited
// cage change.
struct ObjectPickCache {
    uint64_t generation = ~0ull, objectsRevision = ~0ull;  // what `others` was made for
    uint64_t otherPositionRevision = ~0ull;                 // ... (animated cages move)
    uint64_t positionRevision = ~0ull;                      // ... and `edited` (vertex moves)
    std::optional<CageRaycaster> edited;
    std::vector<std::optional<CageRaycaster>> others;  // parallel to Document::otherCages, built on demand
};

// The visible object under the cursor (framebuffer pixels), or UINT32_MAX.
uint32_t pickObjectAt(EditorApp& app, uint32_t viewport, glm::vec2 cursor);
// Selects the object under the cursor, or nothing over empty space.
void clickObject(EditorApp& app, uint32_t viewport, glm::vec2 cursor);

// The handle's frame for the selected object: its origin, world axes or its own.
std::optional<TransformFrame> objectFrame(const EditorApp& app);
// The selected object's transform after a handle drag `drag` from `start`. Scales act along the
// object's own axes whatever the space (an object's transform cannot shear).
std::optional<ObjectTransform> draggedTransform(const ObjectTransform& start, const GizmoShape& shape, const GizmoDrag& drag);

// Tab: edit mode on the selected object's cage (its owner's for an instance), or back to
// object mode (the object edited stays selected).
void toggleEditMode(EditorApp& app);
void enterObjectMode(EditorApp& app);
bool enterEditMode(EditorApp& app);

// The object shortcuts (they act on the selected object; each reports in the status line).
bool deleteSelectedObject(EditorApp& app);
bool duplicateSelectedObject(EditorApp& app, bool linked);
bool hideSelectedObject(EditorApp& app);
void unhideAllObjects(EditorApp& app);
bool addObjectFromFile(EditorApp& app, const std::string& path);

}  // namespace qp::editor
