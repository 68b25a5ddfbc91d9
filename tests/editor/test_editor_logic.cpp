// The editor's parts that need no window: automation parsing, the orbit camera, screen-space
// picking, the document's edit route and saving, recovery files, frame statistics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "automation.h"
#include "cage_pick.h"
#include "document.h"
#include "frame_stats.h"
#include "gizmo.h"
#include "mesh/file_io.h"
#include "recovery.h"
#include "test_cages.h"
#include "view_camera.h"
#include "viewport_input.h"

using namespace qp;
using namespace qp::editor;
namespace fs = std::filesystem;

namespace {

fs::path scratchDir(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / ("quadplan_editor_logic_" + std::to_string(getpid())) / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::unique_ptr<Document> cubeDocument() {
    Scene scene = sceneOfCage(test::makeSubdividedCube(2), "cage");
    Result<std::unique_ptr<Document>> doc = createDocument(scene, "", PlanOptions{});
    EXPECT_TRUE(doc.ok()) << doc.error().message;
    return doc ? std::move(doc).value() : nullptr;
}

// --- automation scripts -------------------------------------------------------------------

TEST(AutomationScript, ParsesCommandsCommentsAndQuotedText) {
    Result<std::vector<AutomationCommand>> parsed = parseAutomation(
        "# a comment\n\nwait-frames 3\nclick-button \"Discard changes\"\nset-edge-sharpness 1 2 2.5 # trailing\n"
        "select-vertex 4 add\nkey KP7\nmeasure-frames 10 out.json drag\n",
        "script");
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    ASSERT_EQ(parsed->size(), 6u);
    EXPECT_EQ((*parsed)[0].line, 3);
    EXPECT_EQ((*parsed)[1].args, std::vector<std::string>{"Discard changes"});
    EXPECT_EQ((*parsed)[2].args, (std::vector<std::string>{"1", "2", "2.5"}));
    EXPECT_EQ((*parsed)[3].args, (std::vector<std::string>{"4", "add"}));
    EXPECT_EQ((*parsed)[5].args.size(), 3u);
}

TEST(AutomationScript, RejectsMistakesNamingTheLine) {
    struct Case {
        const char* text;
        const char* expected;
    } cases[] = {
        {"wait-frames 2\nfly-to-moon\n", "script:2: unknown command 'fly-to-moon'"},
        {"select-vertex -3\n", "not a whole number"},
        {"move-selection 1 2\n", "needs 3 argument"},
        {"move-selection 1 2 nan\n", "not a number"},
        {"wait-frames 1 2\n", "unexpected '2'"},
        {"action file.teleport\n", "unknown action"},
        {"key hyper\n", "unknown key"},
        {"mouse-down thumb\n", "left, middle or right"},
        {"measure-frames 5 out.json sprint\n", "'drag', 'orbit' or 'sculpt'"},
    };
    for (const Case& c : cases) {
        Result<std::vector<AutomationCommand>> parsed = parseAutomation(c.text, "script");
        ASSERT_FALSE(parsed.ok()) << c.text;
        EXPECT_NE(parsed.error().message.find(c.expected), std::string::npos) << parsed.error().message;
    }
}

// --- the orbit camera ---------------------------------------------------------------------

// Two presses that reach one frame must still be a double click (ImGui 1.86 would merge them).
TEST(ClickPairing, PairsPressesByTheirOwnTimesAndPlaces) {
    ClickPairing pairing;
    EXPECT_FALSE(pairPress(pairing, 10.0, {100, 100}, 0.3, 6.0));
    EXPECT_TRUE(pairPress(pairing, 10.09, {102, 101}, 0.3, 6.0)) << "a double click";
    EXPECT_FALSE(pairPress(pairing, 10.18, {102, 101}, 0.3, 6.0)) << "a third press starts a new pair";
    EXPECT_TRUE(pairPress(pairing, 10.25, {102, 101}, 0.3, 6.0));
    EXPECT_FALSE(pairPress(pairing, 20.0, {100, 100}, 0.3, 6.0));
    EXPECT_FALSE(pairPress(pairing, 20.5, {100, 100}, 0.3, 6.0)) << "too slow";
    EXPECT_FALSE(pairPress(pairing, 20.6, {120, 100}, 0.3, 6.0)) << "too far";
    EXPECT_TRUE(pairPress(pairing, 20.7, {121, 100}, 0.3, 6.0));
}

TEST(ViewCamera, OrbitPanAndDollyKeepWhatTheyShould) {
    ViewCamera c;
    c.target = {1, 2, 3};
    c.distance = 4;
    orbit(c, 100, 50, 400);
    EXPECT_NEAR(glm::length(eyePosition(c) - c.target), 4.0f, 1e-5f);
    EXPECT_EQ(c.target, glm::vec3(1, 2, 3));

    const glm::vec3 before = c.target, forward = glm::normalize(c.target - eyePosition(c));
    pan(c, 30, -20, 400);
    EXPECT_GT(glm::length(c.target - before), 0.0f);
    EXPECT_NEAR(glm::dot(c.target - before, forward), 0.0f, 1e-5f);  // in the view plane

    dolly(c, 1);
    EXPECT_LT(c.distance, 4.0f);
    for (int i = 0; i < 1000; ++i) dolly(c, 10);
    EXPECT_GT(c.distance, 0.0f);  // never through the target
}

TEST(ViewCamera, StandardViewsLookAlongTheAxes) {
    ViewCamera c;
    setStandardView(c, StandardView::Front);
    EXPECT_NEAR(glm::normalize(eyePosition(c) - c.target).z, 1.0f, 1e-5f);
    setStandardView(c, StandardView::Right);
    EXPECT_NEAR(glm::normalize(eyePosition(c) - c.target).x, 1.0f, 1e-5f);
    setStandardView(c, StandardView::Top);
    EXPECT_NEAR(glm::normalize(eyePosition(c) - c.target).y, 1.0f, 1e-5f);
    EXPECT_NEAR(upVector(c).z, -1.0f, 1e-5f);  // front at the bottom of the screen, as in Blender
    setStandardView(c, StandardView::Bottom);
    EXPECT_NEAR(glm::normalize(eyePosition(c) - c.target).y, -1.0f, 1e-5f);
}

TEST(ViewCamera, FramedBoxIsInsideTheViewForAnyAspect) {
    const glm::vec3 lo(-1, 0, -2), hi(3, 1, 0.5f);
    for (float aspect : {0.5f, 1.0f, 2.5f})
        for (bool ortho : {false, true}) {
            ViewCamera c;
            c.yaw = 0.7f;
            c.pitch = 0.4f;
            c.orthographic = ortho;
            frameBox(c, lo, hi, aspect);
            const glm::mat4 vp = viewProjection(renderCamera(c, aspect, Bounds{lo, hi}));
            for (int corner = 0; corner < 8; ++corner) {
                glm::vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
                glm::vec4 clip = vp * glm::vec4(p, 1.0f);
                glm::vec3 ndc = glm::vec3(clip) / clip.w;
                EXPECT_LE(std::abs(ndc.x), 1.0f) << aspect << " " << ortho;
                EXPECT_LE(std::abs(ndc.y), 1.0f) << aspect << " " << ortho;
                EXPECT_GE(ndc.z, 0.0f);
                EXPECT_LE(ndc.z, 1.0f);
            }
        }
}

TEST(ViewCamera, SceneCameraRoundTrip) {
    Camera s;
    s.eye = {3.4f, 2.6f, 3.8f};
    s.target = {0.1f, 0.75f, 0.0f};
    s.fovYDegrees = 35.0f;
    const Camera back = toSceneCamera(fromSceneCamera(s));
    EXPECT_NEAR(glm::length(back.eye - s.eye), 0.0f, 1e-4f);
    EXPECT_NEAR(glm::length(back.target - s.target), 0.0f, 1e-6f);
    EXPECT_NEAR(back.fovYDegrees, 35.0f, 1e-4f);
}

// Z up: yaw turns about z, the front view looks along +y (from -y), the top view down -z, and
// a scene camera survives the round trip.
TEST(ViewCamera, ZUpOrbitsAboutZAndKeepsBlendersViews) {
    ViewCamera c;
    c.up = UpAxis::Z;
    setStandardView(c, StandardView::Front);
    EXPECT_GT(glm::dot(glm::normalize(eyePosition(c) - c.target), glm::vec3(0, -1, 0)), 0.999f);
    EXPECT_GT(upVector(c).z, 0.999f);
    setStandardView(c, StandardView::Top);
    EXPECT_GT(glm::normalize(eyePosition(c) - c.target).z, 0.999f);
    setStandardView(c, StandardView::Right);
    EXPECT_GT(glm::normalize(eyePosition(c) - c.target).x, 0.999f);
    c.pitch = 0.3f;
    const float height = (eyePosition(c) - c.target).z;
    orbit(c, 120.0f, 0.0f, 600.0f);  // a horizontal drag: the eye keeps its height above the target
    EXPECT_NEAR((eyePosition(c) - c.target).z, height, 1e-4f);
    Camera s;
    s.eye = {3.4f, -2.6f, 3.8f};
    s.target = {0.1f, 0.75f, 0.2f};
    s.up = {0, 0, 1};
    const Camera back = toSceneCamera(fromSceneCamera(s, UpAxis::Z));
    EXPECT_NEAR(glm::length(back.eye - s.eye), 0.0f, 1e-4f);
    EXPECT_GT(back.up.z, 0.0f);
}

TEST(ViewCamera, GuessesTheUpAxisFromTheCagesExtent) {
    EXPECT_EQ(guessUpAxis(Bounds{{-1, -1, -1}, {1, 1, 1}}), UpAxis::Y);      // a cube: the old default
    EXPECT_EQ(guessUpAxis(Bounds{{-1, -0.5f, 0}, {1, 0.5f, 4}}), UpAxis::Z);  // a figure standing on z = 0
    EXPECT_EQ(guessUpAxis(Bounds{{-1, -0.5f, -2}, {1, 0.5f, 2}}), UpAxis::Y); // floating: no telling
    EXPECT_EQ(guessUpAxis(Bounds{{-1, -3, 0}, {1, 3, 1.5f}}), UpAxis::Z);     // a car standing on z = 0
    EXPECT_EQ(guessUpAxis(Bounds{{-1, 0, -3}, {1, 1.5f, 3}}), UpAxis::Y);     // the same car, Y up
    EXPECT_EQ(guessUpAxis(Bounds{{-1, -1, 0}, {1, 1, 0}}), UpAxis::Y);        // flat in the xy plane
}

// --- picking ------------------------------------------------------------------------------

TEST(CagePick, ADragMovesTheProjectionByThePixelsDragged) {
    const Cage cage = test::makeGrid(3);  // vertices at integer x, y in [0, 3]
    // Looking straight down -z at the grid's centre; one world unit = 100 pixels.
    ScreenMapping m;
    m.rect = {{10, 20}, {600, 600}};
    m.viewProjection = glm::ortho(-1.5f, 4.5f, 4.5f, -1.5f, -10.0f, 10.0f) *
                       glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    std::optional<glm::vec2> p = projectToWindow(m, cage.positions[5]);  // (1, 1)
    ASSERT_TRUE(p);
    // A drag of (30, -20) pixels moves the projection by exactly that.
    const glm::vec3 offset = dragOffset(m, cage.positions[5], {30, -20});
    std::optional<glm::vec2> moved = projectToWindow(m, cage.positions[5] + offset);
    EXPECT_NEAR(moved->x - p->x, 30.0f, 1e-3f);
    EXPECT_NEAR(moved->y - p->y, -20.0f, 1e-3f);
}

// --- the transform handle ----------------------------------------------------------------

// Looking down -z at the origin, orthographic, 100 pixels per world unit, in a 600 x 600 view.
PickView topView() {
    return PickView{glm::ortho(-3.0f, 3.0f, 3.0f, -3.0f, -10.0f, 10.0f) *
                        glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0)),
                    glm::vec2(600.0f)};
}

