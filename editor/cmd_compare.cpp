// `quadplan compare`: the same cage and camera through several scheme plugins, side by side,
// each with its error against the exact limit surface (docs/schemes.md).
//
// The image: one column per requested scheme (four per row at most); each holds a label bar
// (name, max and RMS error, normal deviation), the scheme's own rendering, and below it the
// heat map of its error, with one colour legend for all at the bottom. The heat map is the
// scheme's surface as its CPU evaluator gives it on a uniform grid (--samples segments per
// sub-face edge), coloured by the error at each grid point; the numbers come from the same
// points. The exact surface is OpenSubdiv's Far adaptive patches at depth 10 in double by
// default (--reference, surface_error.h): its own error, ~2e-8 of the diagonal, is printed with
// the table and in the JSON.
//
// Exit status: 0 when every requested scheme was drawn; 2 when some were not (unknown,
// refused the cage, failed), the others drawn and reported; 1 when nothing could be (bad
// input, no Vulkan, no scheme drawn, the image not written); 4 when --validate saw messages.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "cull_report.h"
#include "gpu_timer.h"
#include "image_overlay.h"
#include "mesh_pass.h"
#include "offscreen_target.h"
#include "pipeline_cache.h"
#include "plan_pass.h"
#include "render_setup.h"
#include "scene/planned_scene.h"
#include "scene_schemes.h"
#include "scheme_support.h"
#include "surface_error.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

struct CompareArgs {
    std::string path, out;
    std::string schemes;  // comma-separated; empty: every loaded scheme
    std::string size = "360x300";
    uint32_t tess = 8, samples = 16, depth = 6, repeats = 5;
    std::string reference = "far";  // far | plans
    uint32_t referenceDepth = 10;
    std::string camera, pluginDir;
    std::vector<std::string> options;  // SCHEME:KEY=VALUE
    std::string cull = "none";         // DrawView::cull for every scheme
    bool json = false, validate = false;
};

constexpr uint32_t kMaxColumns = 4;
constexpr glm::vec3 kBackground{0.9f, 0.92f, 0.95f};

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = text.find(',', start);
        std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (!item.empty()) items.push_back(item);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return items;
}

std::string sci(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2e", value);
    return text;
}

// Where everything goes in the image.
struct Layout {
    uint32_t tileWidth, tileHeight, columns, rows, labelHeight, legendHeight;
    uint32_t width() const { return columns * tileWidth; }
    uint32_t cellHeight() const { return labelHeight + 2 * tileHeight; }
    uint32_t height() const { return rows * cellHeight() + legendHeight; }
    VkRect2D tile(uint32_t scheme, bool heat) const {
        const uint32_t x = (scheme % columns) * tileWidth, y = (scheme / columns) * cellHeight() + labelHeight;
        return {{int32_t(x), int32_t(y + (heat ? tileHeight : 0))}, {tileWidth, tileHeight}};
    }
};

int nameScale(const Layout& layout) { return layout.tileWidth >= 200 ? 2 : 1; }

void drawLegend(RgbaImage& image, const Layout& layout, const ExactReference& reference) {
    const int top = int(layout.rows * layout.cellHeight());
    image.fill(0, top, int(image.width), int(layout.legendHeight), {255, 255, 255});
    const int margin = 16;
    const int barWidth = std::min(int(image.width) - 2 * margin, 720);
    const int x0 = margin, y0 = top + 10, barHeight = 14;
    for (int x = 0; x < barWidth; ++x) {
        const double decades = std::log10(kHeatHigh / kHeatLow);
        const double value = kHeatLow * std::pow(10.0, decades * (double(x) + 0.5) / double(barWidth));
        const glm::vec3 c = heatColorSrgb(value);
        image.fill(x0 + x, y0, 1, barHeight, {uint8_t(c.r * 255.0f + 0.5f), uint8_t(c.g * 255.0f + 0.5f), uint8_t(c.b * 255.0f + 0.5f)});
    }
    const Rgb ink{20, 20, 20};
    const int decades = int(std::lround(std::log10(kHeatHigh / kHeatLow)));
    for (int d = 0; d <= decades; ++d) {
        const int x = x0 + (barWidth - 1) * d / decades;
        image.fill(x, y0 + barHeight, 1, 5, ink);
        const std::string label = "1e" + std::to_string(int(std::lround(std::log10(kHeatLow))) + d);
        const int w = textWidth(label, 1);
        drawText(image, std::clamp(x - w / 2, 0, int(image.width) - w), y0 + barHeight + 7, label, 1, ink);
    }
    drawText(image, x0, y0 + barHeight + 22,
             "error / bounding-box diagonal at the same (sub-face, u, v) vs the exact limit surface (log scale); exact: " +
                 reference.description(),
             1, ink);
    drawText(image, x0, y0 + barHeight + 36,
             "top: the scheme's own rendering   bottom: its error (CPU evaluation)   label: max / rms error, max normal deviation",
             1, ink);
}

