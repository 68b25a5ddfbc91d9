// quadplan.Scene (a SceneDocument), quadplan.EditReport, quadplan.HistoryEntry.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>

#include "bind_scene.h"
#include "conversions.h"
#include "displacement/displacement_io.h"
#include "displacement_bake.h"
#include "plan_memory.h"
#include "plans/limit_check.h"
#include "plans/plan_evaluator.h"
#include "render_setup.h"
#include "scene_document.h"
#include "scene_export.h"
#include "scheme_support.h"

namespace qp::py {

py::dict cageInfo(const Cage& cage, const std::string& source);
py::list facesList(const Cage& cage);
py::list creasesList(const Cage& cage);
py::list cornersList(const Cage& cage);
py::array_t<uint32_t> edgesArray(const Topology& topology);
std::vector<EdgeCrease> creasesFrom(const py::object& object);
std::vector<VertexCorner> cornersFrom(const py::object& object);

namespace {

Status checkSelection(const Selection& s, const Cage& cage) {
    for (uint32_t v : s.vertices)
        if (v >= cage.vertexCount()) return Error{"vertex " + std::to_string(v + 1) + " does not exist (the cage has " + std::to_string(cage.vertexCount()) + " vertices)"};
    for (const EdgeKey& e : s.edges)
        if (e.v1 >= cage.vertexCount()) return Error{"vertex " + std::to_string(e.v1 + 1) + " does not exist (the cage has " + std::to_string(cage.vertexCount()) + " vertices)"};
    for (uint32_t f : s.faces)
        if (f >= cage.faceCount()) return Error{"face " + std::to_string(f + 1) + " does not exist (the cage has " + std::to_string(cage.faceCount()) + " faces)"};
    return success();
}

std::vector<uint32_t> facesOf(const py::object& target) {
    if (py::isinstance<Selection>(target)) {
        const Selection& s = target.cast<const Selection&>();
        if (s.mode != SelectionMode::Face) throw ScriptError("a face selection is needed here; convert it first (Scene.convert)");
        return s.faces;
    }
    return indicesFrom(target, "faces");
}

const Selection& checkedSelection(const Document& doc, const Selection& s) {
    check(checkSelection(s, doc.cage()));
    return s;
}

py::dict planStats(const PlannedCage& planned) {
    std::set<uint32_t> used;
    uint64_t controlPoints = 0;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
        if (planned.subfacePlan(s) != kNoPlan) used.insert(planned.subfacePlan(s));
        controlPoints += planned.storedControlPoints(s).size();
    }
    std::array<uint64_t, kNodeKindCount> nodes{};
    uint64_t stencils = 0, bytes = 0, totalNodes = 0;
    for (uint32_t id : used) {
        const Plan& plan = planned.database().plan(id);
        for (const PlanNode& node : plan.nodes) ++nodes[uint32_t(node.kind)];
        totalNodes += plan.nodes.size();
        stencils += plan.stencilCount();
        bytes += plan.byteSize();
    }
    py::dict byKind;
    for (uint32_t k = 0; k < kNodeKindCount; ++k) byKind[nodeKindName(NodeKind(k))] = nodes[k];
    const PlanDatabaseStats db = planned.database().stats();
    py::dict out;
    out["depth"] = planned.options().maxDepth;
    out["crease_nodes"] = planned.options().useCreaseNodes;
    out["faces"] = planned.cage().faceCount();
    out["subfaces"] = planned.subfaceCount();
    out["unique_plans"] = used.size();
    out["nodes"] = totalNodes;
    out["nodes_by_kind"] = byKind;
    out["stencils"] = stencils;
    out["bytes"] = bytes;
    out["control_points"] = controlPoints;
    out["control_point_bytes"] = controlPoints * sizeof(glm::vec3);
    out["database_plans"] = db.plans;
    out["database_hits"] = db.hits;
    out["database_misses"] = db.misses;
    out["database_from_cache"] = db.fromFallback;  // copied from the persistent plan cache
    return out;
}


py::array_t<float> pointsArray(const std::vector<LimitSample>& samples, glm::vec3 LimitSample::*member) {
    py::array_t<float> out({py::ssize_t(samples.size()), py::ssize_t(3)});
    float* data = out.mutable_data();
    for (size_t i = 0; i < samples.size(); ++i)
        for (int c = 0; c < 3; ++c) data[3 * i + c] = (samples[i].*member)[c];
    return out;
}

py::tuple tupleOf(const glm::vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

py::list objectsList(const Document& d) {
    py::list out;
    const Scene& scene = d.scene();
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
        const SceneObject& o = scene.objects[i];
        py::dict object;
        object["name"] = o.name;
        object["instance_of"] = o.isInstance() ? py::object(py::str(o.instanceOf)) : py::object(py::none());
        object["translation"] = tupleOf(o.transform.translation);
        object["rotation_degrees"] = tupleOf(o.transform.rotationDegrees);
        object["scale"] = tupleOf(o.transform.scale);
        object["visible"] = o.visible;
        object["faces"] = d.plannedScene().cages[d.plannedScene().cageOfObject[i]].cage().faceCount();
        object["active"] = i == d.activeObject();
        out.append(object);
    }
    return out;
}

py::dict scenePlanStatsDict(const Document& d) {
    const ScenePlanStats stats = scenePlanStats(d.scene(), d.plannedScene());
    py::list objects;
    for (const ObjectPlanStats& o : stats.objects) {
        py::dict object;
        object["name"] = o.name;
        object["instance_of"] = o.instanceOf.empty() ? py::object(py::none()) : py::object(py::str(o.instanceOf));
        object["faces"] = o.faces;
        object["plans"] = o.plans;
        object["shared_plans"] = o.sharedPlans;
        object["new_plans"] = o.newPlans;
        object["plan_bytes"] = o.planBytes;
        objects.append(object);
    }
    py::dict out;
    out["objects"] = objects;
    out["cages"] = stats.cages;
    out["unique_plans"] = stats.uniquePlans;
    out["shared_plans"] = stats.sharedPlans;
    out["plan_bytes"] = stats.planBytes;
    out["instance_faces"] = stats.instanceFaces;
    return out;
}

}  // namespace

