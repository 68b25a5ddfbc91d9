// The editor's objects without a window (editor/app/document_objects.h): moving edit mode
// between cages, object edits in the one history, undo across objects and modes, instances
// following their cage, adding objects from files, and handle drags becoming transforms.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "document.h"
#include "document_objects.h"
#include "gizmo.h"
#include "mesh/obj_io.h"
#include "object_mode.h"
#include "test_cages.h"

using namespace qp;
using namespace qp::editor;
namespace fs = std::filesystem;

namespace {

// A cube ("box"), an instance of it ("box.001", moved), and a grid of its own ("floor").
std::unique_ptr<Document> threeObjects() {
    Scene scene = sceneOfCage(test::makeSubdividedCube(2), "box");
    SceneObject instance;
    instance.name = "box.001";
    instance.instanceOf = "box";
    instance.transform.translation = {3.0f, 0.0f, 0.0f};
    scene.objects.push_back(instance);
    SceneObject floor;
    floor.name = "floor";
    floor.cage = test::makeGrid(3);
    floor.transform.translation = {0.0f, 0.0f, -2.0f};
    scene.objects.push_back(floor);
    Result<std::unique_ptr<Document>> doc = createDocument(scene, "", PlanOptions{});
    EXPECT_TRUE(doc.ok()) << doc.error().message;
    return doc ? std::move(doc).value() : nullptr;
}

uint32_t indexOf(const Document& doc, const std::string& name) { return findObject(doc.scene.objects, name); }

// A crease on the first edge of the edited cage's first face.
SetEdgeSharpness creaseFirstEdge(const Document& doc, float sharpness) {
    const Cage& cage = doc.planned->cage();
    const uint32_t a = cage.faceBegin(0)[0], b = cage.faceBegin(0)[1];
    return SetEdgeSharpness{{{std::min(a, b), std::max(a, b), sharpness}}};
}

}  // namespace

TEST(EditorObjects, EditModeMovesBetweenCagesAndUndoFollowsTheEntry) {
    std::unique_ptr<Document> doc = threeObjects();
    ASSERT_TRUE(doc);
    const uint32_t box = indexOf(*doc, "box"), instance = indexOf(*doc, "box.001"), floor = indexOf(*doc, "floor");
    EXPECT_EQ(doc->activeObject, box);
    EXPECT_EQ(cageOwnerOf(*doc, instance), box);
    EXPECT_EQ(&plannedCageOf(*doc, instance), &*doc->planned);
    const uint32_t boxFaces = doc->planned->cage().faceCount(), floorFaces = plannedCageOf(*doc, floor).cage().faceCount();

    // Crease the box, then edit the floor and move a vertex there.
    ASSERT_TRUE(applyEdit(*doc, creaseFirstEdge(*doc, 2.0f), 1));
    const size_t plans = doc->database->size();
    const uint64_t objects = doc->objectsRevision;
    ASSERT_TRUE(editObjectCage(*doc, floor));
    EXPECT_EQ(doc->activeObject, floor);
    EXPECT_GT(doc->objectsRevision, objects);
    EXPECT_EQ(doc->planned->cage().faceCount(), floorFaces);
    EXPECT_EQ(plannedCageOf(*doc, box).cage().faceCount(), boxFaces);
    EXPECT_EQ(doc->database->size(), plans) << "moving edit mode re-planned";
    const glm::vec3 before = doc->planned->cage().positions[0];
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {before + glm::vec3(0, 0, 1)}}, 2));

    // Undo takes the move back on the floor, then the crease on the box (edit mode follows).
    ASSERT_TRUE(undoEdit(*doc, 3));
    EXPECT_EQ(doc->activeObject, floor);
    EXPECT_EQ(doc->planned->cage().positions[0], before);
    ASSERT_TRUE(undoEdit(*doc, 4));
    EXPECT_EQ(doc->activeObject, box) << "undoing the box's crease did not go back to the box";
    EXPECT_EQ(doc->planned->cage().creases.size(), 0u);
    // Redo both: each on its own cage again.
    ASSERT_TRUE(redoEdit(*doc, 5));
    EXPECT_EQ(doc->planned->cage().creases.size(), 1u);
    ASSERT_TRUE(redoEdit(*doc, 6));
    EXPECT_EQ(doc->activeObject, floor);
    EXPECT_EQ(doc->planned->cage().positions[0], before + glm::vec3(0, 0, 1));
    // Jumping back over both entries works across the cages too.
    ASSERT_TRUE(jumpToHistory(*doc, 0, 7));
    EXPECT_EQ(plannedCageOf(*doc, floor).cage().positions[0], before);
    EXPECT_EQ(plannedCageOf(*doc, box).cage().creases.size(), 0u);
    EXPECT_TRUE(plannedCageOf(*doc, floor).differencesFromRebuild().empty());
    EXPECT_TRUE(plannedCageOf(*doc, box).differencesFromRebuild().empty());

    // Saving takes every cage as it is now, the one in edit mode included.
    ASSERT_TRUE(jumpToHistory(*doc, 2, 8));
    const Scene saved = sceneToSave(*doc);
    EXPECT_EQ(saved.objects[box].cage.creases.size(), 1u);
    EXPECT_EQ(saved.objects[floor].cage.positions[0], before + glm::vec3(0, 0, 1));
}