void drawLabels(RgbaImage& image, const Layout& layout, const std::vector<SchemeComparison>& results) {
    const int scale = nameScale(layout);
    for (uint32_t i = 0; i < results.size(); ++i) {
        const SchemeComparison& r = results[i];
        const int x = int((i % layout.columns) * layout.tileWidth), y = int((i / layout.columns) * layout.cellHeight());
        image.fill(x, y, int(layout.tileWidth), int(layout.labelHeight), {255, 255, 255});
        image.fill(x, y, 1, int(layout.cellHeight()), {170, 170, 170});  // column separator
        drawText(image, x + 6, y + 4, r.name, scale, {10, 10, 10});
        const int line2 = y + 6 + textHeight(scale);
        if (r.drawn) {
            char text[160];
            std::snprintf(text, sizeof text, "max %s  rms %s  normal %.3g deg", sci(r.error.maxRelError).c_str(),
                          sci(r.error.rmsRelError).c_str(), r.error.maxNormalDegrees);
            if (layout.tileWidth < 300)  // narrow tiles: the short form, in every column alike
                std::snprintf(text, sizeof text, "%.1e / %.1e / %.2g deg", r.error.maxRelError, r.error.rmsRelError,
                              r.error.maxNormalDegrees);
            drawText(image, x + 6, line2, text, 1, {40, 40, 40});
            // Approximations at the bottom of the rendering, so nobody misses them: each one's
            // headline (the text before its parenthesised details, which the table's JSON and
            // stderr carry in full), so that every approximation fits.
            const VkRect2D tile = layout.tile(i, false);
            std::vector<std::string> lines;
            for (const std::string& a : r.approximations)
                for (const std::string& l : wrapText("approximates: " + a.substr(0, a.find(" (")), int(layout.tileWidth) - 12, 1))
                    lines.push_back(l);
            if (lines.size() > 6) lines.resize(6);
            int ty = tile.offset.y + int(tile.extent.height) - 4 - int(lines.size()) * (textHeight(1) + 1);
            for (const std::string& l : lines) {
                drawText(image, tile.offset.x + 6, ty, l, 1, {150, 60, 0});
                ty += textHeight(1) + 1;
            }
        } else {
            drawText(image, x + 6, line2, "not drawn", 1, {170, 0, 0});
            const VkRect2D tile = layout.tile(i, false);
            image.fill(tile.offset.x + 1, tile.offset.y, int(tile.extent.width) - 1, int(2 * tile.extent.height), {225, 225, 225});
            int ty = tile.offset.y + 10;
            for (const std::string& l : wrapText(r.reason, int(layout.tileWidth) - 16, 1)) {
                drawText(image, tile.offset.x + 8, ty, l, 1, {150, 0, 0});
                ty += textHeight(1) + 2;
            }
        }
    }
}

std::string referenceLine(const ExactReference& reference) {
    std::string line = "reference: " + reference.description();
    if (reference.errorBound() > 0.0)
        line += " (its own error: " + sci(reference.errorBound()) + " of the diagonal, measured against Stam's exact "
                "evaluation next to extraordinary vertices)";
    else if (reference.kind == ReferenceKind::Plans)
        line += " (exact except within 2^-" + std::to_string(reference.depth) +
                " of extraordinary vertices, where a Gregory end cap stands in: up to 4.4e-3 of the diagonal at depth 6)";
    else
        line += " (Gregory end caps within 2^-" + std::to_string(reference.depth) + " of extraordinary vertices)";
    return line;
}

