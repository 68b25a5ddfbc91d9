// quadplan.Scene's sculpted displacement (docs/python.md, "Sculpting"; SceneDocument's strokes in
// scene_document.cpp).
#include "bind_scene.h"
#include "displacement/displacement_io.h"

namespace qp::py {

void bindSceneDisplacement(SceneClass& scene) {
    scene
        .def("stroke",
             [](Document& d, const py::object& path, float radius, float strength, const std::string& brush,
                const std::string& falloff, const std::string& mirror, float spacing, uint32_t resolution) {
                 StrokeOptions options;
                 auto kind = brushKindFromName(brush);
                 if (!kind) throw ScriptError("unknown brush \"" + brush + "\"; expected raise, lower, smooth, flatten, erase, inflate, crease, mask or unmask");
                 auto fall = falloffFromName(falloff);
                 if (!fall) throw ScriptError("unknown falloff \"" + falloff + "\"; expected smooth, linear, constant or sphere");
                 auto axis = mirrorAxisFromName(mirror);
                 if (!axis) throw ScriptError("unknown mirror axis \"" + mirror + "\"; expected none, x, y or z");
                 options.brush = {*kind, radius, strength, *fall};
                 options.mirror = *axis;
                 options.spacing = spacing;
                 const std::vector<glm::vec3> points = pointsFrom(path, "path");
                 py::gil_scoped_release release;
                 return unwrap(d.stroke(options, points, resolution));
             },
             py::arg("path"), py::arg("radius"), py::arg("strength"), py::arg("brush") = "raise", py::arg("falloff") = "smooth",
             py::arg("mirror") = "none", py::arg("spacing") = 0.0f, py::arg("resolution") = 8,
             R"doc(One brush stroke along a world-space polyline (as `quadplan sculpt`): dabs every `spacing`
(0: a quarter of the radius) change the displacement samples whose limit positions lie within the
radius. brush: raise, lower, smooth, flatten, erase, inflate, crease, mask or unmask; strength: raise/lower/inflate/crease height per dab in
radii, the others a blend in [0, 1]. A scene without displacement first gets a zero one at
`resolution` cells per quad side (its own history entry). One undo takes the stroke back.)doc")
        .def("set_displacement_resolution", [](Document& d, uint32_t r) { return unwrap(d.setDisplacementResolution(r)); },
             py::arg("resolution"), "Resamples the displacement (or creates a zero one) at this power-of-two resolution R (cells along a quad side; raised to 2, or 4 on cages with non-quads).")
        .def("clear_displacement", [](Document& d) { return unwrap(d.clearDisplacement()); },
             "Removes the displacement (undoable).")
        .def("invert_mask", [](Document& d) { return unwrap(d.invertMask()); },
             "Inverts the sculpting mask (m -> 1 - m; with no mask yet, masks everything). One undo entry.")
        .def("clear_mask", [](Document& d) { return unwrap(d.clearMask()); },
             "Clears the sculpting mask (one undo entry; none when nothing was masked).")
        .def_property_readonly("displacement_mask", [](const Document& d) {
                                   const auto& m = d.displacement().mask;
                                   return py::array_t<float>(py::ssize_t(m.size()), m.data());
                               }, "The sculpting mask, one value in [0, 1] per displacement sample (1: fully masked; a copy; empty when nothing was ever masked).")
        .def_property_readonly("has_displacement", [](const Document& d) { return !d.displacement().empty(); },
                               "Whether the scene has sculpted displacement.")
        .def_property_readonly("displacement_samples", [](const Document& d) {
                                   const auto& s = d.displacement().samples;
                                   return py::array_t<float>(py::ssize_t(s.size()), s.data());
                               }, "Every displacement sample: the tiles' B-spline coefficients, each stored once (a copy; empty without displacement): docs/displacement.md.")
        .def_property_readonly("displacement_resolution", [](const Document& d) { return d.displacement().resolution(); },
                               "R, the displacement tiles' cells along a quad's side (an n-gon's sub-faces have R / 2); 0 without displacement.")
        .def("evaluate_displacement",
             [](const Document& d, const py::object& subfaces, const py::object& u, const py::object& v) {
                 if (d.displacement().empty()) throw ScriptError("the scene has no displacement");
                 const std::vector<SampleRequest> requests = sampleRequests(d.planned(), subfaces, u, v);
                 py::array_t<float> out(py::ssize_t(requests.size()));
                 for (size_t i = 0; i < requests.size(); ++i)
                     out.mutable_data()[i] = evaluateDisplacement(d.displacement(), requests[i].subface, requests[i].u, requests[i].v).value;
                 return out;
             },
             py::arg("subfaces"), py::arg("u"), py::arg("v"), "The displacement D at (sub-face, u, v), broadcast like evaluate().");
}

}  // namespace qp::py