TEST(Gizmo, ShapeHitsAndAxisMoveFollowTheCursor) {
    const PickView view = topView();
    TransformFrame frame;
    frame.pivot = glm::vec3(0.5f, 0.0f, 0.0f);
    const GizmoShape shape = gizmoShape(GizmoMode::Move, frame, view, glm::vec3(0.5f, 0, 5), glm::vec3(0, 0, -1), true);
    ASSERT_TRUE(shape.visible);
    EXPECT_NEAR(shape.centre.x, 350.0f, 1e-3f);
    EXPECT_NEAR(glm::length(shape.axisEnd[0] - shape.centre), kGizmoPixels, 0.5f) << "the handle keeps its size on screen";
    EXPECT_NEAR(shape.worldLength, kGizmoPixels / 100.0f, 1e-3f);
    EXPECT_EQ(hitGizmo(shape, shape.centre + glm::vec2(2, -3)), GizmoHandle::View);
    EXPECT_EQ(hitGizmo(shape, glm::mix(shape.centre, shape.axisEnd[0], 0.7f) + glm::vec2(0, 3)), GizmoHandle::X);
    EXPECT_EQ(hitGizmo(shape, glm::mix(shape.centre, shape.axisEnd[1], 0.7f) + glm::vec2(3, 0)), GizmoHandle::Y);
    EXPECT_EQ(hitGizmo(shape, shape.centre + glm::vec2(60, 60)), GizmoHandle::None);
    // Grab the x arrow and drag 80 px right and 30 px down: only x changes, by 0.8.
    const glm::vec2 grab = glm::mix(shape.centre, shape.axisEnd[0], 0.5f);
    const GizmoDrag drag = dragGizmo(shape, GizmoHandle::X, view, grab, grab + glm::vec2(80, 30), false);
    EXPECT_NEAR(drag.values.x, 0.8f, 1e-4f);
    EXPECT_NEAR(drag.values.y, 0.0f, 1e-6f);
    const glm::vec3 moved = glm::vec3(drag.matrix * glm::vec4(1, 1, 0, 1));
    EXPECT_NEAR(moved.x, 1.8f, 1e-4f);
    EXPECT_NEAR(moved.y, 1.0f, 1e-6f);
    // With snapping: multiples of the power of ten below half the handle (0.45 -> 0.1).
    const GizmoDrag snapped = dragGizmo(shape, GizmoHandle::X, view, grab, grab + glm::vec2(83, 0), true);
    EXPECT_NEAR(snapped.values.x, 0.8f, 1e-4f);
    // The centre square moves in the view plane: (+50, +50) px is (+0.5, -0.5) in x, y (pixel y is down).
    const GizmoDrag plane = dragGizmo(shape, GizmoHandle::View, view, shape.centre, shape.centre + glm::vec2(50, 50), false);
    EXPECT_NEAR(plane.values.x, 0.5f, 1e-4f);
    EXPECT_NEAR(plane.values.y, -0.5f, 1e-4f);
    EXPECT_NEAR(plane.values.z, 0.0f, 1e-4f);
}