void printTable(const std::vector<SchemeComparison>& results, const ExactReference& reference, CullMethod cull) {
    std::printf("%s\n", referenceLine(reference).c_str());
    std::printf("| scheme | max rel error | rms rel error | max normal (deg) | patches | triangles | frame ms | draw ms | setup ms |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    for (const SchemeComparison& r : results) {
        if (!r.drawn) continue;
        std::printf("| %s | %s | %s | %.3g | %llu | %llu | %.2f | %.2f | %.1f |\n", r.name.c_str(),
                    sci(r.error.maxRelError).c_str(), sci(r.error.rmsRelError).c_str(), r.error.maxNormalDegrees,
                    (unsigned long long)r.draw.patches, (unsigned long long)r.draw.triangles, r.frameMs, r.drawMs,
                    r.setupMs);
    }
    for (const SchemeComparison& r : results)
        if (!r.drawn) std::printf("not drawn: %s: %s\n", r.name.c_str(), r.reason.c_str());
    // The table's patches and triangles leave the culled ones out; what was culled, per scheme.
    if (cull != CullMethod::None)
        for (const SchemeComparison& r : results)
            if (r.drawn)
                std::printf("culled (%s): %s: %llu of %llu patches outside the frustum, %llu facing away, %llu tested by "
                            "the frustum only; %.2f ms on the CPU\n",
                            cullMethodName(cull), r.name.c_str(), (unsigned long long)r.draw.cull.frustum,
                            (unsigned long long)r.draw.cull.tested, (unsigned long long)r.draw.cull.backFacing,
                            (unsigned long long)r.draw.cull.frustumOnly, r.draw.cullMilliseconds);
}

void printJson(const std::vector<SchemeComparison>& results, const std::string& image, const std::string& cage,
               const CompareArgs& args, const ExactReference& reference) {
    nlohmann::json schemes = nlohmann::json::array(), skipped = nlohmann::json::array();
    for (const SchemeComparison& r : results) {
        if (!r.drawn) {
            skipped.push_back({{"name", r.name}, {"reason", r.reason}});
            continue;
        }
        schemes.push_back({{"name", r.name},
                           {"max_rel_error", r.error.maxRelError},
                           {"rms_rel_error", r.error.rmsRelError},
                           {"max_normal_deg", r.error.maxNormalDegrees},
                           {"p99_normal_deg", r.error.p99NormalDegrees},
                           {"normal_samples_excluded", r.error.normalSamplesExcluded},
                           {"normal_samples_no_tangent_plane", r.error.normalSamplesWithoutTangentPlane},
                           {"patches", r.draw.patches},
                           {"primitives", r.draw.primitives()},
                           {"path", drawnByName(r.draw.drawnBy)},
                           {"single_crease_patches", r.stats.singleCreasePatches},
                           {"triangles", r.draw.triangles},
                           {"frame_ms", r.frameMs},
                           {"draw_ms", r.drawMs},
                           {"setup_ms", r.setupMs},
                           {"control_points", r.stats.controlPoints},
                           {"samples", r.error.samples},
                           {"cull", cullJson(*parseCullMethod(args.cull), r.draw)},
                           {"approximations", r.approximations}});
    }
    nlohmann::json bound = reference.errorBound() > 0.0 ? nlohmann::json(reference.errorBound()) : nlohmann::json(nullptr);
    nlohmann::json exact = {{"method", reference.kind == ReferenceKind::Far ? "far-adaptive" : "plans"},
                            {"depth", reference.depth},
                            {"description", referenceLine(reference).substr(11)},
                            {"error_bound", bound}};
    nlohmann::json out = {{"cage", cage},  {"image", image},     {"tess", args.tess}, {"samples_per_edge", args.samples},
                          {"plan_depth", args.depth}, {"reference", exact}, {"schemes", schemes}, {"skipped", skipped}};
    std::printf("%s\n", out.dump(2).c_str());
}

// The error heat map of every visible object into `area`: its cage's evaluated grid points
// coloured by their error, under the object's transform.
Status drawHeatMaps(const VulkanContext& ctx, const MeshPass& pass, const RenderTarget& area, const DrawView& view,
                    const Scene& scene, const PlannedScene& planned, const std::vector<SubfaceGrid>& grids,
                    const std::vector<size_t>& firstSampleOfCage, std::span<const SurfacePoint> points,
                    std::span<const float> relError) {
    std::vector<GpuMesh> meshes;
    Status ok = success();
    for (uint32_t c = 0; ok && c < grids.size(); ++c) {
        const auto cagePoints = points.subspan(firstSampleOfCage[c], grids[c].samples.size());
        std::vector<glm::vec3> colors(cagePoints.size());
        for (size_t k = 0; k < cagePoints.size(); ++k) colors[k] = heatColorLinear(relError[firstSampleOfCage[c] + k]);
        const std::vector<MeshVertex> vertices = meshVertices(cagePoints);
        Result<GpuMesh> heat = vertices.empty() ? Result<GpuMesh>(GpuMesh{}) : uploadMesh(ctx, vertices, grids[c].indices, colors);
        if (!heat) ok = heat.error();
        else meshes.push_back(*heat);
    }
    if (ok) ok = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        bool cleared = false;
        for (uint32_t i = 0; i < scene.objects.size(); ++i) {
            const GpuMesh& mesh = meshes[planned.cageOfObject[i]];
            if (!scene.objects[i].visible || mesh.indexCount == 0) continue;
            const DrawView object = objectView(view, scene.objects[i].transform);
            const MeshDraw draw{&mesh};
            recordMeshPass(cmd, pass, area, MeshView{object.viewProjection, object.eye, kBackground, Shading::Studio, !cleared},
                           {&draw, 1});
            cleared = true;
        }
        if (!cleared) {
            beginRendering(cmd, area, true, kBackground);
            vkCmdEndRendering(cmd);
        }
    });
    for (GpuMesh& mesh : meshes)
        if (mesh.indexCount) destroyMesh(ctx, mesh);
    return ok;
}

