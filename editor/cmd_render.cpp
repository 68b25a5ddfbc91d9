// `quadplan render`: draws a cage or scene through a scheme plugin (plans by default) into a
// PNG, headless.
#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "cull_report.h"
#include "headless_scene.h"
#include "plan_pass.h"
#include "render_setup.h"
#include "scene/planned_scene.h"
#include "scene_schemes.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

struct RenderArgs {
    std::string path, out;
    DrawOptions draw;  // --scheme, --size, --tess, ... (addDrawOptions)
    bool json = false;
    std::string cull = "none";
};

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

int runRender(const RenderArgs& args) {
    uint32_t width = 0, height = 0;
    if (!parseSize(args.draw.size, width, height))
        return fail("--size must be WIDTHxHEIGHT with each side between 16 and 8192, got '" + args.draw.size + "'");
    if (args.draw.tess > 0 && args.draw.adaptive > 0.0f) return fail("give either --tess or --adaptive, not both");

    Result<DrawInput> input = loadDrawInput(args.path, args.draw);
    if (!input) return fail(input.error().message);
    SchemeSettings settings = input->scheme.settings;
    const PluginCatalog& catalog = input->scheme.catalog;
    Scene& scene = input->file.scene;
    PlannedScene& planned = input->file.planned;

    setTessellation(settings, args.draw.tess, args.draw.adaptive, scene.tessellation);
    const bool showCage = !args.draw.noCage && scene.tessellation.showCage;


    const float aspect = float(width) / float(height);
    Result<RenderCamera> camera = chooseCamera(scene, sceneBounds(scene), aspect, args.draw.camera);
    if (!camera) return fail(camera.error().message);

    HeadlessSceneRequest request{&catalog, args.draw.scheme, settings, args.path, width, height, args.draw.colorBy, args.draw.validate};
    Result<std::unique_ptr<HeadlessScene>> created = createHeadlessScene(request, scene, planned);
    if (!created) return fail(created.error().message);
    HeadlessScene& h = **created;
    int status = h.problem.empty() ? 0 : fail(h.problem);
    if (status == 0) {
        DrawView view = headlessView(*camera, height, args.draw.colorBy, args.draw.wire || scene.tessellation.showWireframe);
        view.cull = *parseCullMethod(args.cull);
        const RenderTarget target = renderTarget(*h.target);
        Result<DrawStats> drawStats = DrawStats{};
        Status drawn = submitAndWait(h.ctx, [&](VkCommandBuffer cmd) {
            drawStats = recordScene(cmd, *h.schemes, scene, planned, target, view);
            if (showCage) recordSceneCageLines(cmd, *h.lines, target, *h.cageLines, scene, planned, view);
        });
        if (drawn && !drawStats) drawn = drawStats.error();
        Result<std::vector<uint8_t>> pixels = drawn ? readPixels(h.ctx, *h.target) : Result<std::vector<uint8_t>>(drawn.error());
        Status written = pixels ? writePng(args.out, width, height, *pixels) : Status(pixels.error());
        if (!written)
            status = fail("rendering " + args.path + " failed: " + written.error().message);
        else if (args.json) {
            const nlohmann::json out = {
                {"out", args.out}, {"width", width}, {"height", height}, {"scheme", args.draw.scheme},
                {"device", h.ctx.deviceName}, {"objects", scene.objects.size()}, {"cages", planned.cages.size()},
                {"path", drawnByName(drawStats->drawnBy)}, {"patches", drawStats->patches},
                // 0 from the scheme means the tessellator chose the count at draw time: unknown.
                {"triangles", drawStats->triangles > 0 ? nlohmann::json(drawStats->triangles) : nlohmann::json(nullptr)},
                {"sample_culled", drawStats->sampleCulledTriangles},
                {"facing_away", drawStats->facingAwayTriangles},
                {"cull", cullJson(view.cull, *drawStats)}};
            std::printf("%s\n", out.dump(1).c_str());
        } else {
            std::string triangles = drawStats->triangles > 0 ? std::to_string(drawStats->triangles) + " triangles"
                                                             : "triangle count set by the tessellator at draw time";
            if (drawStats->sampleCulledTriangles)
                triangles += ", " + std::to_string(drawStats->sampleCulledTriangles) + " of them covering no pixel centre left out";
            if (drawStats->facingAwayTriangles)
                triangles += ", " + std::to_string(drawStats->facingAwayTriangles) + " facing away behind the front left out";
            const std::string objects = scene.objects.size() == 1 ? ""
                                        : std::to_string(scene.objects.size()) + " objects, " +
                                              std::to_string(planned.cages.size()) + " cages, ";
            std::fprintf(stderr, "wrote %s (%ux%u, scheme %s on %s, %s%llu patches, %s)\n", args.out.c_str(), width,
                         height, args.draw.scheme.c_str(), h.ctx.deviceName.c_str(), objects.c_str(),
                         (unsigned long long)drawStats->patches, triangles.c_str());
            if (view.cull != CullMethod::None)
                std::fprintf(stderr, "culled (%s): %llu of %llu patches outside the frustum, %llu facing away, %llu tested by "
                                     "the frustum only; %.2f ms on the CPU\n",
                             cullMethodName(view.cull), (unsigned long long)drawStats->cull.frustum,
                             (unsigned long long)drawStats->cull.tested, (unsigned long long)drawStats->cull.backFacing,
                             (unsigned long long)drawStats->cull.frustumOnly, drawStats->cullMilliseconds);
        }
    }
    return destroyHeadlessScene(h, args.draw.validate, status);
}

}  // namespace

void registerRender(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("render", "Render a cage or scene to a PNG (headless, Vulkan) through a scheme plugin");
    auto args = std::make_shared<RenderArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json)")->required();
    cmd->add_option("--out", args->out, "PNG file to write")->required();
    addDrawOptions(*cmd, args->draw, "EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES] (default: the scene's, or framed)",
                   "plans: auto (default: cpu on a CPU device, tess on a GPU), tess (tessellator), grid (compute-shader "
                   "grid) or cpu (grid from the multithreaded CPU evaluator); osd-fas: auto, tess or cpu; acc1, acc2, pn: "
                   "tess (default) or cpu; the option path=...");
    cmd->add_option("--cull", args->cull, "Skip patches that cannot show a pixel (docs/culling.md): none (default), frustum, "
                                          "or a back-patch test with it: tcone, ncone, pplane")
        ->check(CLI::IsMember({"none", "frustum", "tcone", "ncone", "pplane"}));
    cmd->add_flag("--json", args->json, "Print what was drawn as one JSON object on stdout (patches, triangles, culling) "
                                         "instead of the summary on stderr");
    cmd->callback([args, &exitCode] { exitCode = runRender(*args); });
}

}  // namespace qp::cli