TEST(Gizmo, PerspectiveAxisDragKeepsTheGrabbedPointUnderTheCursor) {
    const glm::vec3 eye(3.0f, 2.5f, 6.0f);
    const PickView view{glm::perspective(glm::radians(40.0f), 1.0f, 0.1f, 50.0f) *
                            glm::lookAt(eye, glm::vec3(0.0f), glm::vec3(0, 1, 0)),
                        glm::vec2(800.0f)};
    TransformFrame frame;
    const GizmoShape shape = gizmoShape(GizmoMode::Move, frame, view, eye, glm::normalize(-eye), false);
    const glm::vec3 grabbed = frame.pivot + glm::vec3(0.5f * shape.worldLength, 0, 0);
    const glm::vec2 start = view.project(grabbed).pixel;
    const glm::vec3 target = grabbed + glm::vec3(0.7f, 0, 0);
    const glm::vec2 cursor = view.project(target).pixel;
    const GizmoDrag drag = dragGizmo(shape, GizmoHandle::X, view, start, cursor, false);
    EXPECT_NEAR(drag.values.x, 0.7f, 1e-3f);
    const glm::vec3 after = glm::vec3(drag.matrix * glm::vec4(grabbed, 1.0f));
    EXPECT_LT(glm::length(view.project(after).pixel - cursor), 0.05f);
}

TEST(Gizmo, RotateAndScaleHandles) {
    const PickView view = topView();
    TransformFrame frame;
    const GizmoShape ring = gizmoShape(GizmoMode::Rotate, frame, view, glm::vec3(0, 0, 5), glm::vec3(0, 0, -1), true);
    // The z ring faces the eye: a quarter turn counter-clockwise on screen is +90 degrees about z.
    const glm::vec2 c = ring.centre;
    EXPECT_EQ(hitGizmo(ring, c + glm::vec2(kGizmoPixels, 0)), GizmoHandle::Z);
    EXPECT_EQ(hitGizmo(ring, c + glm::vec2(0, -ring.viewRingRadius)), GizmoHandle::View);
    const GizmoDrag turn = dragGizmo(ring, GizmoHandle::Z, view, c + glm::vec2(90, 0), c + glm::vec2(0, -90), false);
    EXPECT_NEAR(turn.values.x, 90.0f, 1e-3f);
    const glm::vec3 turned = glm::vec3(turn.matrix * glm::vec4(1, 0, 0, 1));
    EXPECT_NEAR(turned.x, 0.0f, 1e-5f);
    EXPECT_NEAR(turned.y, 1.0f, 1e-5f);
    const GizmoDrag snapped = dragGizmo(ring, GizmoHandle::Z, view, c + glm::vec2(90, 0), c + glm::vec2(90, -30), true);
    EXPECT_NEAR(snapped.values.x, 15.0f, 1e-3f);  // 18.4 degrees snaps to 15

    const GizmoShape boxes = gizmoShape(GizmoMode::Scale, frame, view, glm::vec3(0, 0, 5), glm::vec3(0, 0, -1), true);
    // Dragging the x box out by the handle's length doubles x; the centre box scales evenly.
    const GizmoDrag wider = dragGizmo(boxes, GizmoHandle::X, view, boxes.axisEnd[0], boxes.axisEnd[0] + glm::vec2(kGizmoPixels, 0), false);
    EXPECT_NEAR(wider.values.x, 2.0f, 1e-3f);
    EXPECT_NEAR(wider.values.y, 1.0f, 1e-6f);
    const GizmoDrag even = dragGizmo(boxes, GizmoHandle::View, view, c + glm::vec2(40, 0), c + glm::vec2(20, 0), false);
    EXPECT_NEAR(even.values.x, 0.5f, 1e-4f);
    EXPECT_NEAR(even.values.z, 0.5f, 1e-4f);
}

