// `quadplan sculpt SCENE_OR_CAGE --out OUT.json ...`: applies brush strokes headless, so tests
// and scripts reproduce them, and writes the scene with its displacement (cage inline).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "camera.h"
#include "commands.h"
#include "displacement/brush.h"
#include "displacement/displaced_mesh.h"
#include "displacement/displacement_io.h"
#include "displacement/sculpt_samples.h"
#include "displacement/sculpt_script.h"
#include "mesh/file_io.h"
#include "mesh_pass.h"
#include "offscreen_target.h"
#include "plan_db_option.h"
#include "plans/planned_cage.h"
#include "render_setup.h"
#include "scene/scene.h"
#include "vk_commands.h"
#include "vk_context.h"

namespace qp::cli {

namespace {

struct SculptArgs {
    std::string input, out, strokesFile, path, planDb;
    std::string object;  // empty: the first object with a cage of its own
    std::string brush = "raise", falloff = "smooth", mirror = "none";
    float radius = 0.0f, strength = 0.0f, spacing = 0.0f;
    uint32_t resolution = 0;  // 0: keep the scene's (8 when it has none)
    std::string png;          // also render the displaced mesh here
    bool validate = false;
    bool invertMask = false, clearMask = false;  // steps on the whole mask before any stroke
};

// A preview until the renderer displaces its own surfaces: the CPU displaced mesh
// (displaced_mesh.h, at the factor that shows every sample) through MeshPass, lavapipe.
Status renderPreview(const PlannedCage& planned, const Displacement& displacement, const std::string& path, bool validate) {
    const uint32_t factor = std::min(requiredMeshFactor(planned, displacement.layout), 2 * kMaxDisplacementResolution);
    Result<DisplacedMesh> mesh = buildDisplacedMesh(planned, displacement, factor);
    if (!mesh) return mesh.error();
    std::vector<MeshVertex> vertices(mesh->positions.size());
    for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = {mesh->positions[i], mesh->normals[i]};
    // Framed on the cage, so previews of one scene with different strokes line up.
    const Bounds bounds = computeBounds(planned.cage());
    const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
    constexpr uint32_t kSize = 768;
    ContextOptions options;
    options.validation = validate;
    if (const char* device = std::getenv("QUADPLAN_VK_DEVICE")) options.forceDevice = device;
    Result<VulkanContext> context = createContext(options);
    if (!context) return Error{"cannot start Vulkan: " + context.error().message};
    VulkanContext& ctx = *context;
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, kSize, kSize, format);
    Result<MeshPass> pass = target ? createMeshPass(ctx, VK_NULL_HANDLE, format) : Result<MeshPass>(target.error());
    Result<GpuMesh> gpu = pass ? uploadMesh(ctx, vertices, mesh->indices) : Result<GpuMesh>(pass.error());
    Status status = gpu ? success() : Status(gpu.error());
    if (status) {
        MeshView view;
        view.viewProjection = viewProjection(camera);
        view.eye = camera.eye;
        view.background = glm::vec3(0.02f, 0.025f, 0.03f);
        const MeshDraw draw{&*gpu, glm::vec3(0.75f, 0.72f, 0.68f)};
        status = submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordMeshPass(cmd, *pass, renderTarget(*target), view, {&draw, 1}); });
        Result<std::vector<uint8_t>> pixels = status ? readPixels(ctx, *target) : Result<std::vector<uint8_t>>(status.error());
        status = pixels ? writePng(path, kSize, kSize, *pixels) : Status(pixels.error());
    }
    if (gpu) destroyMesh(ctx, *gpu);
    if (pass) destroyMeshPass(ctx, *pass);
    if (target) destroyOffscreenTarget(ctx, *target);
    destroyContext(ctx);
    if (status && validate && validationMessageCount(ctx) > 0) {
        for (const std::string& m : validationMessages(ctx)) std::fprintf(stderr, "validation: %s\n", m.c_str());
        return Error{"Vulkan validation reported problems"};
    }
    if (status)
        std::fprintf(stderr, "wrote %s (%ux%u, displaced mesh at factor %u, %zu triangles)\n", path.c_str(), kSize, kSize,
                     factor, mesh->indices.size() / 3);
    return status;
}

constexpr uint32_t kDefaultResolution = 8;

