// `quadplan export`: the limit surface of a cage or scene as one welded, watertight triangle mesh
// per cage (export/limit_mesh.h), its order optimised for GPUs (export/mesh_order.h), written as
// glTF (a node per object, instances sharing their mesh), OBJ, PLY, OFF or STL (objects merged,
// or one file each with --split; export/mesh_files.h). The plans export on the CPU without a
// Vulkan device; another scheme is built on the headless device and evaluated at the same slots.
//
// Exit status: 0 written; 1 bad input or a failure (nothing written).
#include <chrono>
#include <cstdio>

#include <glm/glm.hpp>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "mesh/mesh_cage_write.h"
#include "render_setup.h"
#include "scene/planned_scene.h"
#include "scene_export.h"
#include "scheme_host.h"

namespace qp::cli {

namespace {

struct ExportArgs {
    std::string path, out, scheme = "plans", pluginDir, uv = "none", size = "800x600", camera;
    uint32_t tess = 8, depth = 6;
    float adaptive = 0.0f;  // pixels per segment; 0: uniform --tess
    bool displaced = false, split = false, noOptimize = false, json = false, validate = false, cage = false;
};

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

// Another scheme's surface at the grid's slots: the scheme built on a headless device, its CPU
// evaluator asked for every owned slot.
class SchemeSlots {
public:
    Status open(const std::string& pluginDir, bool validate) {
        catalog_ = loadPlugins(pluginDirectory(pluginDir));
        for (const PluginProblem& p : catalog_.problems) std::fprintf(stderr, "warning: %s\n", p.message.c_str());
        Result<VulkanContext> context = createHeadlessContext(validate);
        if (!context) return context.error();
        context_ = std::move(context).value();
        return success();
    }
    Result<LimitMesh> mesh(const std::string& scheme, const PlannedCage& planned, const MeshDensity& density, uint32_t depth,
                           UvMode uv, const std::string& source) {
        SchemeSettings settings;
        settings.tessFactor = density.adaptive ? 64 : density.factor;
        settings.planDepth = depth;
        const GpuContext gpu{&*context_, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
        Result<PreparedScheme> prepared =
            prepareScheme(catalog_, scheme, planned, analyzeCage(planned.cage(), planned.topology()), settings, gpu, source);
        if (!prepared) return prepared.error();
        for (const std::string& a : prepared->support.approximations)
            std::fprintf(stderr, "note: %s: %s\n", scheme.c_str(), a.c_str());
        SchemeInstance& instance = prepared->instance;
        Status evaluated = success();
        Result<LimitMesh> mesh = evaluatedLimitMesh(
            planned, density, [&](std::span<const SampleRequest> requests, std::span<glm::vec3> positions, std::span<glm::vec3> normals) {
                std::vector<SurfacePoint> points(requests.size());
                evaluated = instance.evaluate(requests, points);
                for (size_t i = 0; i < points.size(); ++i) positions[i] = points[i].position, normals[i] = points[i].normal;
            },
            uv);
        (void)instance.destroyGpu();
        if (!evaluated) return evaluated.error();
        return mesh;
    }
    bool validationFailed() { return context_ && reportValidation(*context_); }
    ~SchemeSlots() {
        if (context_) destroyContext(*context_);
    }

private:
    PluginCatalog catalog_;
    std::optional<VulkanContext> context_;
};

// --cage: the visible objects' cages (their polygons, tags and UVs) in the world, merged or one
// file each.
int exportCages(const ExportArgs& args, const Scene& scene, const PlannedScene& planned) {
    auto placed = [&](uint32_t object) {
        const Cage& source = planned.cages[planned.cageOfObject[object]].cage();
        const glm::mat4 matrix = scene.objects[object].transform.matrix();
        const bool mirrored = glm::determinant(glm::mat3(matrix)) < 0.0f;
        Cage cage = source;  // tags, UVs and options as they are
        for (glm::vec3& p : cage.positions) p = glm::vec3(matrix * glm::vec4(p, 1.0f));
        if (mirrored) {  // keep the faces facing out: each face backwards from its first corner
            for (uint32_t f = 0; f < cage.faceCount(); ++f) {
                std::reverse(cage.faceVertices.begin() + cage.faceOffsets[f] + 1, cage.faceVertices.begin() + cage.faceOffsets[f + 1]);
                if (!cage.faceUVIndices.empty())
                    std::reverse(cage.faceUVIndices.begin() + cage.faceOffsets[f] + 1, cage.faceUVIndices.begin() + cage.faceOffsets[f + 1]);
            }
        }
        return cage;
    };
    std::vector<std::pair<std::string, Cage>> files;
    if (args.split || scene.objects.size() == 1) {
        for (uint32_t i = 0; i < scene.objects.size(); ++i)
            if (scene.objects[i].visible)
                files.push_back({scene.objects.size() == 1 ? args.out : splitExportPath(args.out, scene.objects[i].name), placed(i)});
    } else {
        Cage merged;
        bool first = true, uvs = true;
        for (uint32_t i = 0; i < scene.objects.size(); ++i)
            if (scene.objects[i].visible) uvs = uvs && !placed(i).uvs.empty();
        for (uint32_t i = 0; i < scene.objects.size(); ++i) {
            if (!scene.objects[i].visible) continue;
            const Cage part = placed(i);
            if (first) merged.options = part.options;
            else if (!(merged.options == part.options))
                std::fprintf(stderr, "warning: the objects' subdivision options differ: the merged cage takes the first's\n");
            first = false;
            const uint32_t base = merged.vertexCount(), faceBase = merged.faceCount(), uvBase = uint32_t(merged.uvs.size());
            merged.positions.insert(merged.positions.end(), part.positions.begin(), part.positions.end());
            for (uint32_t f = 0; f < part.faceCount(); ++f) {
                std::vector<uint32_t> face(part.faceBegin(f), part.faceBegin(f) + part.faceSize(f));
                for (uint32_t& v : face) v += base;
                merged.addFace(face.data(), uint32_t(face.size()));
            }
            for (EdgeCrease c : part.creases) merged.creases.push_back({c.v0 + base, c.v1 + base, c.sharpness});
            for (VertexCorner c : part.corners) merged.corners.push_back({c.vertex + base, c.sharpness});
            for (uint32_t h : part.holes) merged.holes.push_back(h + faceBase);
            if (uvs) {
                merged.uvs.insert(merged.uvs.end(), part.uvs.begin(), part.uvs.end());
                for (uint32_t index : part.faceUVIndices) merged.faceUVIndices.push_back(index + uvBase);
            }
        }
        files.push_back({args.out, std::move(merged)});
    }
    for (const auto& [path, cage] : files) {
        std::vector<std::string> lost;
        if (Status saved = saveMeshCage(cage, path, &lost); !saved) return fail(saved.error().message);
        for (const std::string& l : lost) std::fprintf(stderr, "warning: %s\n", l.c_str());
        std::printf("wrote %s: the cage, %u vertices, %u faces\n", path.c_str(), cage.vertexCount(), cage.faceCount());
    }
    return 0;
}

int runExport(const ExportArgs& args) {
    const auto start = std::chrono::steady_clock::now();
    if (!args.cage) {
        if (Result<MeshFormat> format = meshFormatOf(args.out); !format) return fail(format.error().message);
        if (args.displaced && args.scheme != "plans")
            return fail("--displaced exports the plans' displaced surface; give --scheme plans (or leave it out)");
    }
    PlanDatabase database;
    Result<PlannedFile> file = loadAndPlan(args.path, database, PlanOptions{args.depth, true});
    if (!file) return fail(file.error().message);
    const Scene& scene = file->scene;
    const PlannedScene& planned = file->planned;
    if (args.cage) return exportCages(args, scene, planned);

    ExportOptions options;
    options.factor = args.tess;
    options.displaced = args.displaced;
    options.optimize = !args.noOptimize;
    options.split = args.split;
    options.uv = *parseUvMode(args.uv);
    if (args.adaptive > 0.0f) {
        uint32_t width = 0, height = 0;
        if (!parseSize(args.size, width, height))
            return fail("--size must be WIDTHxHEIGHT with each side between 16 and 8192, got '" + args.size + "'");
        Result<RenderCamera> camera = chooseCamera(scene, sceneBounds(scene), float(width) / float(height), args.camera);
        if (!camera) return fail(camera.error().message);
        options.adaptive = adaptiveExport(*camera, height, args.adaptive);
    }
    std::optional<SchemeSlots> slots;
    CageMesher mesher;
    const SceneCages cages = sceneCages(planned);
    if (args.scheme != "plans") {
        slots.emplace();
        if (Status opened = slots->open(args.pluginDir, args.validate); !opened) return fail(opened.error().message);
        mesher = [&](const PlannedCage& cage, uint32_t c, const std::string& source) {
            return slots->mesh(args.scheme, cage, exportDensity(scene, cages, c, options), args.depth, options.uv, source);
        };
    }
    Result<ExportReport> report = exportScene(scene, cages, args.out, options, args.path, mesher);
    if (!report) return fail(report.error().message);
    for (const std::string& note : report->notes) std::fprintf(stderr, "note: %s\n", note.c_str());
    if (slots && args.validate && slots->validationFailed()) return 4;
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const ExportReport& r = *report;
    if (args.json) {
        nlohmann::json out = {{"file", r.files.size() == 1 ? nlohmann::json(r.files[0]) : nlohmann::json(r.files)},
                              {"format", meshFormatName(*meshFormatOf(args.out))},
                              {"scheme", args.scheme},
                              {"factor", args.adaptive > 0.0f ? nlohmann::json(nullptr) : nlohmann::json(args.tess)},
                              {"adaptive_pixels", args.adaptive > 0.0f ? nlohmann::json(args.adaptive) : nlohmann::json(nullptr)},
                              {"displaced", args.displaced},
                              {"uv", args.uv},
                              {"objects", r.objects},
                              {"meshes", r.meshes},
                              {"vertices", r.vertices},
                              {"triangles", r.triangles},
                              {"watertight", r.closure.watertight()},
                              {"border_edges", r.closure.borderEdges},
                              {"non_manifold_edges", r.closure.nonManifoldEdges},
                              {"acmr_before", args.noOptimize ? nlohmann::json(nullptr) : nlohmann::json(r.order.acmrBefore)},
                              {"acmr_after", args.noOptimize ? nlohmann::json(nullptr) : nlohmann::json(r.order.acmrAfter)},
                              {"ms", ms}};
        std::printf("%s\n", out.dump(2).c_str());
        return 0;
    }
    const std::string closure = r.closure.watertight() ? "watertight"
                                                       : std::to_string(r.closure.borderEdges) + " border and " +
                                                             std::to_string(r.closure.nonManifoldEdges) + " non-manifold edges";
    char adaptive[64];
    std::snprintf(adaptive, sizeof adaptive, "adaptive, %g px per segment at %s", double(args.adaptive), args.size.c_str());
    const std::string density = args.adaptive > 0.0f ? adaptive : "factor " + std::to_string(args.tess);
    std::printf("wrote %s: %llu vertices, %llu triangles (%s, %s%s), %s", r.files.size() == 1 ? r.files[0].c_str() : "files",
                (unsigned long long)r.vertices, (unsigned long long)r.triangles, args.scheme.c_str(), density.c_str(),
                args.displaced ? ", displaced" : "", closure.c_str());
    if (!args.noOptimize) std::printf(", ACMR %.3f -> %.3f", r.order.acmrBefore, r.order.acmrAfter);
    std::printf(", %.0f ms\n", ms);
    for (size_t i = 1; i < r.files.size(); ++i) std::printf("wrote %s\n", r.files[i].c_str());
    return 0;
}

}  // namespace

void registerExport(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("export", "Export the limit surface as a welded, watertight triangle mesh (glTF, OBJ, PLY, OFF, STL)");
    auto args = std::make_shared<ExportArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json)")->required();
    cmd->add_option("--out", args->out, "File to write: .glb (default glTF), .gltf, .obj, .ply, .off or .stl; with --cage .obj, .om, .ply, .off or .stl")->required();
    cmd->add_option("--scheme", args->scheme, "Surface to export (default plans, the exact limit surface; `quadplan schemes` lists them)");
    auto* tess = cmd->add_option("--tess", args->tess, "Uniform tessellation factor: segments per sub-face edge (default 8)")
        ->check(CLI::Range(1u, 64u));
    cmd->add_option("--adaptive", args->adaptive,
                    "Screen-adaptive density instead of --tess: each edge cut into segments of about this many pixels, "
                    "as the grid path cuts it for the scene's camera (or --camera) at --size")
        ->check(CLI::Range(0.25f, 1024.0f))
        ->excludes(tess);
    cmd->add_option("--size", args->size, "Image size the --adaptive pixels refer to (default 800x600, as render)");
    cmd->add_option("--camera", args->camera, "--adaptive's camera: EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES] (default: the scene's, or framed)");
    cmd->add_flag("--displaced", args->displaced, "Apply the scene's sculpted displacement (plans)");
    cmd->add_flag("--cage", args->cage, "Write the cage itself (its polygons) instead of the limit surface: .obj or .om keep its tags, .ply, .off or .stl lose them (named)");
    cmd->add_flag("--split", args->split, "One file per object (NAME_OBJECT.EXT) instead of one for the scene");
    cmd->add_option("--uv", args->uv,
                    "none (default); linear: the cage's texture coordinates bilinear over each face; smooth: OpenSubdiv's "
                    "face-varying limit with the cage's face-varying rule")
        ->check(CLI::IsMember({"none", "linear", "smooth"}));
    cmd->add_flag("--no-optimize", args->noOptimize, "Keep the grid's own triangle order (no meshoptimizer pass)");
    cmd->add_flag("--json", args->json, "Print what was written as JSON");
    cmd->add_option("--plugin-dir", args->pluginDir, "Where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else <bin>/../plugins)");
    cmd->add_option("--depth", args->depth, "Plan depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--validate", args->validate, "Enable Vulkan validation (other schemes than plans); any message fails the command");
    cmd->callback([args, &exitCode] { exitCode = runExport(*args); });
}

}  // namespace qp::cli
