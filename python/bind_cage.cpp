// quadplan.Cage, quadplan.Camera, quadplan.Tessellation and quadplan.Selection: value types.
#include <cmath>

#include "conversions.h"
#include "mesh/generated_cage.h"
#include "mesh/obj_io.h"
#include "mesh/topology.h"
#include "plans/osd_refiner.h"
#include "scene/scene.h"

namespace qp::py {

namespace {

py::dict histogramDict(const std::map<uint32_t, uint32_t>& histogram) {
    py::dict out;
    for (const auto& [key, count] : histogram) out[py::str(std::to_string(key))] = count;
    return out;
}

}  // namespace

// `quadplan info --json`'s object without "file", after OpenSubdiv accepted the cage.
py::dict cageInfo(const Cage& cage, const std::string& source) {
    if (auto refiner = createRefiner(cage, source); !refiner) throw ScriptError(refiner.error().message);
    const CageStats s = computeStats(cage, buildTopology(cage));
    py::dict out;
    out["vertices"] = s.vertices;
    out["faces"] = s.faces;
    out["edges"] = s.edges;
    out["face_sizes"] = histogramDict(s.faceSizeHistogram);
    out["valences"] = histogramDict(s.valenceHistogram);
    out["boundary_edges"] = s.boundaryEdges;
    out["nonmanifold_edges"] = s.nonManifoldEdges;
    out["nonmanifold_vertices"] = s.nonManifoldVertices;
    out["isolated_vertices"] = s.isolatedVertices;
    out["extraordinary_vertices"] = s.extraordinaryVertices;
    out["creased_edges"] = s.creasedEdges;
    out["infinitely_sharp_edges"] = s.infinitelySharpEdges;
    out["corner_vertices"] = s.cornerVertices;
    out["holes"] = s.holes;
    return out;
}

py::list facesList(const Cage& cage) {
    py::list faces;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        py::list face;
        for (uint32_t i = 0; i < cage.faceSize(f); ++i) face.append(cage.faceBegin(f)[i]);
        faces.append(face);
    }
    return faces;
}

py::list creasesList(const Cage& cage) {
    py::list out;
    for (const EdgeCrease& c : cage.creases) out.append(py::make_tuple(c.v0, c.v1, c.sharpness));
    return out;
}

py::list cornersList(const Cage& cage) {
    py::list out;
    for (const VertexCorner& c : cage.corners) out.append(py::make_tuple(c.vertex, c.sharpness));
    return out;
}

py::array_t<uint32_t> edgesArray(const Topology& topology) {
    py::array_t<uint32_t> out({py::ssize_t(topology.edgeCount()), py::ssize_t(2)});
    std::copy(topology.edgeVertices.begin(), topology.edgeVertices.end(), out.mutable_data());
    return out;
}

std::vector<EdgeCrease> creasesFrom(const py::object& object) {
    std::vector<EdgeCrease> out;
    for (const py::handle item : py::iter(object)) {
        py::tuple t = py::reinterpret_borrow<py::object>(item).cast<py::tuple>();
        if (t.size() != 3) throw ScriptError("a crease is (vertex a, vertex b, sharpness)");
        const std::vector<uint32_t> ends = indicesFrom(py::make_tuple(t[0], t[1]), "crease vertices");
        out.push_back({ends[0], ends[1], t[2].cast<float>()});
    }
    return out;
}

std::vector<VertexCorner> cornersFrom(const py::object& object) {
    std::vector<VertexCorner> out;
    for (const py::handle item : py::iter(object)) {
        py::tuple t = py::reinterpret_borrow<py::object>(item).cast<py::tuple>();
        if (t.size() != 2) throw ScriptError("a corner is (vertex, sharpness)");
        out.push_back({indicesFrom(t[0], "corner vertex")[0], t[1].cast<float>()});
    }
    return out;
}