Result<std::vector<ScriptedStroke>> strokesFromArgs(const SculptArgs& args) {
    if (!args.strokesFile.empty()) {
        if (!args.path.empty()) return Error{"give either --path or --strokes, not both"};
        Result<std::string> text = readFile(args.strokesFile);
        if (!text) return text.error();
        return parseStrokeFile(*text, args.strokesFile);
    }
    std::vector<ScriptedStroke> steps;
    if (args.invertMask) steps.push_back({{}, {}, WholeMaskStep::Invert});
    if (args.clearMask) steps.push_back({{}, {}, WholeMaskStep::Clear});
    if (args.path.empty()) {
        if (!steps.empty()) return steps;
        return Error{"nothing to sculpt: give --path \"x,y,z;...\" (with --radius and --strength), --strokes FILE.json, "
                     "--invert-mask or --clear-mask"};
    }
    ScriptedStroke stroke;
    Brush& brush = stroke.options.brush;
    auto kind = brushKindFromName(args.brush);
    if (!kind) return Error{"--brush: unknown brush \"" + args.brush + "\"; expected raise, lower, smooth, flatten, erase, inflate, crease, mask or unmask"};
    auto falloff = falloffFromName(args.falloff);
    if (!falloff) return Error{"--falloff: unknown falloff \"" + args.falloff + "\"; expected smooth, linear, constant or sphere"};
    auto mirror = mirrorAxisFromName(args.mirror);
    if (!mirror) return Error{"--mirror: unknown axis \"" + args.mirror + "\"; expected none, x, y or z"};
    brush = {*kind, args.radius, args.strength, *falloff};
    if (Status valid = validateBrush(brush); !valid) return Error{valid.error().message + " (--radius, --strength)"};
    if (args.spacing < 0.0f) return Error{"--spacing must be >= 0 (0: a quarter of the radius)"};
    stroke.options.mirror = *mirror;
    stroke.options.spacing = args.spacing;
    Result<std::vector<glm::vec3>> path = parsePath(args.path);
    if (!path) return Error{"--path: " + path.error().message};
    stroke.path = std::move(path).value();
    if (Status fits = checkStrokeLength(stroke); !fits) return Error{"--path: " + fits.error().message};
    steps.push_back(std::move(stroke));
    return steps;
}

// The object --object names (it must have a cage of its own), or the first that has one.
Result<uint32_t> sculptedObject(const Scene& scene, const std::string& name) {
    if (name.empty()) {
        for (uint32_t i = 0; i < scene.objects.size(); ++i)
            if (!scene.objects[i].isInstance()) return i;
        return Error{"the scene has no object with a cage of its own"};
    }
    const uint32_t i = findObject(scene.objects, name);
    if (i == UINT32_MAX) {
        std::string names;
        for (const SceneObject& o : scene.objects) names += (names.empty() ? "" : ", ") + o.name;
        return Error{"--object: no object is called \"" + name + "\" (the scene has " + names + ")"};
    }
    if (scene.objects[i].isInstance())
        return Error{"--object: \"" + name + "\" is an instance of \"" + scene.objects[i].instanceOf +
                     "\" and draws its displacement: sculpt \"" + scene.objects[i].instanceOf + "\" instead"};
    return i;
}