TEST(EditorObjects, ObjectEditsAreHistoryEntriesThatUndo) {
    std::unique_ptr<Document> doc = threeObjects();
    ASSERT_TRUE(doc);
    const uint32_t floor = indexOf(*doc, "floor");
    ObjectTransform moved = doc->scene.objects[floor].transform;
    moved.translation.y = 5.0f;
    moved.rotationDegrees.z = 30.0f;
    ASSERT_TRUE(setObjectTransform(*doc, floor, doc->scene.objects[floor].transform, moved, 1));
    EXPECT_EQ(doc->scene.objects[floor].transform, moved);
    EXPECT_TRUE(doc->dirty);
    ObjectTransform flat = moved;
    flat.scale.y = 0.0f;
    EXPECT_FALSE(setObjectTransform(*doc, floor, moved, flat, 2)) << "a zero scale was taken";
    EXPECT_EQ(doc->history.size(), 1u);

    ASSERT_TRUE(setObjectVisible(*doc, floor, false, 3));
    ASSERT_TRUE(renameObject(*doc, indexOf(*doc, "box"), "crate", 4));
    EXPECT_EQ(doc->scene.objects[indexOf(*doc, "box.001")].instanceOf, "crate") << "the instance did not follow the name";
    EXPECT_FALSE(renameObject(*doc, floor, "crate", 5)) << "a taken name was accepted";
    EXPECT_FALSE(renameObject(*doc, floor, "", 5));

    ASSERT_TRUE(undoEdit(*doc, 6));
    EXPECT_EQ(doc->scene.objects[indexOf(*doc, "box.001")].instanceOf, "box");
    ASSERT_TRUE(undoEdit(*doc, 7));
    EXPECT_TRUE(doc->scene.objects[floor].visible);
    ASSERT_TRUE(undoEdit(*doc, 8));
    EXPECT_EQ(doc->scene.objects[floor].transform.translation, glm::vec3(0, 0, -2));
    EXPECT_FALSE(doc->dirty) << "undoing every object edit should be clean";
    EXPECT_EQ(doc->activeObject, indexOf(*doc, "box")) << "an object edit moved edit mode";
}

TEST(EditorObjects, DeleteDuplicateAndInstanceKeepCagesAndLinks) {
    std::unique_ptr<Document> doc = threeObjects();
    ASSERT_TRUE(doc);
    // The box is instanced: refused; the instance goes, then the box (in edit mode) can.
    EXPECT_FALSE(deleteObject(*doc, indexOf(*doc, "box"), 1));
    ASSERT_TRUE(deleteObject(*doc, indexOf(*doc, "box.001"), 2));
    ASSERT_TRUE(applyEdit(*doc, creaseFirstEdge(*doc, 3.0f), 3));  // an edit on the box before it goes
    ASSERT_TRUE(deleteObject(*doc, indexOf(*doc, "box"), 4));
    ASSERT_EQ(doc->scene.objects.size(), 1u);
    EXPECT_EQ(doc->scene.objects[doc->activeObject].name, "floor") << "edit mode did not move off the deleted cage";
    EXPECT_FALSE(deleteObject(*doc, 0, 5)) << "the last object was deleted";

    // Undo brings the box back with its crease, then takes the crease back on the box's cage
    // (edit mode follows), then brings the instance back, linked, in its place.
    ASSERT_TRUE(undoEdit(*doc, 6));
    ASSERT_EQ(doc->scene.objects.size(), 2u);
    EXPECT_EQ(doc->scene.objects[0].name, "box");
    EXPECT_EQ(plannedCageOf(*doc, 0).cage().creases.size(), 1u);
    ASSERT_TRUE(undoEdit(*doc, 7));
    EXPECT_EQ(doc->activeObject, 0u);
    EXPECT_EQ(doc->planned->cage().creases.size(), 0u);
    ASSERT_TRUE(undoEdit(*doc, 8));
    ASSERT_EQ(doc->scene.objects.size(), 3u);
    EXPECT_EQ(doc->scene.objects[1].name, "box.001");
    EXPECT_EQ(cageOwnerOf(*doc, 1), 0u);
    EXPECT_FALSE(doc->dirty);

    // A duplicate has a cage of its own (its plans are the box's: none added); an instance shares it.
    const size_t plans = doc->database->size();
    Result<uint32_t> copy = duplicateObject(*doc, 0, false, 9);
    ASSERT_TRUE(copy) << copy.error().message;
    EXPECT_EQ(doc->scene.objects[*copy].name, "box.002");
    EXPECT_FALSE(doc->scene.objects[*copy].isInstance());
    EXPECT_NE(&plannedCageOf(*doc, *copy), &*doc->planned);
    EXPECT_GT(doc->scene.objects[*copy].transform.translation.x, 0.0f) << "not placed beside the original";
    Result<uint32_t> linked = duplicateObject(*doc, 1, true, 10);  // an instance of an instance links to the cage
    ASSERT_TRUE(linked) << linked.error().message;
    EXPECT_EQ(doc->scene.objects[*linked].instanceOf, "box");
    EXPECT_EQ(selectedObject(*doc), *linked);
    EXPECT_EQ(doc->database->size(), plans) << "duplicates and instances planned new configurations";
    // Editing the copy leaves the box alone; the instances follow the box.
    ASSERT_TRUE(editObjectCage(*doc, *copy));
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{2}, {glm::vec3(0, 0, 9)}}, 11));
    EXPECT_NE(plannedCageOf(*doc, 0).cage().positions[2], glm::vec3(0, 0, 9));
    ASSERT_TRUE(undoEdit(*doc, 12));
    ASSERT_TRUE(undoEdit(*doc, 13));
    ASSERT_TRUE(undoEdit(*doc, 14));
    EXPECT_EQ(doc->scene.objects.size(), 3u);
}