// --- documents ----------------------------------------------------------------------------

TEST(Document, EditsGoThroughApplyEditAndBadOnesChangeNothing) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    EXPECT_EQ(documentTitle(*doc), "untitled");
    const glm::vec3 start = doc->planned->cage().positions[3];

    Result<EditReport> moved = applyEdit(*doc, MoveVertices{{3}, {start + glm::vec3(0, 1, 0)}}, 7);
    ASSERT_TRUE(moved.ok()) << moved.error().message;
    EXPECT_EQ(moved->replannedFaces, 0u);  // moving vertices re-plans nothing
    EXPECT_EQ(doc->planned->cage().positions[3], start + glm::vec3(0, 1, 0));
    EXPECT_EQ(doc->positionRevision, 1u);
    EXPECT_EQ(doc->planRevision, 0u);
    EXPECT_TRUE(doc->dirty);
    EXPECT_EQ(documentTitle(*doc), "untitled*");
    EXPECT_EQ(doc->lastEdit->frame, 7u);
    EXPECT_EQ(doc->lastEdit->description, "move vertex 3");
    EXPECT_EQ(doc->history.size(), 1u);

    EXPECT_FALSE(applyEdit(*doc, MoveVertices{{9999}, {glm::vec3(0)}}, 8).ok());
    EXPECT_FALSE(applyEdit(*doc, MoveVertices{{3}, {glm::vec3(NAN)}}, 8).ok());
    const Cage& cage = doc->planned->cage();
    const uint32_t a = cage.faceBegin(0)[0], b = cage.faceBegin(0)[1], opposite = cage.faceBegin(0)[2];
    Result<EditReport> notEdge = applyEdit(*doc, SetEdgeSharpness{{{a, opposite, 1.0f}}}, 8);
    ASSERT_FALSE(notEdge.ok());
    EXPECT_NE(notEdge.error().message.find("share no edge"), std::string::npos);
    EXPECT_FALSE(applyEdit(*doc, SetEdgeSharpness{{{a, b, -1.0f}}}, 8).ok());
    EXPECT_FALSE(applyEdit(*doc, ExtrudeFaces{{100000}, 0.1f}, 8).ok());
    EXPECT_EQ(doc->planRevision, 0u);
    EXPECT_EQ(doc->lastEdit->frame, 7u);
    EXPECT_EQ(doc->history.size(), 1u) << "failed edits leave no history entry";

    Result<EditReport> creased = applyEdit(*doc, SetEdgeSharpness{{{a, b, 3.0f}}}, 9);
    ASSERT_TRUE(creased.ok()) << creased.error().message;
    EXPECT_GT(creased->replannedFaces, 0u);
    EXPECT_EQ(doc->planRevision, 1u);
    EXPECT_EQ(doc->topologyRevision, 0u);
    EXPECT_FLOAT_EQ(doc->planned->cage().edgeSharpness(a, b), 3.0f);
    EXPECT_TRUE(doc->planned->differencesFromRebuild().empty());
}

// Every kind of edit through the document, then undo to the start restores the cage exactly,
// redo reaches the end again, and a jump lands on the state after that entry.
// After tag edits (a crease, a hole) the limit picker re-samples only what changed and picks
// exactly what a new one picks; the plan change reaches the renderer once.
TEST(Document, EveryEditUndoesRedoesAndJumps) {
    Scene scene = sceneOfCage(test::makeGrid(4), "cage");  // vertex (x, y) = y * 5 + x, face (x, y) = y * 4 + x
    Result<std::unique_ptr<Document>> created = createDocument(scene, "", PlanOptions{});
    ASSERT_TRUE(created.ok()) << created.error().message;
    Document& doc = **created;
    const Cage original = doc.planned->cage();
    std::vector<Cage> states{original};
    auto apply = [&](const Edit& e) {
        Result<EditReport> r = applyEdit(doc, e, 1);
        EXPECT_TRUE(r.ok()) << describeEdit(e) << ": " << (r ? "" : r.error().message);
        if (r) states.push_back(doc.planned->cage());
        return r ? *r : EditReport{};
    };
    const uint32_t facesBefore = doc.planned->cage().faceCount();
    EditReport extrude = apply(ExtrudeFaces{{5}, 0.5f});  // the interior face (1, 1)
    EXPECT_EQ(doc.planned->cage().faceCount(), facesBefore + 4);
    EXPECT_EQ(extrude.replannedFaces, 13u);  // the face, its 8 neighbours, 4 side quads (docs/editing.md)
    EXPECT_EQ(doc.selection.mode, SelectionMode::Vertex);  // the result in the current mode: the moved region
    EXPECT_EQ(doc.selection.vertices.size(), 4u);
    EXPECT_EQ(doc.topologyRevision, 1u);
    apply(DeleteFaces{{0}});
    EXPECT_EQ(doc.planned->cage().faceCount(), facesBefore + 3);
    // Indices from the current cage: corner k of face f.
    auto corner = [&](uint32_t f, uint32_t k) { return doc.planned->cage().faceBegin(f)[k]; };
    const uint32_t last = doc.planned->cage().faceCount() - 1;  // a side quad of the extrusion
    apply(SplitFace{last, corner(last, 0), corner(last, 2)});
    EXPECT_EQ(doc.planned->cage().faceCount(), facesBefore + 4);
    const uint32_t facesBeforeLoop = doc.planned->cage().faceCount();
    apply(InsertEdgeLoop{corner(1, 0), corner(1, 1), 0.25f});
    EXPECT_GT(doc.planned->cage().faceCount(), facesBeforeLoop);
    const uint32_t verticesBeforeMerge = doc.planned->cage().vertexCount();
    apply(MergeVertices{{corner(3, 0), corner(3, 1)}, MergeTarget::Centroid});
    EXPECT_EQ(doc.planned->cage().vertexCount(), verticesBeforeMerge - 1);
    apply(SetEdgeSharpness{{{std::min(corner(4, 0), corner(4, 1)), std::max(corner(4, 0), corner(4, 1)), 2.5f}}});
    apply(SetVertexSharpness{{{corner(4, 2), kInfiniteSharpness}}});
    apply(SetHoles{{2}, true});
    apply(SetCreaseMethod{CreaseMethod::Chaikin});
    apply(MoveVertices{{corner(6, 0), corner(6, 1)}, {glm::vec3(1, 0, 1), glm::vec3(2, 0, 1)}, false, "move"});
    ASSERT_EQ(doc.history.size(), states.size() - 1);
    EXPECT_TRUE(doc.planned->differencesFromRebuild().empty());

    auto same = [](const Cage& a, const Cage& b) {
        return a.positions == b.positions && a.faceOffsets == b.faceOffsets && a.faceVertices == b.faceVertices &&
               sameTopologyAndTags(a, b);
    };
    while (doc.history.canUndo()) ASSERT_TRUE(undoEdit(doc, 2).ok());
    EXPECT_TRUE(same(doc.planned->cage(), original)) << "undo to the start did not restore the cage";
    EXPECT_TRUE(doc.planned->differencesFromRebuild().empty());
    EXPECT_FALSE(undoEdit(doc, 2).ok());
    while (doc.history.canRedo()) ASSERT_TRUE(redoEdit(doc, 3).ok());
    EXPECT_TRUE(same(doc.planned->cage(), states.back()));
    ASSERT_TRUE(jumpToHistory(doc, 2, 4).ok());
    EXPECT_TRUE(same(doc.planned->cage(), states[2]));
    EXPECT_EQ(doc.history.position(), 2u);
    EXPECT_FALSE(jumpToHistory(doc, 99, 4).ok());
    // The selection never names elements that no longer exist.
    for (uint32_t v : doc.selection.vertices) EXPECT_LT(v, doc.planned->cage().vertexCount());
    // A new edit after the jump drops the entries that could have been redone.
    apply(MoveVertices{{0}, {glm::vec3(-1, -1, 0)}});
    EXPECT_EQ(doc.history.size(), 3u);
}