int runCompare(const CompareArgs& args) {
    uint32_t tileWidth = 0, tileHeight = 0;
    if (!parseSize(args.size, tileWidth, tileHeight))
        return fail("--size must be WIDTHxHEIGHT (of one tile) with each side between 16 and 8192, got '" + args.size + "'");

    const PluginCatalog catalog = loadPlugins(pluginDirectory(args.pluginDir));
    for (const PluginProblem& p : catalog.problems) std::fprintf(stderr, "warning: %s\n", p.message.c_str());
    std::vector<std::string> names = splitList(args.schemes);
    if (args.schemes.empty())
        for (const auto& plugin : catalog.plugins) names.push_back(plugin->name);
    if (names.empty()) return fail("no schemes to compare: --schemes is empty and no plugin loaded from " + catalog.directory);

    // SCHEME:KEY=VALUE options, per scheme.
    std::vector<std::pair<std::string, std::pair<std::string, std::string>>> options;
    for (const std::string& text : args.options) {
        const size_t colon = text.find(':');
        auto option = colon == std::string::npos ? Result<std::pair<std::string, std::string>>(Error{""})
                                                 : parseOption(text.substr(colon + 1));
        if (!option) return fail("--option must be SCHEME:KEY=VALUE, got '" + text + "'");
        options.push_back({text.substr(0, colon), *option});
    }

    PlanDatabase database;
    Result<PlannedFile> file = loadAndPlan(args.path, database, PlanOptions{args.depth, true});
    if (!file) return fail(file.error().message);
    Scene& scene = file->scene;
    PlannedScene& planned = file->planned;
    Result<RenderCamera> camera = chooseCamera(scene, sceneBounds(scene), float(tileWidth) / float(tileHeight), args.camera);
    if (!camera) return fail(camera.error().message);
    if (args.reference != "far" && args.reference != "plans")
        return fail("--reference must be far or plans, got '" + args.reference + "'");
    const ReferenceKind referenceKind = args.reference == "far" ? ReferenceKind::Far : ReferenceKind::Plans;
    // Error samples per cage (instances share their cage's: the same surface in other places),
    // each relative to its own cage's diagonal; the reference holds them all, cage after cage.
    std::vector<SubfaceGrid> grids;
    std::vector<size_t> firstSampleOfCage{0};
    std::vector<double> diagonalOfSample;
    ExactReference reference;
    for (uint32_t c = 0; c < planned.cages.size(); ++c) {
        const PlannedCage& cage = planned.cages[c];
        const std::string source = planned.cages.size() == 1
                                       ? args.path
                                       : args.path + ": object \"" + scene.objects[planned.objectOfCage[c]].name + "\"";
        grids.push_back(buildSubfaceGrid(cage, args.samples));
        Result<ExactReference> part = evaluateReference(referenceKind, args.referenceDepth, cage, grids.back().samples, source);
        if (!part) return fail("the exact reference failed: " + part.error().message);
        if (c == 0) {
            reference = std::move(part).value();
        } else {
            reference.samples.insert(reference.samples.end(), part->samples.begin(), part->samples.end());
            reference.withoutTangentPlane.insert(reference.withoutTangentPlane.end(), part->withoutTangentPlane.begin(),
                                                 part->withoutTangentPlane.end());
        }
        diagonalOfSample.resize(diagonalOfSample.size() + grids.back().samples.size(),
                                std::max(double(computeBounds(cage.cage()).diagonal()), 1e-30));
        firstSampleOfCage.push_back(firstSampleOfCage.back() + grids.back().samples.size());
    }

    Layout layout{tileWidth, tileHeight, std::min<uint32_t>(uint32_t(names.size()), kMaxColumns),
                  (uint32_t(names.size()) + kMaxColumns - 1) / kMaxColumns, 0, 78};
    layout.labelHeight = uint32_t(textHeight(nameScale(layout)) + textHeight(1) + 14);

    Result<VulkanContext> context = createHeadlessContext(args.validate);
    if (!context) return fail(context.error().message);
    VulkanContext& ctx = *context;
    std::vector<std::string> cacheWarnings;
    Result<PipelineCache> cache = loadPipelineCache(ctx, defaultPipelineCachePath(), &cacheWarnings);
    for (const std::string& w : cacheWarnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    const VkPipelineCache vkCache = cache ? cache->cache : VK_NULL_HANDLE;
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    const GpuContext gpu{&ctx, vkCache, format, VK_FORMAT_D32_SFLOAT};

    int status = 0;
    std::vector<SchemeComparison> results;
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, layout.width(), layout.height(), format);
    Result<MeshPass> heatPass = target ? createMeshPass(ctx, vkCache, format) : Result<MeshPass>(target.error());
    Result<GpuTimer> timer = heatPass ? createGpuTimer(ctx) : Result<GpuTimer>(heatPass.error());
    // The whole image starts as background; passes then draw their tiles.
    Status cleared = timer ? submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        beginRendering(cmd, renderTarget(*target), true, glm::vec3(1.0f));
        vkCmdEndRendering(cmd);
    }) : Status(timer.error());
    if (!cleared) {
        status = fail("cannot set up the renderer: " + cleared.error().message);
    } else {
        DrawView view;
        view.viewProjection = viewProjection(*camera);
        view.eye = camera->eye;
        view.background = kBackground;
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(*camera), tileHeight);
        view.cull = *parseCullMethod(args.cull);
        view.sampleCulling = false;  // like with like: the frame times compare every scheme's whole draw
        for (uint32_t i = 0; i < names.size(); ++i) {
            SchemeComparison r;
            r.name = names[i];
            SchemeSettings settings;
            settings.tessFactor = args.tess;
            settings.planDepth = args.depth;
            for (const auto& [scheme, option] : options)
                if (scheme == r.name) settings.options.push_back(option);
            // The tiles show the objects' sculpted displacement; the error is the undisplaced
            // surface's (Scheme::evaluate), against the exact limit surface.
            Result<SceneSchemes> prepared = prepareSceneSchemes(catalog, r.name, scene, planned, settings, gpu, args.path);
            if (!prepared) {
                r.reason = prepared.error().message;
                std::fprintf(stderr, "error: %s\n", r.reason.c_str());
                results.push_back(std::move(r));
                continue;
            }
            for (const PreparedScheme& p : prepared->cages)
                r.approximations.insert(r.approximations.end(), p.support.approximations.begin(), p.support.approximations.end());
            for (const std::string& a : r.approximations) std::fprintf(stderr, "warning: %s: %s\n", r.name.c_str(), a.c_str());
            r.setupMs = prepared->setupMs();

            // Frames as if the cages moved every frame: the updates, then the draw, timed; the
            // last one stays in the tile.
            const RenderTarget tile = subArea(renderTarget(*target), layout.tile(i, false));
            Status ok = success();
            if (Result<SchemeFrameTimes> times =
                    timeSceneFrames(ctx, *prepared, scene, planned, tile, view, *timer, args.repeats)) {
                r.draw = times->draw;
                r.frameMs = times->frameMs;
                r.drawMs = times->drawMs;
            } else {
                ok = times.error();
            }

            // The error on the sample grids, and its heat map in the tile below.
            std::vector<SurfacePoint> points(reference.samples.size());
            for (uint32_t c = 0; ok && c < prepared->cages.size(); ++c) {
                ok = prepared->cages[c].instance.evaluate(
                    grids[c].samples, std::span(points).subspan(firstSampleOfCage[c], grids[c].samples.size()));
                Result<SchemeStats> stats = ok ? prepared->cages[c].instance.stats() : Result<SchemeStats>(ok.error());
                if (!stats) {
                    ok = stats.error();
                    break;
                }
                r.stats.patches += stats->patches;
                r.stats.controlPoints += stats->controlPoints;
                r.stats.gpuBytes += stats->gpuBytes;
                r.stats.singleCreasePatches += stats->singleCreasePatches;
            }
            if (ok) {
                SurfaceError error = measureSurfaceError(reference, points, diagonalOfSample);
                r.error = error.stats;
                ok = drawHeatMaps(ctx, *heatPass, subArea(renderTarget(*target), layout.tile(i, true)), view, scene,
                                  planned, grids, firstSampleOfCage, points, error.relError);
            }
            if (Status destroyed = destroySceneSchemes(*prepared); ok && !destroyed) ok = destroyed;
            if (!ok) {
                r.reason = ok.error().message;
                std::fprintf(stderr, "error: %s\n", r.reason.c_str());
            } else {
                r.drawn = true;
            }
            results.push_back(std::move(r));
        }

        Result<std::vector<uint8_t>> pixels = readPixels(ctx, *target);
        if (!pixels) {
            status = fail("reading the image back failed: " + pixels.error().message);
        } else {
            RgbaImage image{layout.width(), layout.height(), std::move(*pixels)};
            drawLabels(image, layout, results);
            drawLegend(image, layout, reference);
            Status written = writePng(args.out, image.width, image.height, image.pixels);
            if (!written) status = fail(written.error().message);
        }
    }

    if (timer) destroyGpuTimer(ctx, *timer);
    if (heatPass) destroyMeshPass(ctx, *heatPass);
    if (target) destroyOffscreenTarget(ctx, *target);
    if (cache) {
        if (Status saved = savePipelineCache(ctx, *cache); !saved)
            std::fprintf(stderr, "warning: pipeline cache not saved: %s\n", saved.error().message.c_str());
        destroyPipelineCache(ctx, *cache);
    }
    destroyContext(ctx);

    const size_t drawn = size_t(std::count_if(results.begin(), results.end(), [](const SchemeComparison& r) { return r.drawn; }));
    if (status == 0) {
        if (args.json) printJson(results, args.out, args.path, args, reference);
        else printTable(results, reference, *parseCullMethod(args.cull));
        std::fprintf(stderr, "wrote %s (%ux%u, %zu of %zu schemes drawn, %zu error samples each)\n", args.out.c_str(),
                     layout.width(), layout.height(), drawn, names.size(), reference.samples.size());
        if (drawn == 0) status = 1;
        else if (drawn < names.size()) status = 2;
    }
    if (args.validate && reportValidation(ctx)) return 4;
    return status;
}

}  // namespace