TEST(EditorObjects, AddsObjectsFromCageAndSceneFiles) {
    const fs::path dir = fs::temp_directory_path() / ("quadplan_editor_objects_" + std::to_string(getpid()));
    fs::create_directories(dir);
    ASSERT_TRUE(saveObj(test::makeCube(), (dir / "box.obj").string()));
    std::unique_ptr<Document> doc = threeObjects();
    ASSERT_TRUE(doc);
    Result<uint32_t> added = addObjectsFromFile(*doc, (dir / "box.obj").string(), 1);
    ASSERT_TRUE(added) << added.error().message;
    EXPECT_EQ(doc->scene.objects[*added].name, "box.002") << "named after the file, made unique";
    EXPECT_TRUE(doc->scene.objects[*added].cagePath.empty()) << "the source file would be written on save";
    // A scene of two objects, one an instance of the other named like ours: links renamed with them.
    Scene other = sceneOfCage(test::makeCube(), "floor");
    SceneObject link;
    link.name = "floor.copy";
    link.instanceOf = "floor";
    other.objects.push_back(link);
    ASSERT_TRUE(saveScene(other, (dir / "two.json").string(), CageStorage::Inline));
    Result<uint32_t> two = addObjectsFromFile(*doc, (dir / "two.json").string(), 2);
    ASSERT_TRUE(two) << two.error().message;
    ASSERT_EQ(doc->scene.objects.size(), 6u);
    EXPECT_EQ(doc->scene.objects[*two].name, "floor.001");
    EXPECT_EQ(doc->scene.objects[*two + 1].instanceOf, "floor.001");
    EXPECT_EQ(cageOwnerOf(*doc, *two + 1), *two);
    // Bad files change nothing and say why.
    Result<uint32_t> missing = addObjectsFromFile(*doc, (dir / "nowhere.obj").string(), 3);
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("nowhere.obj"), std::string::npos) << missing.error().message;
    EXPECT_EQ(doc->scene.objects.size(), 6u);
    ASSERT_TRUE(undoEdit(*doc, 4));
    ASSERT_TRUE(undoEdit(*doc, 5));
    EXPECT_EQ(doc->scene.objects.size(), 3u);
    fs::remove_all(dir);
}

TEST(EditorObjects, HandleDragsBecomeTheObjectsTransform) {
    ObjectTransform start;
    start.translation = {1, 2, 3};
    start.rotationDegrees = {0, 0, 30};
    start.scale = {1, 2, 1};
    GizmoShape shape;
    shape.frame.pivot = start.translation;
    // Rotating 45 degrees about the world's z through the origin: the matrix composes.
    shape.mode = GizmoMode::Rotate;
    GizmoDrag turn;
    turn.matrix = glm::translate(glm::mat4(1.0f), start.translation) *
                  glm::rotate(glm::mat4(1.0f), glm::radians(45.0f), glm::vec3(0, 0, 1)) *
                  glm::translate(glm::mat4(1.0f), -start.translation);
    std::optional<ObjectTransform> turned = draggedTransform(start, shape, turn);
    ASSERT_TRUE(turned);
    EXPECT_NEAR(turned->rotationDegrees.z, 75.0f, 1e-3f);
    EXPECT_EQ(turned->translation, start.translation);
    const glm::mat4 expected = turn.matrix * start.matrix(), got = turned->matrix();
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(got[c][r], expected[c][r], 1e-4f);
    // Scaling multiplies along the object's own axes; a zero factor is refused.
    shape.mode = GizmoMode::Scale;
    GizmoDrag grow;
    grow.values = {2, 1, 0.5f};
    std::optional<ObjectTransform> grown = draggedTransform(start, shape, grow);
    ASSERT_TRUE(grown);
    EXPECT_EQ(grown->scale, glm::vec3(2, 2, 0.5f));
    grow.values = {0, 1, 1};
    EXPECT_FALSE(draggedTransform(start, shape, grow));
    // Moving carries the origin by the drag.
    shape.mode = GizmoMode::Move;
    GizmoDrag move;
    move.matrix = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0, 0));
    EXPECT_EQ(draggedTransform(start, shape, move)->translation, glm::vec3(1.5f, 2, 3));
}