TEST(Document, ADragIsOneHistoryEntry) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    const glm::vec3 start = doc->planned->cage().positions[0];
    for (int step = 0; step < 5; ++step)
        ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {start + glm::vec3(0.1f * float(step + 1), 0, 0)}, step > 0, "move"}, 1).ok());
    EXPECT_EQ(doc->history.size(), 1u);
    // A second drag of the same vertex is its own entry.
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {start}, false, "move"}, 2).ok());
    EXPECT_EQ(doc->history.size(), 2u);
    ASSERT_TRUE(undoEdit(*doc, 3).ok());
    ASSERT_TRUE(undoEdit(*doc, 3).ok());
    EXPECT_EQ(doc->planned->cage().positions[0], start);
}

// The unsaved-changes marker follows the history: back at the saved state the document is
// clean; a new edit that makes the saved state unreachable (a dropped redo branch, a drag
// continuing the entry that ended at it) keeps it dirty for good.
TEST(Document, UndoingBackToTheSavedStateIsClean) {
    const fs::path dir = scratchDir("clean");
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    const glm::vec3 start = doc->planned->cage().positions[0];
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {start + glm::vec3(1, 0, 0)}}, 1).ok());
    EXPECT_TRUE(doc->dirty);
    ASSERT_TRUE(undoEdit(*doc, 2).ok());
    EXPECT_FALSE(doc->dirty) << "undone back to the file as opened";
    ASSERT_TRUE(redoEdit(*doc, 3).ok());
    EXPECT_TRUE(doc->dirty);
    ASSERT_TRUE(saveDocument(*doc, (dir / "cube.json").string()).ok());
    EXPECT_FALSE(doc->dirty);
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{1}, {glm::vec3(2, 2, 2)}}, 4).ok());
    EXPECT_TRUE(doc->dirty);
    ASSERT_TRUE(jumpToHistory(*doc, 1, 5).ok());
    EXPECT_FALSE(doc->dirty) << "jumped back to the saved state";
    ASSERT_TRUE(undoEdit(*doc, 6).ok());
    EXPECT_TRUE(doc->dirty);
    // A new edit here drops the redo entry leading to the saved state: dirty from now on.
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{2}, {glm::vec3(3, 3, 3)}}, 7).ok());
    ASSERT_TRUE(undoEdit(*doc, 8).ok());
    EXPECT_TRUE(doc->dirty) << "the saved state is not in the history any more";
    EXPECT_FALSE(doc->savedPosition.has_value());
    // Saved in the middle of a drag: continuing the drag changes the saved entry.
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {glm::vec3(4, 0, 0)}, false, "move"}, 9).ok());
    ASSERT_TRUE(saveDocument(*doc, (dir / "cube.json").string()).ok());
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {glm::vec3(5, 0, 0)}, true, "move"}, 10).ok());
    EXPECT_TRUE(doc->dirty);
    EXPECT_FALSE(doc->savedPosition.has_value());
}

