// quadplan.Renderer and the Scene's drawing methods (render, render_displaced, render_error,
// compare), quadplan.schemes(), PNG reading and writing.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

#include "conversions.h"
#include "headless_renderer.h"
#include "offscreen_target.h"

namespace qp::py {

namespace {

// What Python holds: close() releases the Vulkan context before the interpreter goes away.
struct RendererHandle {
    std::unique_ptr<HeadlessRenderer> renderer;
    py::dict lastStats;
    HeadlessRenderer& get() {
        if (!renderer) throw ScriptError("this renderer was closed");
        return *renderer;
    }
};

py::array_t<uint8_t> imageArray(const RenderedImage& image) {
    py::array_t<uint8_t> out({py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(4)});
    std::copy(image.rgba.begin(), image.rgba.end(), out.mutable_data());
    return out;
}

RendererHandle& rendererOf(const py::object& renderer) {
    py::object chosen = renderer.is_none() ? py::module_::import("quadplan").attr("default_renderer")() : renderer;
    if (!py::isinstance<RendererHandle>(chosen)) throw ScriptError("renderer must be a quadplan.Renderer");
    return chosen.cast<RendererHandle&>();
}

std::pair<uint32_t, uint32_t> sizeFrom(const py::object& size) {
    const std::vector<uint32_t> wh = indicesFrom(size, "size");
    if (wh.size() != 2) throw ScriptError("size must be (width, height)");
    return {wh[0], wh[1]};
}

SchemeOptions optionsFrom(const py::object& options) {
    SchemeOptions out;
    if (options.is_none()) return out;
    for (const auto& [key, value] : options.cast<py::dict>()) out.push_back({py::str(key), py::str(value)});
    return out;
}

RenderRequest requestFrom(const std::string& scheme, const py::object& size, const std::optional<Camera>& camera,
                          const py::object& tess, const py::object& adaptive, bool wireframe, const py::object& cage,
                          const std::string& colorBy, const py::object& options) {
    RenderRequest request;
    request.scheme = scheme;
    std::tie(request.width, request.height) = sizeFrom(size);
    request.camera = camera;
    if (!tess.is_none()) {
        const int t = tess.cast<int>();
        if (t < 1 || t > 64) throw ScriptError("tess must be between 1 and 64, got " + std::to_string(t));
        request.tess = uint32_t(t);
    }
    if (!adaptive.is_none()) {
        request.adaptive = adaptive.cast<float>();
        if (!(request.adaptive > 0.0f)) throw ScriptError("adaptive must be a positive number of pixels per segment");
    }
    request.wireframe = wireframe;
    if (!cage.is_none()) request.showCage = cage.cast<bool>();
    request.colorBy = colorBy;
    request.options = optionsFrom(options);
    return request;
}

py::array_t<uint8_t> finishImage(RendererHandle& handle, const RenderedImage& image, const py::object& out) {
    handle.lastStats = py::dict();
    handle.lastStats["patches"] = image.draw.patches;
    handle.lastStats["triangles"] = image.draw.triangles;
    // Of the triangles, those the CPU grid left out (render/sample_culling.h): covering no pixel
    // centre, and facing away behind the front under a back-patch cull method.
    handle.lastStats["sample_culled"] = image.draw.sampleCulledTriangles;
    handle.lastStats["facing_away"] = image.draw.facingAwayTriangles;
    py::dict culled;
    culled["tested"] = image.draw.cull.tested;
    culled["frustum"] = image.draw.cull.frustum;
    culled["back_facing"] = image.draw.cull.backFacing;
    culled["frustum_only"] = image.draw.cull.frustumOnly;
    culled["cull_ms"] = image.draw.cullMilliseconds;
    handle.lastStats["culled"] = culled;
    handle.lastStats["approximations"] = image.approximations;
    if (!out.is_none()) check(writePng(py::str(out), image.width, image.height, image.rgba));
    return imageArray(image);
}

py::dict errorDict(const ErrorStats& e) {
    py::dict out;
    out["max_rel_error"] = e.maxRelError;
    out["rms_rel_error"] = e.rmsRelError;
    out["max_normal_deg"] = e.maxNormalDegrees;
    out["p99_normal_deg"] = e.p99NormalDegrees;
    out["normal_samples_excluded"] = e.normalSamplesExcluded;
    out["normal_samples_no_tangent_plane"] = e.normalSamplesWithoutTangentPlane;
    out["samples"] = e.samples;
    return out;
}

std::vector<uint8_t> rgbaFrom(const py::object& image, uint32_t& width, uint32_t& height) {
    auto array = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(image);
    if (!array || array.ndim() != 3 || (array.shape(2) != 3 && array.shape(2) != 4))
        throw ScriptError("an image is an (height, width, 4) or (height, width, 3) array of uint8");
    height = uint32_t(array.shape(0));
    width = uint32_t(array.shape(1));
    const size_t channels = size_t(array.shape(2));
    std::vector<uint8_t> rgba(size_t(width) * height * 4, 255);
    for (size_t p = 0; p < size_t(width) * height; ++p)
        for (size_t c = 0; c < channels; ++c) rgba[4 * p + c] = array.data()[channels * p + c];
    return rgba;
}

}  // namespace

void bindRender(py::module_& m) {
    py::class_<RendererHandle>(m, "Renderer", R"doc(
A headless Vulkan renderer with the scheme plugins: what Scene.render, render_displaced,
render_error and compare draw with. Scenes use quadplan.default_renderer() unless given one.

validation: Vulkan validation layers on; any message during a call makes it raise quadplan.Error.
device: part of a device name (default: $QUADPLAN_VK_DEVICE, else a GPU if any, else lavapipe).
lavapipe: use Mesa's CPU driver only (what tests do: its pictures are deterministic).
plugin_dir: where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else the ones built or
installed with this module).
)doc")
        .def(py::init([](bool validation, const std::string& device, bool lavapipe, const std::string& pluginDir) {
                 RendererOptions options{validation, device, lavapipe, pluginDir};
                 Result<std::unique_ptr<HeadlessRenderer>> renderer = [&] {
                     py::gil_scoped_release release;
                     return HeadlessRenderer::create(options);
                 }();
                 return RendererHandle{unwrap(std::move(renderer)), py::dict()};
             }),
             py::arg("validation") = false, py::arg("device") = "", py::arg("lavapipe") = false, py::arg("plugin_dir") = "")
        .def("close", [](RendererHandle& h) { h.renderer.reset(); },
             "Releases the Vulkan device now (also done when the object is collected).")
        .def("__enter__", [](RendererHandle& h) -> RendererHandle& { return h; }, py::return_value_policy::reference)
        .def("__exit__", [](RendererHandle& h, const py::args&) { h.renderer.reset(); })
        .def_property_readonly("device_name", [](RendererHandle& h) { return h.get().deviceName(); }, "The Vulkan device.")
        .def_property_readonly("is_software", [](RendererHandle& h) { return h.get().isSoftware(); },
                               "Whether the device is a CPU implementation such as lavapipe.")
        .def_property_readonly("validation", [](RendererHandle& h) { return h.get().validation(); },
                               "Whether validation layers are on.")
        .def_property_readonly("plugin_directory", [](RendererHandle& h) { return h.get().catalog().directory; },
                               "Where the scheme plugins were loaded from.")
        .def_property_readonly("schemes", [](RendererHandle& h) {
                                   py::list out;
                                   for (const auto& p : h.get().catalog().plugins) {
                                       py::dict d;
                                       d["name"] = p->name;
                                       d["summary"] = p->summary;
                                       d["path"] = p->path;
                                       out.append(d);
                                   }
                                   return out;
                               }, "The loaded scheme plugins: name, summary, path (as `quadplan schemes --json`).")
        .def_property_readonly("plugin_problems", [](RendererHandle& h) {
                                   std::vector<std::string> out;
                                   for (const PluginProblem& p : h.get().catalog().problems) out.push_back(p.message);
                                   return out;
                               }, "Messages about modules in the plugin directory that could not be loaded.")
        .def("support",
             [](RendererHandle& h, const SceneDocument& d) {
                 const CageFeatures features = analyzeCage(d.cage(), d.planned().topology());
                 py::dict out;
                 for (const auto& plugin : h.get().catalog().plugins) {
                     Result<SchemeInstance> instance = SchemeInstance::create(plugin);
                     Result<SupportReport> report = instance ? instance->support(features, SchemeSettings{})
                                                             : Result<SupportReport>(instance.error());
                     py::dict entry;
                     if (!report) {
                         entry["error"] = report.error().message;
                     } else {
                         entry["approximations"] = report->approximations;
                         entry["refusals"] = report->refusals;
                     }
                     out[py::str(plugin->name)] = entry;
                 }
                 return out;
             },
             py::arg("scene"), "What each scheme approximates or refuses on the scene's cage (`quadplan schemes CAGE`).")
        .def_property_readonly("last_stats", [](RendererHandle& h) { return h.lastStats; },
                               "The last render's patches, triangles (sample_culled and facing_away of them left out), culled patches (tested, frustum, back_facing, frustum_only, cull_ms) and the scheme's approximations.")
        .def("__repr__", [](RendererHandle& h) {
            return h.renderer ? "<quadplan.Renderer on " + h.renderer->deviceName() + ">" : std::string("<quadplan.Renderer (closed)>");
        });