int runSculpt(const SculptArgs& args) {
    auto failWith = [](const std::string& message) {
        std::fprintf(stderr, "error: %s\n", message.c_str());
        return 1;
    };
    Result<std::vector<ScriptedStroke>> strokes = strokesFromArgs(args);
    if (!strokes) return failWith(strokes.error().message);
    if (args.resolution && (!isPowerOfTwo(args.resolution) || args.resolution > kMaxDisplacementResolution))
        return failWith("--resolution must be a power of two between 1 and " + std::to_string(kMaxDisplacementResolution) +
                        ", got " + std::to_string(args.resolution));

    Result<Scene> scene = loadSceneWarning(args.input);
    if (!scene) return failWith(scene.error().message);

    Result<uint32_t> index = sculptedObject(*scene, args.object);
    if (!index) return failWith(args.input + ": " + index.error().message);
    SceneObject& object = scene->objects[*index];

    PlanDatabase database;
    loadPlanDatabase(database, args.planDb);
    Result<PlannedCage> planned = PlannedCage::create(object.cage, database, PlanOptions{}, args.input);
    if (!planned) return failWith(planned.error().message);
    savePlanDatabase(database, args.planDb);

    Displacement& displacement = object.displacement;
    if (displacement.empty())
        displacement = makeDisplacement(object.cage, planned->topology(), args.resolution ? args.resolution : kDefaultResolution);
    else if (args.resolution)
        displacement = resampleDisplacement(displacement, args.resolution);

    SculptSamples samples = SculptSamples::build(*planned, displacement.layout);
    Sculptor sculptor(displacement, samples);
    uint32_t dabs = 0;
    std::vector<uint32_t> changed;
    for (const ScriptedStroke& stroke : *strokes) {
        if (stroke.wholeMask != WholeMaskStep::None) {
            Result<StrokeRecord> record =
                stroke.wholeMask == WholeMaskStep::Invert ? invertMask(displacement) : clearMask(displacement);
            if (!record) return failWith(record.error().message);
            continue;
        }
        sculptor.beginStroke();
        sculptor.dabsAlong(stroke.options, stroke.path);
        StrokeRecord record = sculptor.endStroke();
        dabs += record.dabs;
        for (const SampleChange& c : record.changes) changed.push_back(c.sample);
    }
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());

    for (SceneObject& o : scene->objects) o.cagePath.clear();  // written inline: one self-contained file
    if (Status saved = saveScene(*scene, args.out, CageStorage::Inline); !saved) return failWith(saved.error().message);
    auto [lo, hi] = std::minmax_element(displacement.samples.begin(), displacement.samples.end());
    const size_t maskSteps = size_t(std::count_if(strokes->begin(), strokes->end(),
                                                   [](const ScriptedStroke& s) { return s.wholeMask != WholeMaskStep::None; }));
    const size_t brushStrokes = strokes->size() - maskSteps;
    const size_t masked = size_t(std::count_if(displacement.mask.begin(), displacement.mask.end(), [](float m) { return m > 0.0f; }));
    const std::string steps = maskSteps ? " and " + std::to_string(maskSteps) + (maskSteps == 1 ? " mask step" : " mask steps") : "";
    std::fprintf(stderr, "sculpt: %zu stroke%s%s, %u dabs, %zu of %zu samples changed, %zu masked; displacement in [%g, %g]; wrote %s\n",
                 brushStrokes, brushStrokes == 1 ? "" : "s", steps.c_str(), dabs, changed.size(), displacement.samples.size(),
                 masked, double(*lo), double(*hi), args.out.c_str());
    if (!args.png.empty())
        if (Status rendered = renderPreview(*planned, displacement, args.png, args.validate); !rendered)
            return failWith("preview not rendered: " + rendered.error().message);
    return 0;
}

}  // namespace

void registerSculpt(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand(
        "sculpt", "Apply displacement brush strokes headless and write the scene (cage inline) with its displacement");
    auto args = std::make_shared<SculptArgs>();
    cmd->add_option("input", args->input, "Scene (.json) or cage (.obj, .om, .ply, .off, .stl)")->required();
    cmd->add_option("--out", args->out, "Scene file to write (.json)")->required();
    cmd->add_option("--object", args->object,
                    "The object to sculpt (default: the first with a cage of its own); stroke points are in its "
                    "cage's coordinates");
    cmd->add_option("--path", args->path, "Stroke path in world space: \"x,y,z;x,y,z;...\"");
    cmd->add_option("--strokes", args->strokesFile,
                    "JSON stroke list instead of --path: {\"strokes\": [{\"brush\", \"radius\", \"strength\", "
                    "\"falloff\", \"mirror\", \"spacing\", \"path\": [[x,y,z],...]}]} (core/displacement/sculpt_script.h)");
    cmd->add_option("--brush", args->brush,
                    "raise, lower, smooth, flatten, erase, inflate, crease, mask or unmask (default raise)");
    cmd->add_flag("--invert-mask", args->invertMask, "Invert the sculpting mask first (with no mask yet: mask everything)");
    cmd->add_flag("--clear-mask", args->clearMask, "Clear the sculpting mask first (after --invert-mask)");
    cmd->add_option("--radius", args->radius, "Brush radius in world units");
    cmd->add_option("--strength", args->strength,
                    "raise/lower: height per dab in radii; smooth/flatten/erase: blend per dab in [0, 1]");
    cmd->add_option("--falloff", args->falloff, "smooth, linear, constant or sphere (default smooth)");
    cmd->add_option("--mirror", args->mirror, "Mirror across the x, y or z plane through the model centre (default none)");
    cmd->add_option("--spacing", args->spacing, "Distance between dabs along the path (default: a quarter of the radius)");
    cmd->add_option("--resolution", args->resolution,
                    "Resample the displacement to this power-of-two resolution first: cells along a quad side (default: keep; 8 for a new displacement)");
    cmd->add_option("--png", args->png, "Also render the displaced surface to this PNG (CPU mesh, lit, 768x768)");
    cmd->add_flag("--validate", args->validate, "With --png: Vulkan validation layers on; any message fails");
    addPlanDatabaseOption(cmd, args->planDb);
    cmd->callback([args, &exitCode] { exitCode = runSculpt(*args); });
}

}  // namespace qp::cli