// A stroke in the editor spans frames: dabs as the cursor moves, one history entry at the end.
// Its samples reach the renderer (unsyncedSamples) after every dab and after undo and redo;
// cancelling puts every sample back; the brushes' cache follows vertex moves. The first stroke
// on a cage without displacement makes one with the stroke, in the stroke's entry.
TEST(Document, AStrokeIsOneUndoableEntryAndReportsItsSamples) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    // From inside a sub-face across its edge into the next face.
    const glm::vec3 a = doc->planned->evaluate(0, 0.3f, 0.5f).position, b = doc->planned->evaluate(0, 1.0f, 0.7f).position;
    ASSERT_TRUE(beginStroke(*doc, 8, 1).ok());
    EXPECT_EQ(doc->history.size(), 0u) << "the first stroke's displacement has no entry of its own";
    EXPECT_FALSE(doc->scene.objects[0].displacement.empty());
    EXPECT_EQ(doc->displacementRevision, 1u);
    StrokeOptions options;
    options.brush = Brush{BrushKind::Raise, 0.2f, 0.1f, Falloff::Smooth};
    const uint64_t samplesBefore = doc->sampleRevision;
    EXPECT_GT(strokeTo(*doc, options, a), 0u);
    EXPECT_GT(doc->sampleRevision, samplesBefore);
    const std::vector<uint32_t> firstDab = takeUnsyncedSamples(*doc);
    EXPECT_FALSE(firstDab.empty());
    EXPECT_TRUE(std::is_sorted(firstDab.begin(), firstDab.end()));
    EXPECT_TRUE(takeUnsyncedSamples(*doc).empty()) << "taken once";
    for (int k = 1; k <= 8; ++k) strokeTo(*doc, options, glm::mix(a, b, float(k) / 8.0f));  // one frame each
    EXPECT_FALSE(takeUnsyncedSamples(*doc).empty());
    Result<EditReport> ended = endStroke(*doc, "Raise stroke", 2);
    ASSERT_TRUE(ended.ok()) << ended.error().message;
    EXPECT_EQ(ended->replannedFaces, 0u);
    ASSERT_EQ(doc->history.size(), 1u);
    EXPECT_EQ(doc->history.entry(0).name, "Raise stroke");
    EXPECT_TRUE(takeUnsyncedSamples(*doc).size() < doc->scene.objects[0].displacement.samples.size())
        << "ending the first stroke re-sent every sample";
    EXPECT_TRUE(doc->dirty);
    const std::vector<float> sculpted = doc->scene.objects[0].displacement.samples;
    EXPECT_GT(*std::max_element(sculpted.begin(), sculpted.end()), 0.0f);

    // The same path given whole to applyStroke dabs at the same places: the same samples.
    Displacement whole = makeDisplacement(doc->planned->cage(), doc->planned->topology(), 8);
    std::vector<glm::vec3> path{a};
    for (int k = 1; k <= 8; ++k) path.push_back(glm::mix(a, b, float(k) / 8.0f));
    applyStroke(whole, SculptSamples::build(*doc->planned, whole.layout), options, path);
    EXPECT_EQ(whole.samples, sculpted);

    takeUnsyncedSamples(*doc);
    const uint64_t revision = doc->displacementRevision;
    ASSERT_TRUE(undoEdit(*doc, 3).ok());
    EXPECT_TRUE(doc->scene.objects[0].displacement.empty()) << "undoing the first stroke removes the displacement too";
    EXPECT_GT(doc->displacementRevision, revision) << "undo must tell the renderer";
    ASSERT_TRUE(redoEdit(*doc, 4).ok());
    EXPECT_EQ(doc->scene.objects[0].displacement.samples, sculpted);

    // Cancelled: the samples go back, no entry.
    ASSERT_TRUE(beginStroke(*doc, 8, 5).ok());
    options.brush.kind = BrushKind::Lower;
    strokeTo(*doc, options, b);
    EXPECT_NE(doc->scene.objects[0].displacement.samples, sculpted);
    cancelStroke(*doc);
    EXPECT_EQ(doc->scene.objects[0].displacement.samples, sculpted);
    EXPECT_EQ(doc->history.size(), 1u);
    EXPECT_FALSE(strokeActive(*doc));

    // A vertex move refreshes the brushes' positions (as a fresh cache would have them).
    const glm::vec3 moved = doc->planned->cage().positions[0] + glm::vec3(0.0f, 0.0f, 0.3f);
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {moved}}, 6).ok());
    ASSERT_TRUE(doc->sculptSamples.has_value());
    const SculptSamples fresh = SculptSamples::build(*doc->planned, doc->scene.objects[0].displacement.layout);
    for (uint32_t s = 0; s < fresh.sampleCount(); ++s) {
        if (!fresh.hasSite(s)) continue;
        ASSERT_EQ(doc->sculptSamples->position(s), fresh.position(s)) << "sample " << s;
    }

    // Clearing the displacement is undoable, and drops the cache (a new layout needs a new one).
    ASSERT_TRUE(clearDisplacement(*doc, 8).ok());
    EXPECT_TRUE(doc->scene.objects[0].displacement.empty());
    EXPECT_FALSE(doc->sculptSamples.has_value()) << "a new layout needs a new cache";
    ASSERT_TRUE(undoEdit(*doc, 9).ok());
    EXPECT_EQ(doc->scene.objects[0].displacement.samples, sculpted);
}

// Resampling to a finer resolution keeps the shape and is one undoable entry; bad resolutions
// are refused with the allowed range.
TEST(Document, DisplacementResolutionResamplesAndRefusesBadValues) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    Result<EditReport> bad = setDisplacementResolution(*doc, 12, 1);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("power of two between 1 and 64"), std::string::npos) << bad.error().message;
    EXPECT_FALSE(setDisplacementResolution(*doc, 128, 1).ok());
    EXPECT_TRUE(doc->history.size() == 0 && doc->scene.objects[0].displacement.empty());
    ASSERT_TRUE(setDisplacementResolution(*doc, 4, 1).ok());
    ASSERT_TRUE(beginStroke(*doc, 4, 2).ok());
    StrokeOptions options;
    options.brush = Brush{BrushKind::Raise, 0.4f, 0.2f, Falloff::Smooth};
    strokeTo(*doc, options, doc->planned->evaluate(0, 0.5f, 0.5f).position);
    ASSERT_TRUE(endStroke(*doc, "Raise stroke", 3).ok());
    const Displacement coarse = doc->scene.objects[0].displacement;
    const uint64_t revision = doc->displacementRevision;
    ASSERT_TRUE(setDisplacementResolution(*doc, 16, 4).ok());
    EXPECT_GT(doc->displacementRevision, revision);
    const Displacement& fine = doc->scene.objects[0].displacement;
    EXPECT_GT(fine.samples.size(), coarse.samples.size());
    // The finer tiles refine the coarser B-spline exactly, except within 1.5 coarse cells of the
    // cube's corners (valence 3: one shared sample there, not in the finer space).
    for (uint32_t s = 0; s < fine.layout.tiles.size(); ++s)
        for (float u : {0.4f, 0.5f, 0.6f})
            for (float v : {0.4f, 0.45f, 0.625f})
                EXPECT_NEAR(evaluateDisplacement(fine, s, u, v).value, evaluateDisplacement(coarse, s, u, v).value, 1e-6f)
                    << "sub-face " << s << " at " << u << ", " << v;
    ASSERT_TRUE(undoEdit(*doc, 5).ok());
    EXPECT_EQ(doc->scene.objects[0].displacement, coarse);
}

