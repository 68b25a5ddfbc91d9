// The Scene tab: the outliner (every object: select, show or hide, rename, duplicate, instance,
// delete, add from a file) and the selected object's transform typed in. Every change is an
// object edit of document_objects.h, one undo entry each.
#include "panel_sections.h"

#include <cstdio>
#include <string>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "document_objects.h"
#include "editor_app.h"
#include "object_mode.h"
#include "panel_widgets.h"

namespace qp::editor {

namespace {

// One outliner row: visibility box, then the name (instances show their source, the object
// whose cage edit mode is on is marked). Click selects, double click edits its cage.
void objectRow(EditorApp& app, uint32_t i) {
    Document& doc = *app.doc;
    const SceneObject& object = doc.scene.objects[i];
    const std::string id = std::to_string(doc.objectIds[i]);
    bool visible = object.visible;
    if (checkbox(app, ("##visible" + id).c_str(), &visible, "Show or hide the object (H / Alt+H in object mode)"))
        if (Status done = setObjectVisible(doc, i, visible, app.frame); !done) showError(app, done.error().message);
    ImGui::SameLine();
    std::string label = object.name;
    if (object.isInstance()) label += "  -> " + object.instanceOf;
    if (cageOwnerOf(doc, i) == doc.activeObject && !object.isInstance()) label += "  [cage in edit mode]";
    const std::string widget = label + "##object" + id;
    const bool selected = selectedObject(doc) == i;
    if (ImGui::Selectable(widget.c_str(), selected, ImGuiSelectableFlags_AllowDoubleClick) || pressedByAutomation(app, widget.c_str())) {
        selectObject(doc, i);
        if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) enterEditMode(app);
    }
    recordWidget(app, widget.c_str());
}

// Location, rotation and scale typed in: Enter applies the field as one history entry.
void transformFields(EditorApp& app, uint32_t object) {
    Document& doc = *app.doc;
    const ObjectTransform before = doc.scene.objects[object].transform;
    auto field = [&](const char* label, glm::vec3 ObjectTransform::*member, const char* help) {
        ObjectTransform t = before;
        const bool entered = ImGui::InputFloat3(label, &(t.*member).x, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue);
        recordWidget(app, label);
        tooltip(app, label, help);
        if (!entered || t == before) return;
        if (Status done = setObjectTransform(doc, object, before, t, app.frame); !done)
            showError(app, "Transform refused: " + done.error().message);
    };
    field("Location", &ObjectTransform::translation, "The object's origin in the world (Enter applies)");
    field("Rotation", &ObjectTransform::rotationDegrees, "Degrees about x, then y, then z: XYZ Euler (Enter applies)");
    field("Scale", &ObjectTransform::scale, "Along the object's own axes; negative mirrors, zero is refused (Enter applies)");
}

}  // namespace

void sceneSection(EditorApp& app) {
    Document& doc = *app.doc;
    if (!doc.planned) return;
    const bool objectMode = app.mode == EditorMode::Object;
    if (radio(app, "Object mode", objectMode, "Pick and place whole objects (Tab)")) enterObjectMode(app);
    ImGui::SameLine();
    if (radio(app, "Edit mode", !objectMode, "Edit the selected object's cage (Tab)")) enterEditMode(app);

    ImGui::Text("Outliner: %zu objects", doc.scene.objects.size());
    if (ImGui::BeginChild("##outliner", ImVec2(0.0f, 150.0f), true))
        for (uint32_t i = 0; i < doc.scene.objects.size(); ++i) objectRow(app, i);
    ImGui::EndChild();

    const uint32_t object = selectedObject(doc);
    if (object == kNoObject) {
        ImGui::TextWrapped("Click an object (object mode) or a row above to select it.");
    } else {
        if (button(app, "Edit cage", "Edit mode on this object's cage (Tab; an instance edits its source's)")) enterEditMode(app);
        ImGui::SameLine();
        if (button(app, "Frame##object", "Frame the selected object (F in object mode)")) frameSelection(app, app.activeViewport, false);
        if (button(app, "Duplicate", "A copy with a cage of its own, beside it (Shift+D)")) duplicateSelectedObject(app, false);
        ImGui::SameLine();
        if (button(app, "Instance", "An instance sharing this cage, beside it (Alt+D)")) duplicateSelectedObject(app, true);
        ImGui::SameLine();
        if (button(app, "Delete##object", "Delete the object (X; refused while instanced)")) deleteSelectedObject(app);

        if (app.ui.renameObjectId != doc.objectIds[object]) {
            app.ui.renameText = doc.scene.objects[object].name;
            app.ui.renameObjectId = doc.objectIds[object];
        }
        if (ImGui::InputText("Name", &app.ui.renameText, ImGuiInputTextFlags_EnterReturnsTrue)) {
            if (Status done = renameObject(doc, object, app.ui.renameText, app.frame); !done)
                showError(app, "Rename refused: " + done.error().message);
            app.ui.renameObjectId = 0;  // shows the name the object has now
        }
        recordWidget(app, "Name");
        tooltip(app, "Name", "Type a new name and press Enter (instances follow it)");
        transformFields(app, object);
    }

    ImGui::SetNextItemWidth(-110.0f);
    ImGui::InputText("##addpath", &app.ui.addObjectPath);
    recordWidget(app, "##addpath");
    ImGui::SameLine();
    if (button(app, "Add from file", "Add the objects of a scene (.json) or a cage (.obj) to this scene"))
        addObjectFromFile(app, app.ui.addObjectPath);
}

}  // namespace qp::editor