// (sub-faces, u, v) broadcast against each other, checked.
std::vector<SampleRequest> sampleRequests(const PlannedCage& planned, const py::object& subfaces, const py::object& u,
                                          const py::object& v) {
    py::object numpy = py::module_::import("numpy");
    py::tuple arrays = numpy.attr("broadcast_arrays")(numpy.attr("asarray")(subfaces), numpy.attr("asarray")(u),
                                                       numpy.attr("asarray")(v));
    auto s = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(numpy.attr("ravel")(arrays[0]));
    auto us = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(numpy.attr("ravel")(arrays[1]));
    auto vs = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(numpy.attr("ravel")(arrays[2]));
    if (!s || !us || !vs) throw ScriptError("sub-faces must be integers and u, v numbers");
    std::vector<SampleRequest> requests(size_t(s.size()));
    for (size_t i = 0; i < requests.size(); ++i) {
        const int64_t subface = s.data()[i];
        const double a = us.data()[i], b = vs.data()[i];
        if (subface < 0 || subface >= int64_t(planned.subfaceCount()))
            throw ScriptError("sub-face " + std::to_string(subface) + " does not exist (the cage has " +
                              std::to_string(planned.subfaceCount()) + " sub-faces)");
        if (!planned.hasSurface(uint32_t(subface)))
            throw ScriptError("sub-face " + std::to_string(subface) + " has no limit surface (a hole, or a boundary under the rule \"none\")");
        if (!(a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0))
            throw ScriptError("u and v must lie in [0, 1]; sample " + std::to_string(i) + " has (" + std::to_string(a) + ", " +
                              std::to_string(b) + ")");
        requests[i] = {uint32_t(subface), float(a), float(b)};
    }
    return requests;
}

std::vector<uint32_t> verticesOf(const Document& doc, const py::object& target) {
    if (py::isinstance<Selection>(target)) {
        const Selection& s = target.cast<const Selection&>();
        check(checkSelection(s, doc.cage()));
        return selectedVertices(s, doc.cage());
    }
    return indicesFrom(target, "vertices");
}

ObjectTransform transformFrom(const py::object& translation, const py::object& rotation, const py::object& scale,
                              ObjectTransform base) {
    if (!translation.is_none()) base.translation = vec3From(translation, "translation");
    if (!rotation.is_none()) base.rotationDegrees = vec3From(rotation, "rotation_degrees");
    if (!scale.is_none()) base.scale = vec3From(scale, "scale");
    return base;
}