TEST(Document, SelectionModesOpsAndIndexChecks) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    ASSERT_TRUE(selectVertex(*doc, 4, false).ok());
    ASSERT_TRUE(selectVertex(*doc, 2, true).ok());
    EXPECT_EQ(doc->selection.vertices, (std::vector<uint32_t>{2, 4}));
    ASSERT_TRUE(selectVertex(*doc, 4, true).ok());  // toggles off
    EXPECT_EQ(doc->selection.vertices, std::vector<uint32_t>{2});
    EXPECT_FALSE(selectVertex(*doc, 100000, false).ok());
    const Cage& cage = doc->planned->cage();
    ASSERT_TRUE(selectEdge(*doc, cage.faceBegin(0)[1], cage.faceBegin(0)[0]).ok());
    EXPECT_EQ(doc->selection.mode, SelectionMode::Edge);
    ASSERT_EQ(doc->selection.edges.size(), 1u);
    EXPECT_LT(doc->selection.edges[0].v0, doc->selection.edges[0].v1);
    const uint32_t faces[] = {0, 1};
    ASSERT_TRUE(selectElements(*doc, SelectionMode::Face, faces, SelectOp::Replace).ok());
    const uint32_t remove[] = {0};
    ASSERT_TRUE(selectElements(*doc, SelectionMode::Face, remove, SelectOp::Remove).ok());
    EXPECT_EQ(doc->selection.faces, std::vector<uint32_t>{1});
    setSelectionMode(*doc, SelectionMode::Vertex);  // face 1's corners
    EXPECT_EQ(doc->selection.vertices.size(), 4u);
    EXPECT_EQ(selectedFaces(*doc), std::vector<uint32_t>{1});
    const uint32_t badFace[] = {100000};
    EXPECT_FALSE(selectElements(*doc, SelectionMode::Face, badFace, SelectOp::Add).ok());
    clearSelection(*doc);
    EXPECT_TRUE(doc->selection.empty());
    EXPECT_EQ(doc->selection.mode, SelectionMode::Vertex);
}

TEST(Document, SavesSceneOrCageAtomicallyAndClearsTheMarker) {
    const fs::path dir = scratchDir("save");
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {glm::vec3(-2, -2, -2)}}, 1).ok());
    Status bad = saveDocument(*doc, (dir / "cube.txt").string());
    ASSERT_FALSE(bad.ok());
    EXPECT_TRUE(doc->dirty);
    ASSERT_TRUE(saveDocument(*doc, (dir / "cube.json").string()).ok());
    EXPECT_FALSE(doc->dirty);
    EXPECT_EQ(doc->path, (dir / "cube.json").string());
    Result<Scene> scene = loadSceneOrCage((dir / "cube.json").string());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    EXPECT_EQ(scene->objects[0].cage.positions[0], glm::vec3(-2, -2, -2));
    ASSERT_TRUE(saveDocument(*doc, (dir / "cube.obj").string()).ok());
    Result<Scene> cage = loadSceneOrCage((dir / "cube.obj").string());
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_EQ(cage->objects[0].cage.faceCount(), doc->planned->cage().faceCount());
}

// Save As writes the cage under the new scene's name: the scene that was opened, and the OBJ it
// names, are left as they were (a topology edit saved over its OBJ would break it).
TEST(Document, SaveAsLeavesTheOpenedScenesFilesAlone) {
    const fs::path dir = scratchDir("save-as");
    for (const char* name : {"default.json", "default.obj"}) fs::copy_file(fs::path(QUADPLAN_SCENES_DIR) / name, dir / name);
    Result<Scene> opened = loadSceneOrCage((dir / "default.json").string());
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    Result<std::unique_ptr<Document>> created = createDocument(*opened, (dir / "default.json").string(), PlanOptions{});
    ASSERT_TRUE(created.ok()) << created.error().message;
    Document& doc = **created;
    const std::string objBefore = readFile((dir / "default.obj").string()).value();
    const uint32_t facesBefore = doc.planned->cage().faceCount();
    ASSERT_TRUE(applyEdit(doc, ExtrudeFaces{{0}, 0.2f}, 1).ok());

    ASSERT_TRUE(saveDocument(doc, (dir / "edited.json").string()).ok());
    EXPECT_EQ(readFile((dir / "default.obj").string()).value(), objBefore) << "Save As overwrote the opened scene's cage";
    Result<Scene> original = loadSceneOrCage((dir / "default.json").string()), edited = loadSceneOrCage((dir / "edited.json").string());
    ASSERT_TRUE(original.ok() && edited.ok());
    EXPECT_EQ(original->objects[0].cage.faceCount(), facesBefore);
    EXPECT_EQ(edited->objects[0].cage.faceCount(), facesBefore + 4);
    EXPECT_TRUE(fs::exists(dir / "edited.obj"));

    // Saving again to the same scene writes the same files.
    ASSERT_TRUE(applyEdit(doc, ExtrudeFaces{{0}, 0.2f}, 2).ok());
    ASSERT_TRUE(saveDocument(doc, (dir / "edited.json").string()).ok());
    Result<Scene> again = loadSceneOrCage((dir / "edited.json").string());
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_EQ(again->objects[0].cage.faceCount(), facesBefore + 8);
    EXPECT_EQ(readFile((dir / "default.obj").string()).value(), objBefore);
}

// --- recovery -----------------------------------------------------------------------------