    auto scene = py::reinterpret_borrow<py::class_<SceneDocument, std::unique_ptr<SceneDocument>>>(m.attr("Scene"));
    scene
        .def("render",
             [](const SceneDocument& d, const std::string& scheme, const py::object& size, std::optional<Camera> camera,
                const py::object& tess, const py::object& adaptive, bool wireframe, const py::object& cage,
                const std::string& colorBy, const py::object& options, const std::string& cull, const py::object& out,
                const py::object& renderer) {
                 RendererHandle& handle = rendererOf(renderer);
                 RenderRequest request = requestFrom(scheme, size, camera, tess, adaptive, wireframe, cage, colorBy, options);
                 const std::optional<CullMethod> method = parseCullMethod(cull);
                 if (!method) throw ScriptError("unknown cull '" + cull + "'; use none, frustum, tcone, ncone or pplane");
                 request.cull = *method;
                 Result<RenderedImage> image = [&] {
                     py::gil_scoped_release release;
                     return handle.get().render(d, request);
                 }();
                 return finishImage(handle, unwrap(std::move(image)), out);
             },
             py::arg("scheme") = "plans", py::arg("size") = py::make_tuple(800, 600), py::arg("camera") = py::none(),
             py::arg("tess") = py::none(), py::arg("adaptive") = py::none(), py::arg("wireframe") = false,
             py::arg("cage") = py::none(), py::arg("color_by") = "shading", py::arg("options") = py::none(),
             py::arg("cull") = "none", py::arg("out") = py::none(), py::arg("renderer") = py::none(),
             R"doc(Draws the limit surface through a scheme plugin (with the scene's sculpted displacement, each scheme
along its own normal), as `quadplan render` does, and returns the picture
as a (height, width, 4) uint8 array (sRGB, rows top to bottom); out="file.png" also writes it.

scheme: a loaded plugin ("plans", "osd-fas", "uniform", ...); camera: a quadplan.Camera (default:
the scene's, else framed on the cage); tess: uniform factor 1..64, or adaptive: pixels per segment
(default: the scene's tessellation settings); wireframe: the tessellation's edges; cage: draw the
cage (default: the scene's setting); color_by: "shading" or a scheme's own mode (plans: node-kind,
depth, sharpness); options: the scheme's key/value options (e.g. {"level": 4} for uniform); cull:
"none", "frustum", "tcone", "ncone" or "pplane", patches skipped that cannot show a pixel (the picture is
the same; Renderer.last_stats["culled"] says what was culled).)doc")
        .def("render_displaced",
             [](const SceneDocument& d, const py::object& size, std::optional<Camera> camera, const py::object& tess,
                bool wireframe, const py::object& cage, const py::object& out, const py::object& renderer) {
                 RendererHandle& handle = rendererOf(renderer);
                 const RenderRequest request = requestFrom("", size, camera, tess, py::none(), wireframe, cage, "shading", py::none());
                 Result<RenderedImage> image = [&] {
                     py::gil_scoped_release release;
                     return handle.get().renderDisplaced(d, request);
                 }();
                 return finishImage(handle, unwrap(std::move(image)), out);
             },
             py::arg("size") = py::make_tuple(800, 600), py::arg("camera") = py::none(), py::arg("tess") = py::none(),
             py::arg("wireframe") = false, py::arg("cage") = py::none(), py::arg("out") = py::none(),
             py::arg("renderer") = py::none(),
             R"doc(Draws the displaced surface (limit surface + D along its normal) as a CPU triangle mesh fine enough
to show every displacement sample (at least `tess` per quad edge), lit, as `quadplan sculpt --png`.)doc")
        .def("render_error",
             [](const SceneDocument& d, const std::string& scheme, const py::object& size, std::optional<Camera> camera,
                uint32_t tess, uint32_t samples, const py::object& options, const py::object& out, const py::object& renderer) {
                 RendererHandle& handle = rendererOf(renderer);
                 RenderRequest request = requestFrom(scheme, size, camera, py::int_(tess), py::none(), false, py::bool_(false),
                                                     "shading", options);
                 ErrorStats stats;
                 Result<RenderedImage> image = [&] {
                     py::gil_scoped_release release;
                     return handle.get().renderError(d, request, samples, &stats);
                 }();
                 py::array_t<uint8_t> pixels = finishImage(handle, unwrap(std::move(image)), out);
                 return py::make_tuple(pixels, errorDict(stats));
             },
             py::arg("scheme"), py::arg("size") = py::make_tuple(360, 300), py::arg("camera") = py::none(), py::arg("tess") = 8,
             py::arg("samples") = 16, py::arg("options") = py::none(), py::arg("out") = py::none(), py::arg("renderer") = py::none(),
             R"doc(The scheme's error against the exact limit surface as a heat map (the lower tiles of `quadplan
compare`: one colour per decade from 1e-7, dark blue, to 1e-1, red, relative to the bounding-box
diagonal), on a grid of `samples` segments per sub-face edge. Returns (image, numbers).)doc")
        .def("compare",
             [](const SceneDocument& d, const py::object& schemes, uint32_t tess, uint32_t samples, uint32_t depth, uint32_t repeats,
                const py::object& size, std::optional<Camera> camera, const py::object& options, const py::object& renderer) {
                 RendererHandle& handle = rendererOf(renderer);
                 CompareRequest request;
                 if (!schemes.is_none())
                     for (const py::handle s : py::iter(schemes)) request.schemes.push_back(py::str(s));
                 std::tie(request.tileWidth, request.tileHeight) = sizeFrom(size);
                 request.tess = tess, request.samples = samples, request.depth = depth, request.repeats = repeats;
                 request.camera = camera;
                 if (!options.is_none())
                     for (const auto& [scheme, pairs] : options.cast<py::dict>())
                         for (const auto& [key, value] : optionsFrom(py::reinterpret_borrow<py::object>(pairs)))
                             request.options.push_back({py::str(scheme), {key, value}});
                 Result<std::vector<SchemeComparison>> results = [&] {
                     py::gil_scoped_release release;
                     return handle.get().compare(d, request);
                 }();
                 py::list drawn, skipped;
                 for (const SchemeComparison& r : unwrap(std::move(results))) {
                     py::dict entry;
                     entry["name"] = r.name;
                     if (!r.drawn) {
                         entry["reason"] = r.reason;
                         skipped.append(entry);
                         continue;
                     }
                     entry["max_rel_error"] = r.error.maxRelError;
                     entry["rms_rel_error"] = r.error.rmsRelError;
                     entry["max_normal_deg"] = r.error.maxNormalDegrees;
                     entry["p99_normal_deg"] = r.error.p99NormalDegrees;
                     entry["normal_samples_excluded"] = r.error.normalSamplesExcluded;
                     entry["normal_samples_no_tangent_plane"] = r.error.normalSamplesWithoutTangentPlane;
                     entry["patches"] = r.draw.patches;
                     entry["primitives"] = r.draw.primitives();
                     entry["path"] = drawnByName(r.draw.drawnBy);
                     entry["single_crease_patches"] = r.stats.singleCreasePatches;
                     entry["triangles"] = r.draw.triangles;
                     entry["frame_ms"] = r.frameMs;
                     entry["draw_ms"] = r.drawMs;
                     entry["setup_ms"] = r.setupMs;
                     entry["control_points"] = r.stats.controlPoints;
                     entry["samples"] = r.error.samples;
                     entry["approximations"] = r.approximations;
                     drawn.append(entry);
                 }
                 py::dict out;
                 out["tess"] = tess;
                 out["samples_per_edge"] = samples;
                 out["plan_depth"] = depth;
                 out["schemes"] = drawn;
                 out["skipped"] = skipped;
                 return out;
             },
             py::arg("schemes") = py::none(), py::arg("tess") = 8, py::arg("samples") = 16, py::arg("depth") = 6,
             py::arg("repeats") = 5, py::arg("size") = py::make_tuple(360, 300), py::arg("camera") = py::none(),
             py::arg("options") = py::none(), py::arg("renderer") = py::none(),
             R"doc(`quadplan compare`'s numbers for each scheme (default: every loaded one), computed the same way
and laid out like its --json output: {"tess", "samples_per_edge", "plan_depth", "schemes": [{"name",
"max_rel_error", "rms_rel_error", "max_normal_deg", "patches", "triangles", "frame_ms", "draw_ms",
"setup_ms", "control_points", "samples", "approximations"}], "skipped": [{"name", "reason"}]}.
Errors are relative to the bounding-box diagonal against the exact surface at plan depth `depth`
on `samples` segments per sub-face edge; times are medians of `repeats` frames (update + draw at
`size`) after one warm-up. options: {"uniform": {"level": 4}, ...}.)doc");

    m.def("write_png",
          [](const std::string& path, const py::object& image) {
              uint32_t width = 0, height = 0;
              const std::vector<uint8_t> rgba = rgbaFrom(image, width, height);
              check(writePng(path, width, height, rgba));
          },
          py::arg("path"), py::arg("image"), "Writes an (h, w, 4) or (h, w, 3) uint8 array as PNG, atomically.");
    m.def("read_png",
          [](const std::string& path) {
              int width = 0, height = 0, channels = 0;
              stbi_uc* pixels = stbi_load(path.c_str(), &width, &height, &channels, 4);
              if (!pixels) throw ScriptError("cannot read PNG " + path + ": " + stbi_failure_reason());
              py::array_t<uint8_t> out({py::ssize_t(height), py::ssize_t(width), py::ssize_t(4)});
              std::copy(pixels, pixels + size_t(width) * height * 4, out.mutable_data());
              stbi_image_free(pixels);
              return out;
          },
          py::arg("path"), "Reads a PNG as an (h, w, 4) uint8 array.");
    m.def("set_default_plugin_dir", &setDefaultPluginDirectory, py::arg("directory"),
          "Where renderers look for scheme plugins when neither plugin_dir nor $QUADPLAN_PLUGIN_DIR says (set at import).");
}

}  // namespace qp::py
