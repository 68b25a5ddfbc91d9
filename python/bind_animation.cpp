// quadplan.Scene's animation (docs/python.md, "Animation"; SceneDocument's in
// scene_document_animation.cpp).
#include <cmath>
#include <numeric>
#include <optional>

#include "bind_scene.h"

namespace qp::py {

namespace {

const NameTable<Interpolation> kInterpolationNames{{"linear", Interpolation::Linear}, {"catmull-rom", Interpolation::CatmullRom}};

}  // namespace

void bindSceneAnimation(SceneClass& scene) {
    scene
        .def_property_readonly("frame", &Document::frame,
                               "The frame the scene shows (a float: set_frame may stop between frames).")
        .def_property_readonly("frames", [](const Document& d) {
                                   const Timeline t = d.timeline();
                                   return py::make_tuple(t.firstFrame, t.lastFrame);
                               }, R"doc((first, last), the frames the scene plays, both included: the timeline's (set_timeline), or
without one the range of every key ((1, 1) when nothing is keyed).)doc")
        .def_property_readonly("fps", [](const Document& d) { return d.timeline().framesPerSecond; },
                               "Frames per second the scene plays at (24 without a timeline).")
        .def_property_readonly("is_animated", [](const Document& d) { return isAnimated(d.scene()); },
                               "Whether any object has keys (of its vertices or of its transform).")
        .def_property_readonly("keyed_frames", [](const Document& d) { return keyedFrames(d.animation()); },
                               "The frames with a key of some vertex of the active object, sorted.")
        .def_property_readonly("interpolation", [](const Document& d) { return enumName(kInterpolationNames, d.animation().interpolation); },
                               "How the active object's keys are interpolated: \"linear\" or \"catmull-rom\".")
        .def_property_readonly("rest_positions", [](const Document& d) { return toArray(d.restPositions()); },
                               R"doc(The active object's rest positions, an (N, 3) float32 array (a copy): where a vertex without keys
stays, and what a saved scene holds as the cage. Without vertex keys they are `positions`.)doc")
        .def("set_frame",
             [](Document& d, double frame) {
                 if (!std::isfinite(frame)) throw py::value_error("the frame must be a finite number, not " + std::to_string(frame));
                 return unwrap(d.setFrame(frame));
             },
             py::arg("frame"),
             R"doc(Shows `frame` (any finite number; between keys the positions are interpolated): every object with
vertex keys moves there, every object with transform keys takes its transform there. A vertex move:
nothing is re-planned (replanned_faces is 0). Not a history entry. The report's counts add up every
object's, its lists are the active object's. A non-finite frame raises ValueError.)doc")
        .def("set_key",
             [](Document& d, const py::object& vertices, const py::object& positions, std::optional<int64_t> frame) {
                 std::vector<uint32_t> vs;
                 if (vertices.is_none()) {
                     vs.resize(d.cage().vertexCount());
                     std::iota(vs.begin(), vs.end(), 0u);
                 } else {
                     vs = verticesOf(d, vertices);
                 }
                 std::optional<std::vector<glm::vec3>> ps;
                 if (!positions.is_none()) ps = pointsFrom(positions, "positions");
                 return unwrap(d.setKeys(vs, ps, frame));
             },
             py::arg("vertices") = py::none(), py::arg("positions") = py::none(), py::arg("frame") = py::none(),
             R"doc(Keys vertices of the active object (a Selection or indices; None: all of them) at `frame` (an int;
None: the current frame, which must then be whole). With `positions` (one (x, y, z) each) the keys
put them there, else where the animation has them at that frame. The cage then shows the current
frame of the new keys. Undoable.)doc")
        .def("remove_keys", [](Document& d, int64_t frame) { return unwrap(d.removeKeys(frame)); }, py::arg("frame"),
             "Removes every vertex key of the active object at `frame` (refused where there is none). Undoable.")
        .def("set_transform_key",
             [](Document& d, const std::string& name, int64_t frame, const py::object& translation, const py::object& rotation,
                const py::object& scale) {
                 const uint32_t i = findObject(d.scene().objects, name);
                 const ObjectTransform at = i == UINT32_MAX ? ObjectTransform{}
                                                            : evaluateTransform(d.scene().objects[i].animation, double(frame),
                                                                                d.scene().objects[i].transform);
                 check(d.setTransformKey(name, frame, transformFrom(translation, rotation, scale, at)));
             },
             py::arg("name"), py::arg("frame"), py::arg("translation") = py::none(), py::arg("rotation_degrees") = py::none(),
             py::arg("scale") = py::none(),
             R"doc(Keys an object's transform (any object, instances too) at `frame`: the parts given, the others as
the object has them at that frame. Between keys each part is interpolated. Undoable.)doc")
        .def("remove_transform_key",
             [](Document& d, const std::string& name, int64_t frame) { check(d.removeTransformKey(name, frame)); },
             py::arg("name"), py::arg("frame"),
             R"doc(Removes an object's transform key at `frame` (refused, naming the object and the frame, where it has
none). Without keys left the object keeps the transform it shows now. Undoable.)doc")
        .def("set_interpolation",
             [](Document& d, const std::string& name) {
                 return unwrap(d.setInterpolation(enumFrom(kInterpolationNames, name, "interpolation")));
             },
             py::arg("interpolation"),
             "\"linear\" or \"catmull-rom\" between the active object's keys (its transform keys too). Undoable.")
        .def("set_timeline",
             [](Document& d, int64_t first, int64_t last, std::optional<double> fps) {
                 check(d.setTimeline(first, last, fps.value_or(d.timeline().framesPerSecond)));
             },
             py::arg("first"), py::arg("last"), py::arg("fps") = py::none(),
             R"doc(The frames the scene plays, first to last included, at `fps` (None: as now); saved with the scene.
The current frame stays. Undoable.)doc")
        .def("load_sequence",
             [](Document& d, const std::string& pattern) {
                 py::gil_scoped_release release;
                 return unwrap(d.loadSequence(pattern));
             },
             py::arg("pattern"),
             R"doc(Makes an OBJ sequence the active object's vertex keys: the files of the pattern's folder whose
names are the pattern with a number for its one '*' ("walk/frame_*.obj"), each keyed at its number.
Every frame is read first: a missing number, a frame that does not load or whose vertices or faces
differ from the cage's is refused naming the frame, and nothing changes. A saved scene refers to the
sequence (relative to itself) while the keys are unchanged. Undoable.)doc")

        ;
}

}  // namespace qp::py