TEST(Recovery, WritesFindsLoadsAndRemoves) {
    const fs::path dir = scratchDir("recovery");
    EXPECT_FALSE(findRecovery(dir.string()));
    Scene scene = sceneOfCage(test::makeCube(), "cage");
    scene.objects[0].cage.positions[0] = {-5, 0, 0};
    ASSERT_TRUE(writeRecovery((dir / "nested").string(), scene, {"/some/where.json", "2024-01-02 03:04:05"}).ok());
    std::optional<RecoveryInfo> found = findRecovery((dir / "nested").string());
    ASSERT_TRUE(found);
    EXPECT_EQ(found->source, "/some/where.json");
    EXPECT_EQ(found->savedAt, "2024-01-02 03:04:05");
    Result<Scene> loaded = loadRecovery((dir / "nested").string());
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->objects[0].cage.positions[0], glm::vec3(-5, 0, 0));
    removeRecovery((dir / "nested").string());
    EXPECT_FALSE(findRecovery((dir / "nested").string()));
}

TEST(Recovery, DirectoryFollowsTheEnvironment) {
    const char* saved = std::getenv("QUADPLAN_RECOVERY_DIR");
    const std::string keep = saved ? saved : "";
    setenv("QUADPLAN_RECOVERY_DIR", "/tmp/qp-recovery-test", 1);
    EXPECT_EQ(recoveryDirectory(), "/tmp/qp-recovery-test");
    unsetenv("QUADPLAN_RECOVERY_DIR");
    setenv("XDG_STATE_HOME", "/tmp/state", 1);
    EXPECT_EQ(recoveryDirectory(), "/tmp/state/quadplan");
    unsetenv("XDG_STATE_HOME");
    if (saved) setenv("QUADPLAN_RECOVERY_DIR", keep.c_str(), 1);
}

// --- frame statistics ---------------------------------------------------------------------

TEST(FrameStats, MediansByKindOfFrame) {
    FrameStats stats;
    for (int i = 1; i <= 9; ++i) stats.add({double(i), -1.0, 10.0 * i, i % 3 == 0});
    stats.setGpuMs(0, 5.0);  // the newest (9, drawn)
    const Summary cpu = summarize(stats, FrameField::Cpu);
    EXPECT_EQ(cpu.count, 9u);
    EXPECT_EQ(cpu.median, 5.0);
    EXPECT_EQ(cpu.max, 9.0);
    EXPECT_EQ(summarize(stats, FrameField::Cpu, 0, FrameFilter::SceneDrawn).count, 3u);   // 3, 6, 9
    EXPECT_EQ(summarize(stats, FrameField::Cpu, 0, FrameFilter::SceneDrawn).median, 6.0);
    EXPECT_EQ(summarize(stats, FrameField::Gpu).count, 1u);  // unknown GPU times are skipped
    EXPECT_EQ(summarize(stats, FrameField::Interval, 2).median, 90.0);
}

}  // namespace

// Previews of interactive tools: replaceLastEdit keeps a slider drag one entry; revertTo leaves
// no trace of a cancelled preview. Hidden faces drop out of the selection and go when faces are
// renumbered.
TEST(Document, LiveEditsRevertsAndHiddenFaces) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    const Cage before = doc->planned->cage();
    const uint32_t a = before.faceBegin(0)[0], b = before.faceBegin(0)[1];
    ASSERT_TRUE(applyEdit(*doc, SetEdgeSharpness{{{a, b, 1.0f}}}, 1).ok());
    ASSERT_TRUE(replaceLastEdit(*doc, SetEdgeSharpness{{{a, b, 3.0f}}}, 2).ok());
    EXPECT_EQ(doc->history.size(), 1u);
    EXPECT_EQ(doc->planned->cage().edgeSharpness(a, b), 3.0f);
    ASSERT_TRUE(undoEdit(*doc, 3).ok());
    EXPECT_EQ(doc->planned->cage().edgeSharpness(a, b), 0.0f) << "the replaced entry undoes to before the drag";

    ASSERT_TRUE(applyEdit(*doc, ExtrudeFaces{{0}, 0.0f}, 4).ok());
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {glm::vec3(2, 2, 2)}, false, "preview"}, 5).ok());
    ASSERT_TRUE(revertTo(*doc, 0, 6).ok());
    EXPECT_EQ(doc->history.size(), 0u) << "a reverted preview left redo entries";
    EXPECT_EQ(doc->planned->cage().positions, before.positions);
    EXPECT_EQ(doc->planned->cage().faceVertices, before.faceVertices);
    EXPECT_FALSE(doc->dirty);

    ASSERT_TRUE(selectElements(*doc, SelectionMode::Face, std::vector<uint32_t>{0, 1}, SelectOp::Replace).ok());
    ASSERT_TRUE(hideFaces(*doc, std::vector<uint32_t>{1}).ok());
    EXPECT_EQ(doc->hiddenFaces, std::vector<uint32_t>{1});
    EXPECT_EQ(doc->selection.faces, std::vector<uint32_t>{0}) << "hiding drops the face from the selection";
    EXPECT_TRUE(isFaceHidden(*doc, 1));
    EXPECT_FALSE(isFaceHidden(*doc, 0));
    EXPECT_FALSE(hideFaces(*doc, std::vector<uint32_t>{999}).ok());
    const uint64_t revision = doc->hiddenRevision;
    ASSERT_TRUE(applyEdit(*doc, ExtrudeFaces{{0}, 0.1f}, 7).ok());
    ASSERT_TRUE(doc->lastEdit);
    const std::vector<uint32_t>& previousFaceOf = doc->lastEdit->report.previousFaceOf;
    ASSERT_EQ(previousFaceOf.size(), doc->planned->cage().faceCount());
    const auto hiddenNow = std::find(previousFaceOf.begin(), previousFaceOf.end(), 1u);
    ASSERT_NE(hiddenNow, previousFaceOf.end()) << "the extrude kept face 2";
    EXPECT_EQ(doc->hiddenFaces, std::vector<uint32_t>{uint32_t(hiddenNow - previousFaceOf.begin())})
        << "a topology edit carries the hidden set to the faces' new numbers";
    EXPECT_GT(doc->hiddenRevision, revision);
    ASSERT_TRUE(hideFaces(*doc, std::vector<uint32_t>{2}).ok());
    unhideAll(*doc);
    EXPECT_TRUE(doc->hiddenFaces.empty());
}