Camera makeCamera(const py::object& eye, const py::object& target, const py::object& up, float fov, bool orthographic,
                  float orthoHeight) {
    Camera camera;
    camera.eye = vec3From(eye, "eye");
    camera.target = vec3From(target, "target");
    camera.up = vec3From(up, "up");
    camera.fovYDegrees = fov;
    camera.projection = orthographic ? Projection::Orthographic : Projection::Perspective;
    camera.orthoHeight = orthoHeight;
    // The rules of the scene file's "camera" (docs/scene-format.md).
    if (!(fov > 0.0f && fov < 180.0f)) throw ScriptError("camera fov must be between 0 and 180 degrees, got " + std::to_string(fov));
    if (!(orthoHeight > 0.0f) || !std::isfinite(orthoHeight)) throw ScriptError("camera ortho_height must be a positive number");
    if (camera.eye == camera.target) throw ScriptError("camera target must differ from eye");
    if (glm::length(glm::cross(camera.target - camera.eye, camera.up)) == 0.0f)
        throw ScriptError("camera up must not be parallel to the view direction");
    return camera;
}

void bindCage(py::module_& m) {
    py::class_<Cage>(m, "Cage", R"doc(
A Catmull-Clark control cage with its subdivision tags: vertex positions, faces (counter-clockwise
vertex lists), semi-sharp creases, corners, holes and OpenSubdiv's options.

A Cage is a value: its properties return copies, and a Scene made from it keeps its own copy.
Vertices and faces are numbered from 0 here; error messages number them from 1, as OBJ files and
the command line do (index i is "vertex i+1" in a message).
)doc")
        .def(py::init([](const py::object& positions, const py::object& faces, const py::object& creases,
                         const py::object& corners, const py::object& holes, const std::string& boundary,
                         const std::string& creaseMethod, const std::string& triangleSubdivision) {
                 Cage cage;
                 cage.positions = pointsFrom(positions, "positions");
                 for (const py::handle face : py::iter(faces)) {
                     const std::vector<uint32_t> vertices = indicesFrom(py::reinterpret_borrow<py::object>(face), "a face");
                     cage.addFace(vertices.data(), uint32_t(vertices.size()));
                 }
                 for (const EdgeCrease& c : creasesFrom(creases)) cage.creases.push_back(EdgeCrease{std::min(c.v0, c.v1), std::max(c.v0, c.v1), c.sharpness});
                 cage.corners = cornersFrom(corners);
                 cage.holes = indicesFrom(holes, "holes");
                 cage.options.boundary = enumFrom(kBoundaryNames, boundary, "boundary rule");
                 cage.options.creaseMethod = enumFrom(kCreaseMethodNames, creaseMethod, "crease method");
                 cage.options.triangleSubdivision = enumFrom(kTriangleNames, triangleSubdivision, "triangle subdivision");
                 normalizeTags(cage);
                 check(validateCage(cage, "cage"));
                 return cage;
             }),
             py::arg("positions"), py::arg("faces"), py::arg("creases") = py::tuple(), py::arg("corners") = py::tuple(),
             py::arg("holes") = py::tuple(), py::arg("boundary") = "edges-and-corners", py::arg("crease_method") = "normal",
             py::arg("triangle_subdivision") = "catmark",
             R"doc(Builds a cage and checks it (every rule of core/mesh/cage.h); raises quadplan.Error naming the fault.

positions: (N, 3) numbers. faces: lists of vertex indices, counter-clockwise seen from outside.
creases: (a, b, sharpness) per edge, sharpness in (0, 10], 10 = infinitely sharp.
corners: (vertex, sharpness). holes: face indices.
boundary: "edges-and-corners", "edges-only" or "none". crease_method: "normal" or "chaikin".
triangle_subdivision: "catmark" or "smooth".)doc")
        .def_static(
            "load",
            [](const std::string& path) {
                std::vector<std::string> warnings;
                Result<Cage> cage = loadObj(path, &warnings);
                warnAll(warnings);
                return unwrap(std::move(cage));
            },
            py::arg("path"), "Reads an OBJ file with OpenSubdiv's tag lines (creases, corners, holes, options).")
        .def_static("generated", [](uint32_t faces, uint32_t seed) {
                        if (faces < 16 || faces > 10000000) throw ScriptError("faces must be between 16 and 10000000");
                        return makeBenchmarkCage(faces, seed);
                    },
                    py::arg("faces"), py::arg("seed") = 1,
                    R"doc(The benchmarks' deterministic test cage (core/mesh/generated_cage.h): a closed torus of about `faces`
quads with poked quads (valence-5 vertices, triangles), semi-sharp and infinitely sharp creases and
corners. The same (faces, seed) always gives the same cage.)doc")
        .def("save", [](const Cage& cage, const std::string& path) { check(saveObj(cage, path)); }, py::arg("path"),
             "Writes the cage as OBJ with its tags, atomically (the file is replaced whole or left as it was).")
        .def("to_obj", &formatObj, "The OBJ text save() writes.")
        .def("info", [](const Cage& cage) { return cageInfo(cage, "cage"); },
             "Counts and histograms, the object `quadplan info --json` prints (without \"file\").")
        .def_property_readonly("vertex_count", &Cage::vertexCount, "Number of vertices.")
        .def_property_readonly("face_count", &Cage::faceCount, "Number of faces.")
        .def_property_readonly("positions", [](const Cage& c) { return toArray(c.positions); },
                               "Vertex positions, an (N, 3) float32 array (a copy).")
        .def_property_readonly("faces", &facesList, "Faces as lists of vertex indices (a copy).")
        .def_property_readonly("edges", [](const Cage& c) { return edgesArray(buildTopology(c)); },
                               "Edges as an (E, 2) array of vertex pairs, first < second, sorted.")
        .def_property_readonly("creases", &creasesList, "(a, b, sharpness) per creased edge, a < b, sorted.")
        .def_property_readonly("corners", &cornersList, "(vertex, sharpness) per corner, sorted.")
        .def_property_readonly("holes", [](const Cage& c) { return c.holes; }, "Faces tagged as holes, sorted.")
        .def_property_readonly("boundary", [](const Cage& c) { return enumName(kBoundaryNames, c.options.boundary); },
                               "Boundary interpolation rule.")
        .def_property_readonly("crease_method", [](const Cage& c) { return enumName(kCreaseMethodNames, c.options.creaseMethod); },
                               "\"normal\" or \"chaikin\".")
        .def_property_readonly("triangle_subdivision",
                               [](const Cage& c) { return enumName(kTriangleNames, c.options.triangleSubdivision); },
                               "\"catmark\" or \"smooth\".")
        .def("edge_sharpness", &Cage::edgeSharpness, py::arg("a"), py::arg("b"), "Sharpness of edge a-b (0: no crease).")
        .def("vertex_sharpness", &Cage::vertexSharpness, py::arg("vertex"), "Corner sharpness of a vertex (0: none).")
        .def("bounds", [](const Cage& c) {
                 const Bounds b = computeBounds(c);
                 return py::make_tuple(std::vector<float>{b.min.x, b.min.y, b.min.z}, std::vector<float>{b.max.x, b.max.y, b.max.z});
             }, "(min, max) corners of the axis-aligned bounding box.")
        .def_property_readonly("diagonal", [](const Cage& c) { return computeBounds(c).diagonal(); },
                               "Length of the bounding-box diagonal (the scale of relative errors).")
        .def("__eq__", [](const Cage& a, const Cage& b) { return a.positions == b.positions && sameTopologyAndTags(a, b); })
        .def("__repr__", [](const Cage& c) {
            return "<quadplan.Cage " + std::to_string(c.vertexCount()) + " vertices, " + std::to_string(c.faceCount()) +
                   " faces, " + std::to_string(c.creases.size()) + " creases>";
        });

    py::class_<Camera>(m, "Camera", R"doc(
A look-at camera, as a scene file stores it: eye, target, up, vertical field of view in degrees,
perspective or orthographic (ortho_height = world-space height of the view). Renders take their
near and far planes from the cage, as `quadplan render` does.
)doc")
        .def(py::init(&makeCamera), py::arg("eye"), py::arg("target") = py::make_tuple(0, 0, 0),
             py::arg("up") = py::make_tuple(0, 1, 0), py::arg("fov") = 45.0f, py::arg("orthographic") = false,
             py::arg("ortho_height") = 2.0f, "Checks the values as the scene loader does.")
        .def_property_readonly("eye", [](const Camera& c) { return std::vector<float>{c.eye.x, c.eye.y, c.eye.z}; }, "Eye position.")
        .def_property_readonly("target", [](const Camera& c) { return std::vector<float>{c.target.x, c.target.y, c.target.z}; },
                               "Point looked at.")
        .def_property_readonly("up", [](const Camera& c) { return std::vector<float>{c.up.x, c.up.y, c.up.z}; }, "Up direction.")
        .def_property_readonly("fov", [](const Camera& c) { return c.fovYDegrees; }, "Vertical field of view, degrees.")
        .def_property_readonly("orthographic", [](const Camera& c) { return c.projection == Projection::Orthographic; },
                               "True for an orthographic projection.")
        .def_property_readonly("ortho_height", [](const Camera& c) { return c.orthoHeight; },
                               "World-space height of an orthographic view.")
        .def("__eq__", [](const Camera& a, const Camera& b) { return a == b; })
        .def("__repr__", [](const Camera& c) {
            char text[200];
            std::snprintf(text, sizeof text, "<quadplan.Camera eye (%g, %g, %g) target (%g, %g, %g) fov %g%s>", c.eye.x, c.eye.y,
                          c.eye.z, c.target.x, c.target.y, c.target.z, c.fovYDegrees,
                          c.projection == Projection::Orthographic ? " orthographic" : "");
            return std::string(text);
        });

    py::class_<Tessellation>(m, "Tessellation", R"doc(
A scene's tessellation settings: mode "uniform" (factor segments per face edge, 1..64) or
"adaptive" (pixels_per_edge on screen), and whether the cage and the wireframe are shown.
Renders use them unless tess or adaptive is given.
)doc")
        .def(py::init<>(), "The defaults of a scene file.")
        .def_property("mode", [](const Tessellation& t) { return t.mode == TessellationMode::Uniform ? "uniform" : "adaptive"; },
                      [](Tessellation& t, const std::string& mode) {
                          if (mode != "uniform" && mode != "adaptive") throw ScriptError("tessellation mode must be uniform or adaptive");
                          t.mode = mode == "uniform" ? TessellationMode::Uniform : TessellationMode::Adaptive;
                      }, "\"uniform\" or \"adaptive\".")
        .def_property("factor", [](const Tessellation& t) { return t.factor; },
                      [](Tessellation& t, int factor) {
                          if (factor < 1 || factor > 64) throw ScriptError("tessellation factor must be between 1 and 64");
                          t.factor = factor;
                      }, "Uniform mode: segments per face edge, 1..64.")
        .def_property("pixels_per_edge", [](const Tessellation& t) { return t.pixelsPerEdge; },
                      [](Tessellation& t, float p) {
                          if (!(p > 0.0f) || !std::isfinite(p)) throw ScriptError("pixels_per_edge must be a positive number");
                          t.pixelsPerEdge = p;
                      }, "Adaptive mode: target on-screen length of a tessellated edge.")
        .def_readwrite("show_cage", &Tessellation::showCage, "Draw the cage over the surface.")
        .def_readwrite("show_wireframe", &Tessellation::showWireframe, "Draw the tessellation wireframe.")
        .def("__repr__", [](const Tessellation& t) {
            return std::string("<quadplan.Tessellation ") + (t.mode == TessellationMode::Uniform ? "uniform " + std::to_string(t.factor)
                                                                                                : "adaptive " + std::to_string(t.pixelsPerEdge) + " px") +
                   ">";
        });

    py::class_<Selection>(m, "Selection", R"doc(
Selected vertices, edges or faces of a cage: sorted unique lists of the mode's elements (edges as
vertex pairs (a, b), a < b). Make one from indices (Selection.of_vertices, of_edges, of_faces) or
by a predicate (Scene.select); grow, shrink, invert and convert it through a Scene, which knows
the adjacency. Combine with | (add), - (remove) and ^ (toggle).
)doc")
        .def(py::init([](const std::string& mode) {
                 Selection s;
                 s.mode = enumFrom(kSelectionModeNames, mode, "selection mode");
                 return s;
             }),
             py::arg("mode") = "vertex", "An empty selection in \"vertex\", \"edge\" or \"face\" mode.")
        .def_static("of_vertices", [](const py::object& vertices) {
                        Selection s;
                        applyPick(s, SelectOp::Replace, std::span<const uint32_t>(indicesFrom(vertices, "vertices")));
                        return s;
                    }, py::arg("vertices"), "A vertex selection of these indices.")
        .def_static("of_faces", [](const py::object& faces) {
                        Selection s;
                        s.mode = SelectionMode::Face;
                        applyPick(s, SelectOp::Replace, std::span<const uint32_t>(indicesFrom(faces, "faces")));
                        return s;
                    }, py::arg("faces"), "A face selection of these indices.")
        .def_static("of_edges", [](const py::object& edges) {
                        Selection s;
                        s.mode = SelectionMode::Edge;
                        std::vector<EdgeKey> keys;
                        for (const py::handle e : py::iter(edges)) {
                            const std::vector<uint32_t> ends = indicesFrom(py::reinterpret_borrow<py::object>(e), "an edge");
                            if (ends.size() != 2) throw ScriptError("an edge is a pair of vertex indices (a, b)");
                            keys.push_back(makeEdgeKey(ends[0], ends[1]));
                        }
                        applyPick(s, SelectOp::Replace, std::span<const EdgeKey>(keys));
                        return s;
                    }, py::arg("edges"), "An edge selection of these vertex pairs (either order).")
        .def_property_readonly("mode", [](const Selection& s) { return enumName(kSelectionModeNames, s.mode); },
                               "\"vertex\", \"edge\" or \"face\".")
        .def_property_readonly("vertices", [](const Selection& s) { return s.vertices; }, "Selected vertices (vertex mode).")
        .def_property_readonly("faces", [](const Selection& s) { return s.faces; }, "Selected faces (face mode).")
        .def_property_readonly("edges", [](const Selection& s) {
                                   std::vector<std::pair<uint32_t, uint32_t>> out;
                                   for (const EdgeKey& e : s.edges) out.push_back({e.v0, e.v1});
                                   return out;
                               }, "Selected edges as (a, b), a < b (edge mode).")
        .def("__len__", &Selection::size)
        .def("__eq__", [](const Selection& a, const Selection& b) { return a == b; })
        .def("__or__", [](Selection a, const Selection& b) {
            if (a.mode != b.mode) throw ScriptError("cannot combine selections of different modes; convert one first");
            if (a.mode == SelectionMode::Edge) applyPick(a, SelectOp::Add, std::span<const EdgeKey>(b.edges));
            else applyPick(a, SelectOp::Add, std::span<const uint32_t>(a.mode == SelectionMode::Vertex ? b.vertices : b.faces));
            return a;
        }, "Union.")
        .def("__sub__", [](Selection a, const Selection& b) {
            if (a.mode != b.mode) throw ScriptError("cannot combine selections of different modes; convert one first");
            if (a.mode == SelectionMode::Edge) applyPick(a, SelectOp::Remove, std::span<const EdgeKey>(b.edges));
            else applyPick(a, SelectOp::Remove, std::span<const uint32_t>(a.mode == SelectionMode::Vertex ? b.vertices : b.faces));
            return a;
        }, "Difference.")
        .def("__xor__", [](Selection a, const Selection& b) {
            if (a.mode != b.mode) throw ScriptError("cannot combine selections of different modes; convert one first");
            if (a.mode == SelectionMode::Edge) applyPick(a, SelectOp::Toggle, std::span<const EdgeKey>(b.edges));
            else applyPick(a, SelectOp::Toggle, std::span<const uint32_t>(a.mode == SelectionMode::Vertex ? b.vertices : b.faces));
            return a;
        }, "Symmetric difference (toggle).")
        .def("__repr__", [](const Selection& s) {
            const char* plural[] = {"vertices", "edges", "faces"};
            return "<quadplan.Selection of " + std::to_string(s.size()) + " " + plural[uint32_t(s.mode)] + ">";
        });
}

}  // namespace qp::py