void registerCompare(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand(
        "compare", "Render a cage through several schemes side by side with their error against the exact limit surface");
    auto args = std::make_shared<CompareArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json)")->required();
    cmd->add_option("--out", args->out, "PNG file to write")->required();
    cmd->add_option("--schemes", args->schemes, "Comma-separated scheme names (default: every loaded scheme)");
    cmd->add_option("--size", args->size, "Size of one tile, WIDTHxHEIGHT (default 360x300)");
    cmd->add_option("--tess", args->tess, "Tessellation factor the schemes draw with (default 8)")->check(CLI::Range(1u, 64u));
    cmd->add_option("--samples", args->samples, "Error samples per sub-face edge (default 16)")->check(CLI::Range(1u, 256u));
    cmd->add_option("--depth", args->depth, "Plan depth (the plans scheme, osd-fas's isolation, --reference plans)")
        ->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_option("--reference", args->reference,
                    "The exact surface errors are measured against: far (OpenSubdiv Far adaptive patches in double, "
                    "default) or plans (the plans at --depth)");
    cmd->add_option("--reference-depth", args->referenceDepth, "Isolation depth of --reference far (default 10)")
        ->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_option("--repeats", args->repeats, "Timed frames per scheme, after one warm-up (default 5)")->check(CLI::Range(1u, 1000u));
    cmd->add_option("--camera", args->camera, "EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES] (default: the scene's, or framed)");
    cmd->add_option("--option", args->options, "Scheme option SCHEME:KEY=VALUE (repeatable), e.g. uniform:level=4");
    cmd->add_option("--plugin-dir", args->pluginDir, "Where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else <bin>/../plugins)");
    cmd->add_option("--cull", args->cull, "Every scheme skips patches that cannot show a pixel (docs/culling.md): none "
                                          "(default), frustum, or a back-patch test with it: tcone, ncone, pplane")
        ->check(CLI::IsMember({"none", "frustum", "tcone", "ncone", "pplane"}));
    cmd->add_flag("--json", args->json, "Print the results as JSON");
    cmd->add_flag("--validate", args->validate, "Enable Vulkan validation; any message makes the command fail");
    cmd->callback([args, &exitCode] { exitCode = runCompare(*args); });
}

}  // namespace qp::cli
