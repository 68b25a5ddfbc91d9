// `quadplan export`: the limit surface of a cage or scene as one welded, watertight triangle mesh
// per cage (export/limit_mesh.h), its order optimised for GPUs (export/mesh_order.h), written as
// glTF (a node per object, instances sharing their mesh), OBJ, PLY, OFF or STL (objects merged,
// or one file each with --split; export/mesh_files.h). The plans export on the CPU without a
// Vulkan device; another scheme is built on the headless device and evaluated at the same slots.
//
// Exit status: 0 written; 1 bad input or a failure (nothing written).
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "mesh_files.h"
#include "mesh_order.h"
#include "pipeline_cache.h"
#include "planned_scene.h"
#include "render_setup.h"
#include "scheme_host.h"
#include "scheme_support.h"

namespace qp::cli {

namespace {

struct ExportArgs {
    std::string path, out, scheme = "plans", pluginDir;
    uint32_t tess = 8, depth = 6;
    bool displaced = false, split = false, noOptimize = false, json = false, validate = false;
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
    Result<LimitMesh> mesh(const std::string& scheme, const PlannedCage& planned, uint32_t factor, uint32_t depth,
                           const std::string& source) {
        SchemeSettings settings;
        settings.tessFactor = factor;
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
            planned, factor, [&](std::span<const SampleRequest> requests, std::span<glm::vec3> positions, std::span<glm::vec3> normals) {
                std::vector<SurfacePoint> points(requests.size());
                evaluated = instance.evaluate(requests, points);
                for (size_t i = 0; i < points.size(); ++i) positions[i] = points[i].position, normals[i] = points[i].normal;
            });
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

std::string splitPath(const std::string& out, const std::string& object) {
    const std::filesystem::path path(out);
    return (path.parent_path() / (path.stem().string() + "_" + object + path.extension().string())).string();
}

int runExport(const ExportArgs& args) {
    const auto start = std::chrono::steady_clock::now();
    Result<MeshFormat> format = meshFormatOf(args.out);
    if (!format) return fail(format.error().message);
    if (args.displaced && args.scheme != "plans")
        return fail("--displaced exports the plans' displaced surface; give --scheme plans (or leave it out)");
    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(args.path, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!scene) return fail(scene.error().message);
    PlanDatabase database;
    Result<PlannedScene> planned = PlannedScene::create(*scene, database, PlanOptions{args.depth, true}, args.path);
    if (!planned) return fail(planned.error().message);

    std::optional<SchemeSlots> slots;
    if (args.scheme != "plans") {
        slots.emplace();
        if (Status opened = slots->open(args.pluginDir, args.validate); !opened) return fail(opened.error().message);
    }
    ExportScene exported;
    OrderReport order;
    MeshClosure closure;
    for (uint32_t c = 0; c < planned->cages.size(); ++c) {
        const SceneObject& owner = scene->objects[planned->objectOfCage[c]];
        const std::string source = planned->cages.size() == 1 ? args.path : args.path + ": object \"" + owner.name + "\"";
        if (args.displaced && owner.displacement.empty())
            std::fprintf(stderr, "note: %s has no sculpted displacement; exported without\n", source.c_str());
        const Displacement* displacement = args.displaced && !owner.displacement.empty() ? &owner.displacement : nullptr;
        Result<LimitMesh> mesh = slots ? slots->mesh(args.scheme, planned->cages[c], args.tess, args.depth, source)
                                       : exactLimitMesh(planned->cages[c], args.tess, displacement);
        if (!mesh) return fail(source + ": " + mesh.error().message);
        const MeshClosure cageClosure = meshClosure(mesh->indices);
        closure.borderEdges += cageClosure.borderEdges;
        closure.nonManifoldEdges += cageClosure.nonManifoldEdges;
        if (!args.noOptimize) {
            const OrderReport r = optimizeMeshOrder(*mesh);
            const float weight = float(mesh->triangleCount());
            order.acmrBefore += r.acmrBefore * weight, order.acmrAfter += r.acmrAfter * weight;
        }
        exported.meshes.push_back(std::move(mesh).value());
        exported.meshNames.push_back(owner.name);
    }
    uint64_t triangles = 0, vertices = 0, meshTriangles = 0;
    for (const LimitMesh& m : exported.meshes) meshTriangles += m.triangleCount();
    if (!args.noOptimize && meshTriangles > 0) order.acmrBefore /= float(meshTriangles), order.acmrAfter /= float(meshTriangles);
    for (uint32_t i = 0; i < scene->objects.size(); ++i)
        if (scene->objects[i].visible)
            exported.objects.push_back({scene->objects[i].name, scene->objects[i].transform, planned->cageOfObject[i]});

    std::vector<std::string> files;
    auto write = [&](const ExportScene& part, const std::string& path) -> Status {
        if (Status written = writeMeshFile(part, path, *format); !written) return written;
        files.push_back(path);
        if (hasNodes(*format)) {
            for (const LimitMesh& m : part.meshes) vertices += m.vertexCount(), triangles += m.triangleCount();
        } else {
            for (const ExportObject& o : part.objects)
                vertices += part.meshes[o.mesh].vertexCount(), triangles += part.meshes[o.mesh].triangleCount();
        }
        return success();
    };
    if (args.split && exported.objects.size() > 1) {
        for (const ExportObject& object : exported.objects) {
            ExportScene one{exported.meshes, exported.meshNames, {object}};
            if (Status s = write(one, splitPath(args.out, object.name)); !s) return fail(s.error().message);
        }
    } else if (Status s = write(exported, args.out); !s) {
        return fail(s.error().message);
    }
    if (slots && args.validate && slots->validationFailed()) return 4;
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (args.json) {
        nlohmann::json out = {{"file", files.size() == 1 ? nlohmann::json(files[0]) : nlohmann::json(files)},
                              {"format", meshFormatName(*format)},
                              {"scheme", args.scheme},
                              {"factor", args.tess},
                              {"displaced", args.displaced},
                              {"objects", exported.objects.size()},
                              {"meshes", exported.meshes.size()},
                              {"vertices", vertices},
                              {"triangles", triangles},
                              {"watertight", closure.watertight()},
                              {"border_edges", closure.borderEdges},
                              {"non_manifold_edges", closure.nonManifoldEdges},
                              {"acmr_before", args.noOptimize ? nlohmann::json(nullptr) : nlohmann::json(order.acmrBefore)},
                              {"acmr_after", args.noOptimize ? nlohmann::json(nullptr) : nlohmann::json(order.acmrAfter)},
                              {"ms", ms}};
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("wrote %s: %llu vertices, %llu triangles (%s, factor %u%s), %s", files.size() == 1 ? files[0].c_str() : "files",
                    (unsigned long long)vertices, (unsigned long long)triangles, args.scheme.c_str(), args.tess,
                    args.displaced ? ", displaced" : "",
                    closure.watertight() ? "watertight"
                                         : (std::to_string(closure.borderEdges) + " border and " +
                                            std::to_string(closure.nonManifoldEdges) + " non-manifold edges")
                                               .c_str());
        if (!args.noOptimize) std::printf(", ACMR %.3f -> %.3f", order.acmrBefore, order.acmrAfter);
        std::printf(", %.0f ms\n", ms);
        for (size_t i = 1; i < files.size(); ++i) std::printf("wrote %s\n", files[i].c_str());
    }
    return 0;
}

}  // namespace

void registerExport(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("export", "Export the limit surface as a welded, watertight triangle mesh (glTF, OBJ, PLY, OFF, STL)");
    auto args = std::make_shared<ExportArgs>();
    cmd->add_option("file", args->path, "Cage (.obj) or scene (.json)")->required();
    cmd->add_option("--out", args->out, "File to write: .glb (default glTF), .gltf, .obj, .ply, .off or .stl")->required();
    cmd->add_option("--scheme", args->scheme, "Surface to export (default plans, the exact limit surface; `quadplan schemes` lists them)");
    cmd->add_option("--tess", args->tess, "Uniform tessellation factor: segments per sub-face edge (default 8)")
        ->check(CLI::Range(1u, 64u));
    cmd->add_flag("--displaced", args->displaced, "Apply the scene's sculpted displacement (plans)");
    cmd->add_flag("--split", args->split, "One file per object (NAME_OBJECT.EXT) instead of one for the scene");
    cmd->add_flag("--no-optimize", args->noOptimize, "Keep the grid's own triangle order (no meshoptimizer pass)");
    cmd->add_flag("--json", args->json, "Print what was written as JSON");
    cmd->add_option("--plugin-dir", args->pluginDir, "Where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else <bin>/../plugins)");
    cmd->add_option("--depth", args->depth, "Plan depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--validate", args->validate, "Enable Vulkan validation (other schemes than plans); any message fails the command");
    cmd->callback([args, &exitCode] { exitCode = runExport(*args); });
}

}  // namespace qp::cli