void bindScene(py::module_& m) {
    py::class_<EditOutcome>(m, "EditReport", R"doc(
What an edit did: how many faces were re-planned (their configuration looked up again), how many
sub-faces got new control points, how many plans had to be built (database misses), the time it
took, and the lists themselves (sorted, in the numbering after the edit). Topology operations also
say what they suggest selecting next (result_vertices, result_edges, result_faces), strokes how
many dabs they made and how many displacement samples they changed.
)doc")
        .def_readonly("name", &EditOutcome::name, "The history entry's name (\"Extrude\", \"Undo Crease\", ...).")
        .def_property_readonly("replanned_faces", [](const EditOutcome& o) { return o.report.replannedFaces; },
                               "Number of faces re-planned.")
        .def_property_readonly("updated_subfaces", [](const EditOutcome& o) { return o.report.updatedSubfaces; },
                               "Number of sub-faces whose control points were recomputed.")
        .def_property_readonly("new_plans", [](const EditOutcome& o) { return o.report.newPlans; },
                               "Plans built because the database had no plan for a configuration.")
        .def_property_readonly("milliseconds", [](const EditOutcome& o) { return o.report.milliseconds; },
                               "Time the PlannedCage spent on the edit.")
        .def_property_readonly("replanned_face_list", [](const EditOutcome& o) { return o.report.replannedFaceList; },
                               "The re-planned faces (sorted).")
        .def_property_readonly("updated_subface_list", [](const EditOutcome& o) { return o.report.updatedSubfaceList; },
                               "The sub-faces with new control points (sorted).")
        .def_property_readonly("topology_changed", [](const EditOutcome& o) { return o.report.topologyChanged; },
                               "Faces or vertices were renumbered.")
        .def_readonly("result_vertices", &EditOutcome::resultVertices, "Topology edits: vertices to select next.")
        .def_readonly("result_faces", &EditOutcome::resultFaces, "Topology edits: faces to select next.")
        .def_property_readonly("result_edges", [](const EditOutcome& o) {
                                   std::vector<std::pair<uint32_t, uint32_t>> out;
                                   for (const EdgeKey& e : o.resultEdges) out.push_back({e.v0, e.v1});
                                   return out;
                               }, "Topology edits: edges to select next, as (a, b).")
        .def_readonly("dabs", &EditOutcome::dabs, "Strokes: dabs applied.")
        .def_readonly("changed_samples", &EditOutcome::changedSamples, "Strokes: displacement samples changed.")
        .def("__repr__", [](const EditOutcome& o) {
            return "<quadplan.EditReport " + o.name + ": " + std::to_string(o.report.replannedFaces) + " faces re-planned, " +
                   std::to_string(o.report.updatedSubfaces) + " sub-faces updated, " + std::to_string(o.report.newPlans) + " new plans>";
        });

    py::class_<HistoryEntryInfo>(m, "HistoryEntry", "One entry of the undo history.")
        .def_readonly("name", &HistoryEntryInfo::name, "What the edit was.")
        .def_property_readonly("replanned_faces", [](const HistoryEntryInfo& e) { return e.report.replannedFaces; },
                               "Faces re-planned the last time it was done, undone or redone.")
        .def_readonly("bytes", &HistoryEntryInfo::bytes, "Memory the entry holds.")
        .def("__repr__", [](const HistoryEntryInfo& e) { return "<quadplan.HistoryEntry " + e.name + ">"; });

    py::class_<Document, std::unique_ptr<Document>> scene(m, "Scene", R"doc(
An open scene: a cage planned for its limit surface (one subdivision plan per face), the scene's
camera and tessellation settings, its sculpted displacement, and an undo history.

Every edit goes through the history and returns an EditReport; undo() and redo() re-plan only
what the edit re-planned. An edit that fails raises quadplan.Error with the message the command
line prints and changes nothing. Vertex and face indices are 0-based (messages count from 1).
A topology edit on a sculpted object carries the displacement to the new faces in the same entry.
An animated scene shows one frame at a time (set_frame); a move of an object with vertex keys keys
it at that frame and a topology edit carries its keys (docs/python.md, "Animation").
)doc");
    scene
        .def(py::init([](const Cage& cage, uint32_t depth) {
                 Scene s = sceneOfCage(cage, "cage");
                 std::vector<std::string> warnings;  // the plan cache's
                 Result<std::unique_ptr<Document>> doc = [&] {
                     py::gil_scoped_release release;
                     return Document::create(std::move(s), PlanOptions{depth, true}, "cage", &warnings);
                 }();
                 warnAll(warnings);
                 return unwrap(std::move(doc));
             }),
             py::arg("cage"), py::arg("depth") = 6, "A scene with default settings around a copy of the cage, planned to depth.")
        .def_static("load",
                    [](const std::string& path, uint32_t depth) {
                        std::vector<std::string> warnings;
                        Result<std::unique_ptr<Document>> doc = [&] {
                            py::gil_scoped_release release;
                            return Document::load(path, PlanOptions{depth, true}, &warnings);
                        }();
                        warnAll(warnings);
                        return unwrap(std::move(doc));
                    },
                    py::arg("path"), py::arg("depth") = 6,
                    "Opens a scene (.json) or a bare cage (.obj, .om, .ply, .off, .stl) and plans it (also quadplan.load).")
        .def("copy", &Document::copy, "An independent copy of the current state, with an empty history.")
        .def("save",
             [](Document& doc, const std::string& path, const py::object& inlineCage) {
                 const CageStorage storage = inlineCage.is_none() ? CageStorage::AsLoaded
                                             : inlineCage.cast<bool>() ? CageStorage::Inline
                                                                       : CageStorage::Referenced;
                 std::vector<std::string> lost;
                 check(doc.save(path, storage, &lost));
                 warnAll(lost);
             },
             py::arg("path"), py::arg("inline_cage") = py::none(),
             R"doc(Saves atomically. A .json path writes the scene, with the cage inline, or beside it as an OBJ when
inline_cage is False (default: as it was loaded); .obj or .om the cage alone with its tags; .ply, .off or .stl its
polygons alone (a warning names each tag lost). Any other name is refused.)doc")
        .def("export",
             [](const Document& doc, const std::string& path, uint32_t tess, bool displaced, bool split, bool optimize,
                const std::string& uv, const std::optional<float>& adaptive, std::pair<uint32_t, uint32_t> size) {
                 Result<UvMode> uvMode = parseUvMode(uv);
                 if (!uvMode) throw ScriptError(uvMode.error().message);
                 ExportOptions options;
                 options.uv = *uvMode;
                 options.factor = tess;
                 if (adaptive) {
                     if (!(*adaptive > 0.0f)) throw ScriptError("adaptive must be a positive number of pixels per segment");
                     if (size.first < 16 || size.second < 16) throw ScriptError("size must be at least 16 x 16 pixels");
                     Result<RenderCamera> camera =
                         cli::chooseCamera(doc.currentScene(), sceneBounds(doc.currentScene(), doc.plannedScene()),
                                           float(size.first) / float(size.second), "");
                     if (!camera) throw ScriptError(camera.error().message);
                     options.adaptive = adaptiveExport(*camera, size.second, *adaptive);
                 }
                 options.displaced = displaced;
                 options.split = split;
                 options.optimize = optimize;
                 Result<ExportReport> report = [&] {
                     py::gil_scoped_release release;
                     return exportScene(doc.currentScene(), sceneCages(doc.plannedScene()), path, options, doc.source());
                 }();
                 if (!report) throw ScriptError(report.error().message);
                 warnAll(report->notes);
                 py::dict out;
                 out["files"] = report->files;
                 out["vertices"] = report->vertices;
                 out["triangles"] = report->triangles;
                 out["objects"] = report->objects;
                 out["meshes"] = report->meshes;
                 out["watertight"] = report->closure.watertight();
                 out["border_edges"] = report->closure.borderEdges;
                 out["non_manifold_edges"] = report->closure.nonManifoldEdges;
                 out["acmr_before"] = optimize ? py::object(py::float_(report->order.acmrBefore)) : py::object(py::none());
                 out["acmr_after"] = optimize ? py::object(py::float_(report->order.acmrAfter)) : py::object(py::none());
                 out["ms"] = report->ms;
                 return out;
             },
             py::arg("path"), py::arg("tess") = 8, py::arg("displaced") = false, py::arg("split") = false,
             py::arg("optimize") = true, py::arg("uv") = "none", py::arg("adaptive") = py::none(),
             py::arg("size") = std::pair<uint32_t, uint32_t>(800, 600),
             R"doc(Exports the exact limit surface (as `quadplan export` does): one welded, watertight mesh per cage
at the uniform factor `tess` (or, with adaptive=PIXELS, cut as the grid path cuts it for the scene's camera at `size`),
as .glb/.gltf (a node per visible object, instances sharing a mesh) or .obj/.ply/.off/.stl (objects merged in the
world, or one file per object with split=True); displaced=True applies the sculpted displacement; uv="linear" adds
the cage's texture coordinates bilinear over each face, uv="smooth" OpenSubdiv's face-varying limit. Written atomically. Returns what was written (files, vertices, triangles, watertight, acmr_before,
acmr_after, ms).)doc")
        .def("bake",
             [](const Document& doc, const std::string& path, uint32_t size, const std::string& uv,
                const std::optional<std::string>& normalMap, uint32_t padding) {
                 Result<UvMode> uvMode = parseUvMode(uv);
                 if (!uvMode || *uvMode == UvMode::None) throw ScriptError("uv must be 'linear' or 'smooth', got '" + uv + "'");
                 BakeOptions options;
                 options.size = size;
                 options.uv = *uvMode;
                 options.padding = padding;
                 options.normalMap = normalMap.has_value();
                 Result<BakeReport> report = [&] {
                     py::gil_scoped_release release;
                     return bakeScene(doc.currentScene(), sceneCages(doc.plannedScene()), path, normalMap.value_or(""), options,
                                      doc.source());
                 }();
                 if (!report) throw ScriptError(report.error().message);
                 warnAll(report->notes);
                 py::dict out;
                 out["files"] = report->files;
                 out["island_texels"] = report->islandTexels;
                 out["padding_texels"] = report->paddingTexels;
                 out["min"] = report->minValue;
                 out["max"] = report->maxValue;
                 out["ms"] = report->ms;
                 return out;
             },
             py::arg("path"), py::arg("size") = 1024, py::arg("uv") = "linear", py::arg("normal_map") = py::none(),
             py::arg("padding") = 4,
             R"doc(Bakes the sculpted displacement (as `quadplan bake` does) into a size x size, 32-bit float OpenEXR
map at `path` (.exr) in the cage's UV space (uv="linear" or "smooth"), with `padding` texels grown around each UV
island, and with normal_map="FILE.png" a tangent-space normal map (OpenGL convention). Several sculpted objects give
one map each (NAME_OBJECT.exr). Written atomically. Returns files, island_texels, padding_texels, min, max, ms.)doc")
        .def_property_readonly("source", &Document::source, "The file the scene came from (or \"cage\").")
        .def_property_readonly("cage", [](const Document& d) { return d.cage(); }, "A copy of the current cage.")
        .def_property_readonly("positions", [](const Document& d) { return toArray(d.cage().positions); },
                               "Vertex positions, an (N, 3) float32 array (a copy).")
        .def_property_readonly("vertex_count", [](const Document& d) { return d.cage().vertexCount(); }, "Number of vertices.")
        .def_property_readonly("face_count", [](const Document& d) { return d.cage().faceCount(); }, "Number of faces.")
        .def_property_readonly("subface_count", [](const Document& d) { return d.planned().subfaceCount(); },
                               "Number of sub-faces (a quad is one, an n-gon n; OpenSubdiv's Ptex faces).")
        .def_property_readonly("faces", [](const Document& d) { return facesList(d.cage()); }, "Faces as vertex lists.")
        .def_property_readonly("edges", [](const Document& d) { return edgesArray(d.planned().topology()); },
                               "Edges, an (E, 2) array of vertex pairs (first < second).")
        .def_property_readonly("creases", [](const Document& d) { return creasesList(d.cage()); }, "(a, b, sharpness) per crease.")
        .def_property_readonly("corners", [](const Document& d) { return cornersList(d.cage()); }, "(vertex, sharpness) per corner.")
        .def_property_readonly("holes", [](const Document& d) { return d.cage().holes; }, "Faces tagged as holes.")
        .def_property_readonly("crease_method", [](const Document& d) { return enumName(kCreaseMethodNames, d.cage().options.creaseMethod); },
                               "\"normal\" or \"chaikin\".")
        .def_property_readonly("depth", [](const Document& d) { return d.planned().options().maxDepth; }, "Plan depth.")
        .def("face_of_subface", [](const Document& d, uint32_t s) {
                 if (s >= d.planned().subfaceCount()) throw ScriptError("sub-face " + std::to_string(s) + " does not exist");
                 return faceOfSubface(d.planned(), s);
             }, py::arg("subface"), "The face a sub-face belongs to.")
        .def("subfaces_of_face", [](const Document& d, uint32_t f) {
                 if (f >= d.cage().faceCount()) throw ScriptError("face " + std::to_string(f + 1) + " does not exist");
                 std::vector<uint32_t> out;
                 for (uint32_t s = d.planned().firstSubface(f); s < d.planned().firstSubface(f + 1); ++s) out.push_back(s);
                 return out;
             }, py::arg("face"), "The sub-faces of a face (one for a quad, n for an n-gon).")
        .def_property("camera", [](const Document& d) { return d.scene().camera; },
                      [](Document& d, std::optional<Camera> c) { d.settings().camera = c; },
                      "The scene's camera (None: renders frame the cage).")
        .def_property("tessellation", [](const Document& d) { return d.scene().tessellation; },
                      [](Document& d, const Tessellation& t) { d.settings().tessellation = t; },
                      "The scene's tessellation settings (a copy; assign to change them).")
        .def_property_readonly("viewport_schemes", [](const Document& d) {
                                   std::vector<std::string> out;
                                   for (const Viewport& v : d.scene().viewports) out.push_back(v.scheme);
                                   return out;
                               }, "The scheme of each of the scene's viewports.")
        .def("info", [](const Document& d) { return cageInfo(d.cage(), d.source()); },
             "Counts and histograms of the current cage (`quadplan info --json`'s object without \"file\").")
        .def("plan_stats", [](const Document& d) { return planStats(d.planned()); },
             R"doc(Plans of the current cage: the plans its sub-faces use (unique_plans), their quadtree nodes
(by kind), stencils and bytes, the control points, and the database's size, hits, misses (plans
built) and plans copied from the persistent plan cache (database_from_cache).)doc")
        .def("memory", [](const Document& d) {
                 const PlanMemory mem = measurePlanMemory(d.planned());
                 py::dict out;
                 out["vertex_bytes"] = mem.vertexBytes;
                 out["index_bytes"] = mem.indexBytes;
                 out["plans"] = mem.plans;
                 out["quadtree_bytes"] = mem.quadtreeBytes;
                 out["stencil_bytes"] = mem.stencilBytes;
                 out["scratch_bytes"] = mem.scratchBytes;
                 return out;
             },
             "GPU memory in the columns of the paper's Table 4 (render/plan_memory.h): vertex, index, plans, quadtree, stencils, scratch.")
        // ---- objects ----
        .def_property_readonly("objects", [](const Document& d) { return objectsList(d); },
             R"doc(The scene's objects in order, one dict each: name, instance_of (None: a cage of its own),
translation, rotation_degrees, scale, visible, faces, active.)doc")
        .def_property("active_object", [](const Document& d) { return d.scene().objects[d.activeObject()].name; },
             [](Document& d, const std::string& name) { check(d.setActive(name)); },
             "The object every cage, tag, displacement and selection call acts on (an object with a cage of its own).")
        .def("object", [](py::object self, const std::string& name) {
                 check(self.cast<Document&>().setActive(name));
                 return self;
             }, py::arg("name"),
             R"doc(Makes `name` the active object and returns the scene, so scene.object("car").extrude([3], 0.2)
edits the car (and so does every later cage call, until another object is made active).)doc")
        .def("add_object",
             [](Document& d, const py::object& source, const std::string& name, const py::object& translation,
                const py::object& rotation, const py::object& scale) {
                 Cage cage;
                 std::string base = name;
                 if (py::isinstance<py::str>(source)) {
                     std::vector<std::string> warnings;
                     const std::string path = source.cast<std::string>();
                     Result<Scene> loaded = loadSceneOrCage(path, &warnings);
                     warnAll(warnings);
                     Scene scene = unwrap(std::move(loaded));
                     if (scene.objects.size() != 1 || scene.objects[0].isInstance())
                         throw ScriptError(path + ": add_object takes a cage (or a scene of one object); this scene has " +
                                           std::to_string(scene.objects.size()) + " objects");
                     cage = std::move(scene.objects[0].cage);
                     if (base.empty()) base = scene.objects[0].name;
                 } else {
                     cage = source.cast<Cage>();
                 }
                 const ObjectTransform transform = transformFrom(translation, rotation, scale, ObjectTransform{});
                 Result<std::string> added = [&] {
                     py::gil_scoped_release release;
                     return d.addObject(std::move(cage), base, transform);
                 }();
                 return unwrap(std::move(added));
             },
             py::arg("cage"), py::arg("name") = "", py::arg("translation") = py::none(), py::arg("rotation_degrees") = py::none(),
             py::arg("scale") = py::none(),
             R"doc(Adds an object from a cage file (any cage the product opens) or a quadplan.Cage, planned through the
scene's one plan database (configurations it shares with other objects add no plans). Returns the
name it got (`name`, else the file's or "object", made unique as "name.001"). Undoable.)doc")
        .def("instance",
             [](Document& d, const std::string& source, const std::string& name, const py::object& translation,
                const py::object& rotation, const py::object& scale) {
                 const ObjectTransform transform = transformFrom(translation, rotation, scale, ObjectTransform{});
                 return unwrap(d.addInstance(source, name, transform));
             },
             py::arg("source"), py::arg("name") = "", py::arg("translation") = py::none(), py::arg("rotation_degrees") = py::none(),
             py::arg("scale") = py::none(),
             R"doc(Adds an instance of `source`: its cage, plans and displacement, drawn under its own transform. It
plans nothing. Returns its name. Undoable.)doc")
        .def("remove_object", [](Document& d, const std::string& name) { check(d.removeObject(name)); }, py::arg("name"),
             "Removes an object (refused while others instance it, and for the last object with a cage). Undoable.")
        .def("rename_object", [](Document& d, const std::string& name, const std::string& to) { check(d.renameObject(name, to)); },
             py::arg("name"), py::arg("new_name"), "Renames an object; instance links follow. Undoable.")
        .def("set_transform",
             [](Document& d, const std::string& name, const py::object& translation, const py::object& rotation,
                const py::object& scale) {
                 const uint32_t i = findObject(d.scene().objects, name);
                 const ObjectTransform current = i == UINT32_MAX ? ObjectTransform{} : d.scene().objects[i].transform;
                 check(d.setTransform(name, transformFrom(translation, rotation, scale, current)));
             },
             py::arg("name"), py::arg("translation") = py::none(), py::arg("rotation_degrees") = py::none(),
             py::arg("scale") = py::none(),
             R"doc(Sets an object's transform (the parts given; the others stay). Re-plans and re-evaluates nothing. An
object with transform keys gets a key at the current frame instead (set_transform_key). Undoable.)doc")
        .def("set_visible", [](Document& d, const std::string& name, bool visible) { check(d.setVisible(name, visible)); },
             py::arg("name"), py::arg("visible"), "Shows or hides an object (hidden ones are kept and saved). Undoable.");
    bindSceneAnimation(scene);
    bindSceneDisplacement(scene);
    scene
        .def("scene_plan_stats", [](const Document& d) { return scenePlanStatsDict(d); },
             R"doc(Plans per object and for the whole scene, as `quadplan plan-stats --json` reports them: objects
(name, instance_of, faces, plans, shared_plans, new_plans, plan_bytes), cages, unique_plans,
shared_plans, plan_bytes, instance_faces.)doc")
        .def("differences_from_rebuild", [](const Document& d) {
                 py::gil_scoped_release release;
                 return d.differencesFromRebuild();
             }, "Per sub-face differences between the incrementally kept plans and planning from scratch (empty: equal).")
        .def("check_limit",
             [](const Document& d, uint32_t samples) {
                 if (samples < 2 || samples > 1000) throw ScriptError("samples must be between 2 and 1000");
                 const uint32_t depth = d.planned().options().maxDepth;
                 LimitCheck c;
                 {
                     py::gil_scoped_release release;
                     Result<LimitReference> reference = LimitReference::create(d.cage(), depth, d.source());
                     if (!reference) throw ScriptError(reference.error().message);
                     c = compareWithReference(d.planned(), *reference, samples);
                 }
                 py::dict out;
                 out["subfaces"] = c.subfaces;
                 out["samples"] = c.samples;
                 out["depth"] = depth;
                 out["max_rel_error_position"] = c.maxPositionError;
                 out["max_rel_error_derivative"] = c.maxDerivativeError;
                 out["tolerance_position"] = kPositionTolerance;
                 out["tolerance_derivative"] = derivativeTolerance(depth);
                 out["pass"] = c.pass();
                 return out;
             },
             py::arg("samples") = 9,
             "The planned limit surface against OpenSubdiv's at the same depth (`quadplan check-limit --json`'s numbers).")

        // ---- evaluation ----
        .def("evaluate",
             [](const Document& d, const py::object& subfaces, const py::object& u, const py::object& v, bool derivatives) -> py::object {
                 const std::vector<SampleRequest> requests = sampleRequests(d.planned(), subfaces, u, v);
                 std::vector<LimitSample> out(requests.size());
                 {
                     py::gil_scoped_release release;
                     evaluateBatch(d.planned(), requests, out);
                 }
                 if (!derivatives) return pointsArray(out, &LimitSample::position);
                 return py::make_tuple(pointsArray(out, &LimitSample::position), pointsArray(out, &LimitSample::du),
                                       pointsArray(out, &LimitSample::dv));
             },
             py::arg("subfaces"), py::arg("u"), py::arg("v"), py::arg("derivatives") = false,
             R"doc(The exact limit surface at (sub-face, u, v), batched on all cores: subfaces, u and v are arrays (or
scalars) broadcast against each other, u and v in [0, 1] in the sub-face's frame. Returns an (N, 3)
float32 array of positions, or (positions, du, dv) with derivatives=True. Sub-faces without a
surface (holes) raise quadplan.Error.)doc")
        .def("sample_grid",
             [](const Document& d, uint32_t segments) {
                 if (segments < 1 || segments > 256) throw ScriptError("segments must be between 1 and 256");
                 const SubfaceGrid grid = buildSubfaceGrid(d.planned(), segments);
                 std::vector<uint32_t> subfaces(grid.samples.size());
                 std::vector<float> us(grid.samples.size()), vs(grid.samples.size());
                 for (size_t i = 0; i < grid.samples.size(); ++i)
                     subfaces[i] = grid.samples[i].subface, us[i] = grid.samples[i].u, vs[i] = grid.samples[i].v;
                 py::array_t<uint32_t> triangles({py::ssize_t(grid.indices.size() / 3), py::ssize_t(3)});
                 std::copy(grid.indices.begin(), grid.indices.end(), triangles.mutable_data());
                 return py::make_tuple(toArray(subfaces), py::array_t<float>(py::ssize_t(us.size()), us.data()),
                                       py::array_t<float>(py::ssize_t(vs.size()), vs.data()), triangles);
             },
             py::arg("segments") = 16,
             R"doc(The grid `quadplan compare` measures errors on: (subfaces, u, v, triangles), `segments` per quad
sub-face edge (n-gon sub-faces half as many), every sub-face with a surface.)doc")

        // ---- selection ----
        .def("select_all", [](const Document& d, const std::string& mode) {
                 return selectAll(d.cage(), d.planned().topology(), enumFrom(kSelectionModeNames, mode, "selection mode"));
             }, py::arg("mode") = "vertex", "Every vertex used by a face, every edge or every face.")
        .def("grow", [](const Document& d, const Selection& s) { return growSelection(checkedSelection(d, s), d.cage(), d.planned().topology()); },
             py::arg("selection"), "Adds the neighbours (vertices by an edge, edges and faces sharing a vertex).")
        .def("shrink", [](const Document& d, const Selection& s) { return shrinkSelection(checkedSelection(d, s), d.cage(), d.planned().topology()); },
             py::arg("selection"), "Drops the elements next to an unselected one (the inverse of grow).")
        .def("invert", [](const Document& d, const Selection& s) { return invertSelection(checkedSelection(d, s), d.cage(), d.planned().topology()); },
             py::arg("selection"), "Everything of the mode that is not selected.")
        .def("convert", [](const Document& d, const Selection& s, const std::string& mode) {
                 return convertSelection(checkedSelection(d, s), enumFrom(kSelectionModeNames, mode, "selection mode"), d.cage(),
                                         d.planned().topology());
             }, py::arg("selection"), py::arg("mode"),
             "To another mode: vertex->face takes faces with every corner selected, face->vertex their corners, etc.")
        .def("selected_vertices", [](const Document& d, const Selection& s) { return selectedVertices(checkedSelection(d, s), d.cage()); },
             py::arg("selection"), "The vertices a transform of the selection moves (sorted).")

        // ---- edits ----
        .def("move_vertices",
             [](Document& d, const py::object& vertices, const py::object& positions, bool merge) {
                 const std::vector<uint32_t> vs = verticesOf(d, vertices);
                 const std::vector<glm::vec3> ps = pointsFrom(positions, "positions");
                 return unwrap(d.moveVertices(vs, ps, "Move", merge));
             },
             py::arg("vertices"), py::arg("positions"), py::arg("merge") = false,
             R"doc(Moves vertices to new absolute positions (one (x, y, z) each). Re-plans nothing; the sub-faces
whose 1-ring holds a moved vertex get new control points. merge=True extends the newest history
entry when it moved the same vertices (one drag, one entry). On an object with vertex keys the move
keys the moved vertices at the current frame (a whole one) instead, one entry each.)doc")
        .def("translate",
             [](Document& d, const py::object& target, const py::object& offset, const std::string& space) {
                 return unwrap(d.translate(verticesOf(d, target), vec3From(offset, "offset"), enumFrom(kSpaceNames, space, "space")));
             },
             py::arg("target"), py::arg("offset"), py::arg("space") = "world",
             R"doc(Moves a Selection (or vertex indices) by offset, in world axes or local ones ("local": z is the
selection's normal, x world x projected onto its plane).)doc")
        .def("rotate",
             [](Document& d, const py::object& target, const py::object& axis, float degrees, const std::string& space,
                const py::object& pivot) {
                 std::optional<glm::vec3> p;
                 if (!pivot.is_none()) p = vec3From(pivot, "pivot");
                 return unwrap(d.rotate(verticesOf(d, target), vec3From(axis, "axis"), degrees, enumFrom(kSpaceNames, space, "space"), p));
             },
             py::arg("target"), py::arg("axis"), py::arg("degrees"), py::arg("space") = "world", py::arg("pivot") = py::none(),
             "Rotates counter-clockwise about axis (in the frame's axes) through the pivot (default: the centroid).")
        .def("scale",
             [](Document& d, const py::object& target, const py::object& factors, const std::string& space, const py::object& pivot) {
                 std::optional<glm::vec3> p;
                 if (!pivot.is_none()) p = vec3From(pivot, "pivot");
                 return unwrap(d.scale(verticesOf(d, target), vec3From(factors, "factors"), enumFrom(kSpaceNames, space, "space"), p));
             },
             py::arg("target"), py::arg("factors"), py::arg("space") = "world", py::arg("pivot") = py::none(),
             "Scales by one factor or (fx, fy, fz) in the frame's axes about the pivot (default: the centroid); 0 flattens.")
        .def("set_crease", [](Document& d, uint32_t a, uint32_t b, float sharpness) {
                 const EdgeCrease crease{a, b, sharpness};
                 return unwrap(d.setEdgeSharpness({&crease, 1}));
             }, py::arg("a"), py::arg("b"), py::arg("sharpness"),
             "Sets the sharpness of edge a-b (0 clears it; 10 or more is infinitely sharp). Re-plans the faces at a and b.")
        .def("set_creases",
             [](Document& d, const py::object& edges, const py::object& sharpness) {
                 std::vector<EdgeCrease> creases;
                 if (py::isinstance<Selection>(edges)) {
                     const Selection& s = checkedSelection(d, edges.cast<const Selection&>());
                     if (s.mode != SelectionMode::Edge) throw ScriptError("an edge selection is needed here; convert it first (Scene.convert)");
                     if (sharpness.is_none()) throw ScriptError("give the sharpness for the selected edges");
                     for (const EdgeKey& e : s.edges) creases.push_back({e.v0, e.v1, sharpness.cast<float>()});
                 } else {
                     if (!sharpness.is_none()) throw ScriptError("give either (a, b, sharpness) triples, or a Selection and a sharpness");
                     creases = creasesFrom(edges);
                 }
                 return unwrap(d.setEdgeSharpness(creases));
             },
             py::arg("edges"), py::arg("sharpness") = py::none(),
             "Several creases in one edit: (a, b, sharpness) triples, or an edge Selection with one sharpness.")
        .def("set_corner", [](Document& d, uint32_t vertex, float sharpness) {
                 const VertexCorner corner{vertex, sharpness};
                 return unwrap(d.setVertexSharpness({&corner, 1}));
             }, py::arg("vertex"), py::arg("sharpness"), "Sets a vertex's corner sharpness (0 clears it). Re-plans the faces at it.")
        .def("set_corners", [](Document& d, const py::object& corners) { return unwrap(d.setVertexSharpness(cornersFrom(corners))); },
             py::arg("corners"), "Several corners in one edit: (vertex, sharpness) pairs.")
        .def("set_holes", [](Document& d, const py::object& faces, bool hole) { return unwrap(d.setHoles(facesOf(faces), hole)); },
             py::arg("faces"), py::arg("hole") = true, "Tags faces (a face Selection or indices) as holes, or clears the tag. Re-plans only them.")
        .def("set_crease_method",
             [](Document& d, const std::string& method) {
                 return unwrap(d.setCreaseMethod(enumFrom(kCreaseMethodNames, method, "crease method")));
             },
             py::arg("method"), "\"normal\" or \"chaikin\". Re-plans every face (the options are part of every plan's key).")
        .def("extrude", [](Document& d, const py::object& faces, float distance) { return unwrap(d.extrude(facesOf(faces), distance)); },
             py::arg("faces"), py::arg("distance") = 0.0f,
             R"doc(Region extrude of the faces along their normal by distance (0: in place, to move result_vertices
afterwards). Re-plans the region, its neighbours and the new side quads.)doc")
        .def("delete_faces",
             [](Document& d, const py::object& faces, bool removeUnused) { return unwrap(d.deleteFaces(facesOf(faces), removeUnused)); },
             py::arg("faces"), py::arg("remove_unused_vertices") = true,
             "Deletes faces (leaving an open boundary); with remove_unused_vertices, also the vertices only they used.")
        .def("split_face", [](Document& d, uint32_t face, uint32_t a, uint32_t b) { return unwrap(d.splitFace(face, a, b)); },
             py::arg("face"), py::arg("a"), py::arg("b"), "Splits a face by a new edge between its non-adjacent corners a and b.")
        .def("insert_edge_loop", [](Document& d, uint32_t a, uint32_t b, float t) { return unwrap(d.insertEdgeLoop(a, b, t)); },
             py::arg("a"), py::arg("b"), py::arg("t") = 0.5f,
             "Cuts the ring of quads across edge a-b at fraction t (0 < t < 1) from a.")
        .def("merge_vertices",
             [](Document& d, const py::object& vertices, const std::string& target) {
                 if (target != "centroid" && target != "last") throw ScriptError("merge target must be centroid or last");
                 return unwrap(d.mergeVertices(verticesOf(d, vertices), target == "centroid" ? MergeTarget::Centroid : MergeTarget::Last));
             },
             py::arg("vertices"), py::arg("target") = "centroid",
             "Merges the vertices into the last one, placed at their centroid or where the last one is.")
        .def("make_face", [](Document& d, const py::object& vertices) { return unwrap(d.makeFace(indicesFrom(vertices, "vertices"))); },
             py::arg("vertices"), "Adds a face through existing vertices (reversed if its neighbours' orientation says so).")

        // ---- history ----
        .def("undo", [](Document& d) { return unwrap(d.undo()); }, "Undoes the newest applied entry (raises when there is none).")
        .def("redo", [](Document& d) { return unwrap(d.redo()); }, "Redoes the next entry (raises when there is none).")
        .def("jump_to", [](Document& d, size_t position) { return unwrap(d.jumpTo(position)); }, py::arg("position"),
             "Undoes or redoes until `position` entries are applied; the report adds up every step.")
        .def_property_readonly("can_undo", [](const Document& d) { return d.history().canUndo(); }, "Whether undo() has something to undo.")
        .def_property_readonly("can_redo", [](const Document& d) { return d.history().canRedo(); }, "Whether redo() has something to redo.")
        .def_property_readonly("history_position", [](const Document& d) { return d.history().position(); },
                               "How many history entries are applied.")
        .def_property_readonly("history", [](const Document& d) {
                                   std::vector<HistoryEntryInfo> out;
                                   for (size_t i = 0; i < d.history().size(); ++i) out.push_back(d.history().entry(i));
                                   return out;
                               }, "The history entries, oldest first.")
        .def_property_readonly("history_bytes", [](const Document& d) { return d.history().bytes(); }, "Memory the history holds.")
        .def_property("history_budget", [](const Document& d) { return d.history().budget(); },
                      [](Document& d, size_t bytes) { d.setHistoryBudget(bytes); },
                      "Memory the history may hold (bytes, default 256 MiB); past it the oldest entries are dropped.")
        .def("__repr__", [](const Document& d) {
            return "<quadplan.Scene " + d.source() + ": " + std::to_string(d.cage().vertexCount()) + " vertices, " +
                   std::to_string(d.cage().faceCount()) + " faces, " + std::to_string(d.history().size()) + " history entries>";
        });
}

}  // namespace qp::py
