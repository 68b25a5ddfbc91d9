// `quadplan animate` (issue 22): plays a cage or scene animation headless and writes a PNG per
// frame. Every frame is a vertex move (core/animation/animation_playback.h showFrame: nothing re-planned)
// and the scheme instance built once takes it through Scheme::updateMoved, the way the editor
// and `bench animation` (c) update a drawn cage; a scheme that fails to update in place is built
// again, and the count is reported.
//
// Inputs are checked before anything is written: an OBJ sequence (--sequence) is read whole
// (a missing frame number, a frame with another topology, a frame that does not load fail the
// command naming the file), and a failure while rendering removes the frames already written.
#include <algorithm>
#include <cerrno>
#include <climits>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "animation/animation_playback.h"
#include "animation/cage_sequence.h"
#include "bench/bench_report.h"
#include "bench/bench_stats.h"
#include "commands.h"
#include "headless_scene.h"
#include "plan_pass.h"
#include "render_setup.h"
#include "scene/planned_scene.h"
#include "scene_schemes.h"
#include "vk_buffer.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

namespace fs = std::filesystem;

// Frame numbers as the scene reader accepts them (and as a file name's four digits grow from).

struct AnimateArgs {
    std::string path, out, sequence, frames;
    DrawOptions draw;  // --scheme, --size, --tess, ... (addDrawOptions)
    bool json = false;
};

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

// One integer of "A:B", within +-kMaxKeyFrame.
bool parseFrameNumber(const std::string& text, int32_t& out) {
    if (text.empty()) return false;
    errno = 0;
    char* end = nullptr;
    const long long value = std::strtoll(text.c_str(), &end, 10);
    if (*end != '\0' || errno == ERANGE || value > kMaxKeyFrame || value < -kMaxKeyFrame) return false;
    out = int32_t(value);
    return true;
}

Result<std::pair<int32_t, int32_t>> parseFrames(const std::string& text) {
    const size_t colon = text.find(':');
    int32_t first = 0, last = 0;
    if (colon == std::string::npos || !parseFrameNumber(text.substr(0, colon), first) ||
        !parseFrameNumber(text.substr(colon + 1), last))
        return Error{"--frames must be A:B, two frame numbers (inclusive), got '" + text + "'"};
    if (first > last)
        return Error{"--frames " + text + ": the first frame, " + std::to_string(first) + ", comes after the last, " +
                     std::to_string(last)};
    return std::make_pair(first, last);
}

// The world bounds of the visible objects (of all when none is visible) over every frame
// played: one camera frames the whole animation.
Bounds animationBounds(const Scene& scene, const PlannedScene& planned, int32_t first, int32_t last) {
    const bool anyVisible =
        std::any_of(scene.objects.begin(), scene.objects.end(), [](const SceneObject& o) { return o.visible; });
    Bounds out;
    out.min = glm::vec3(std::numeric_limits<float>::max());
    out.max = glm::vec3(-std::numeric_limits<float>::max());
    std::vector<Bounds> cageBounds(planned.cages.size());
    for (int32_t frame = first;; ++frame) {
        for (uint32_t c = 0; c < planned.cages.size(); ++c) {
            const SceneObject& owner = scene.objects[planned.objectOfCage[c]];
            Cage cage;
            cage.positions = owner.animation.vertexKeys.empty()
                                 ? owner.cage.positions
                                 : positionsAtFrame(owner.animation, owner.cage.positions, double(frame));
            cageBounds[c] = computeBounds(cage);
        }
        for (uint32_t i = 0; i < scene.objects.size(); ++i) {
            const SceneObject& object = scene.objects[i];
            if (anyVisible && !object.visible) continue;
            const ObjectTransform transform = evaluateTransform(object.animation, double(frame), object.transform);
            const Bounds b = transformBounds(cageBounds[planned.cageOfObject[i]], transform.matrix());
            out.min = glm::min(out.min, b.min);
            out.max = glm::max(out.max, b.max);
        }
        if (frame == last) break;
    }
    return out;
}

std::string frameFile(const std::string& dir, int32_t frame) {
    char name[32];  // four digits at least, after the sign of a negative frame
    std::snprintf(name, sizeof name, "frame_%s%04lld.png", frame < 0 ? "-" : "", std::llabs((long long)frame));
    return (fs::path(dir) / name).string();
}

int runAnimate(const AnimateArgs& args) {
    uint32_t width = 0, height = 0;
    if (!parseSize(args.draw.size, width, height))
        return fail("--size must be WIDTHxHEIGHT with each side between 16 and 8192, got '" + args.draw.size + "'");
    if (args.draw.tess > 0 && args.draw.adaptive > 0.0f) return fail("give either --tess or --adaptive, not both");
    std::optional<std::pair<int32_t, int32_t>> frameRange;
    if (!args.frames.empty()) {
        Result<std::pair<int32_t, int32_t>> parsed = parseFrames(args.frames);
        if (!parsed) return fail(parsed.error().message);
        frameRange = *parsed;
    }
    if (fs::exists(args.out) && !fs::is_directory(args.out))
        return fail("--out " + args.out + " is a file; give the folder to write the frames into");

    Result<DrawInput> input = loadDrawInput(args.path, args.draw);
    if (!input) return fail(input.error().message);
    SchemeSettings settings = input->scheme.settings;
    const PluginCatalog& catalog = input->scheme.catalog;
    Scene& scene = input->file.scene;
    PlannedScene& planned = input->file.planned;

    if (!args.sequence.empty()) {
        SceneObject& target = scene.objects.front();
        if (target.isInstance())
            return fail("--sequence: the first object, \"" + target.name + "\", is an instance of \"" + target.instanceOf +
                        "\"; an OBJ sequence moves the cage of an object that has its own");
        Result<VertexKeys> keys = loadSequenceKeys(args.sequence, target.cage);
        if (!keys) return fail("--sequence: " + keys.error().message);
        if (!target.animation.vertexKeys.empty())
            std::fprintf(stderr, "warning: --sequence replaces the keys of object \"%s\"\n", target.name.c_str());
        target.animation.vertexKeys = std::move(keys).value();
        target.animation.sequencePattern = args.sequence;
    }
    if (!isAnimated(scene))
        return fail(args.path + " has no animation: no object has vertex or transform keys (give --sequence GLOB to "
                    "play an OBJ sequence on it)");
    const Timeline timeline = timelineOf(scene);
    const int32_t first = frameRange ? frameRange->first : timeline.firstFrame;
    const int32_t last = frameRange ? frameRange->second : timeline.lastFrame;

    setTessellation(settings, args.draw.tess, args.draw.adaptive, scene.tessellation);
    const bool showCage = !args.draw.noCage && scene.tessellation.showCage;
    const float aspect = float(width) / float(height);
    Result<RenderCamera> camera = chooseCamera(scene, animationBounds(scene, planned, first, last), aspect, args.draw.camera);
    if (!camera) return fail(camera.error().message);

    // Each object's own transform, under its transform keys' values per frame.
    std::vector<ObjectTransform> restTransforms;
    for (const SceneObject& o : scene.objects) restTransforms.push_back(o.transform);

    HeadlessSceneRequest request{&catalog, args.draw.scheme, settings, args.path, width, height, args.draw.colorBy, args.draw.validate};
    Result<std::unique_ptr<HeadlessScene>> created = createHeadlessScene(request, scene, planned);
    if (!created) return fail(created.error().message);
    HeadlessScene& h = **created;
    VulkanContext& ctx = h.ctx;
    const GpuContext& gpu = h.gpu;
    int status = h.problem.empty() ? 0 : fail(h.problem);

    // What the frames measured and wrote.
    std::vector<std::string> written;
    std::vector<double> updateMs, frameMs;
    std::vector<uint64_t> triangles;
    uint64_t replanned = 0;
    uint32_t rebuilds = 0;
    bool createdOut = false;
    if (status == 0) {
        const DrawView view = headlessView(*camera, height, args.draw.colorBy, args.draw.wire || scene.tessellation.showWireframe);
        SceneSchemes& schemes = *h.schemes;
        SceneCageLines& cageLineBuffers = *h.cageLines;

        std::error_code error;
        createdOut = !fs::exists(args.out);
        fs::create_directories(args.out, error);
        if (error) status = fail("cannot create the folder " + args.out + ": " + error.message());

        std::vector<glm::vec3> shown;
        std::vector<uint32_t> moved;
        for (int32_t frame = first; status == 0; ++frame) {
            const std::string where = "frame " + std::to_string(frame);
            const auto frameStart = Clock::now();
            double frameUpdateMs = 0.0;
            std::string problem;
            for (uint32_t c = 0; c < planned.cages.size() && problem.empty(); ++c) {
                const SceneObject& owner = scene.objects[planned.objectOfCage[c]];
                if (owner.animation.vertexKeys.empty()) continue;
                PlannedCage& cage = planned.cages[c];
                shown = cage.cage().positions;
                const auto updateStart = Clock::now();
                Result<EditReport> report = showFrame(cage, owner.animation, owner.cage.positions, double(frame));
                frameUpdateMs += msSince(updateStart);
                if (!report) {
                    problem = report.error().message;
                    break;
                }
                replanned += report->replannedFaces;
                const std::vector<glm::vec3>& now = cage.cage().positions;
                moved.clear();
                for (uint32_t v = 0; v < now.size(); ++v)
                    if (now[v] != shown[v]) moved.push_back(v);
                if (moved.empty()) continue;
                SchemeInstance& instance = schemes.cages[c].instance;
                if (Status updated = instance.updateMoved(moved); !updated) {
                    // Built again for the cage as it is now, as the editor does when a scheme
                    // cannot take a change in place.
                    std::fprintf(stderr, "warning: %s: %s could not update in place (%s); building it again\n",
                                 where.c_str(), args.draw.scheme.c_str(), updated.error().message.c_str());
                    (void)instance.destroyGpu();
                    Result<PreparedScheme> again =
                        prepareScheme(catalog, args.draw.scheme, cage, analyzeCage(cage.cage(), cage.topology()), settings, gpu,
                                      args.path, owner.displacement.empty() ? nullptr : &owner.displacement);
                    if (!again) {
                        problem = again.error().message;
                        break;
                    }
                    schemes.cages[c] = std::move(again).value();
                    ++rebuilds;
                }
                if (showCage) {
                    const std::vector<LineVertex> vertices = cageLines(cage.cage());
                    if (vertices.size() == cageLineBuffers.counts[c])
                        uploadBuffer(cageLineBuffers.buffers[c], vertices.data(), vertices.size() * sizeof(LineVertex));
                }
            }
            for (uint32_t i = 0; i < scene.objects.size(); ++i)
                scene.objects[i].transform = evaluateTransform(scene.objects[i].animation, double(frame), restTransforms[i]);

            Result<DrawStats> drawStats = DrawStats{};
            Status drawn = problem.empty() ? success() : Status(Error{problem});
            if (drawn)
                drawn = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                    drawStats = recordScene(cmd, schemes, scene, planned, renderTarget(*h.target), view);
                    if (showCage) recordSceneCageLines(cmd, *h.lines, renderTarget(*h.target), cageLineBuffers, scene, planned, view);
                });
            if (drawn && !drawStats) drawn = drawStats.error();
            Result<std::vector<uint8_t>> pixels = drawn ? readPixels(ctx, *h.target) : Result<std::vector<uint8_t>>(drawn.error());
            if (pixels) {
                frameMs.push_back(msSince(frameStart));
                updateMs.push_back(frameUpdateMs);
            }
            const std::string png = frameFile(args.out, frame);
            Status saved = pixels ? writePng(png, width, height, *pixels) : Status(pixels.error());
            if (!saved) {
                status = fail("animating " + args.path + " failed at " + where + ": " + saved.error().message);
                break;
            }
            written.push_back(png);
            triangles.push_back(drawStats->triangles);
            if (frame == last) break;
        }
        if (status != 0) {
            // No partial animation is left behind.
            for (const std::string& path : written) fs::remove(path, error);
            if (createdOut) fs::remove(args.out, error);  // only when empty
            written.clear();
        }
    }
    const std::string device = ctx.deviceName;
    status = destroyHeadlessScene(h, args.draw.validate, status);
    if (status != 0) return status;

    if (replanned > 0)
        std::fprintf(stderr, "warning: playback re-planned %llu faces (a frame should only move vertices)\n",
                     (unsigned long long)replanned);
    const double updateMedian = median(updateMs), frameMedian = median(frameMs);
    const bool adaptive = settings.adaptivePixels > 0.0f;
    if (args.json) {
        nlohmann::json out = {{"out", args.out},
                              {"frames", written.size()},
                              {"first_frame", first},
                              {"last_frame", last},
                              {"replanned_faces", replanned},
                              {"update_ms_median", updateMedian},
                              {"frame_ms_median", frameMedian},
                              {"triangles", triangles},
                              {"scheme", args.draw.scheme},
                              {"tess", adaptive ? nlohmann::json(nullptr) : nlohmann::json(settings.tessFactor)},
                              {"adaptive_pixels", adaptive ? nlohmann::json(settings.adaptivePixels) : nlohmann::json(nullptr)},
                              {"rebuilds", rebuilds},
                              {"size", std::to_string(width) + "x" + std::to_string(height)},
                              {"device", device}};
        std::printf("%s\n", out.dump(2).c_str());
    }
    char density[64];
    if (adaptive) std::snprintf(density, sizeof density, "adaptive %g px", double(settings.adaptivePixels));
    else std::snprintf(density, sizeof density, "factor %u", settings.tessFactor);
    std::fprintf(stderr,
                 "wrote %zu frames (%d..%d) to %s (%ux%u, scheme %s at %s on %s): update %.3f ms, frame %.3f ms "
                 "(medians, PNG encoding not counted), %llu faces re-planned, %u rebuilds\n",
                 written.size(), int(first), int(last), args.out.c_str(), width, height, args.draw.scheme.c_str(), density,
                 device.c_str(), updateMedian, frameMedian, (unsigned long long)replanned, rebuilds);
    return 0;
}

}  // namespace

void registerAnimate(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("animate", "Play a cage or scene animation (keys or an OBJ sequence) into a PNG per frame "
                                              "(headless, Vulkan) through a scheme plugin");
    auto args = std::make_shared<AnimateArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json)")->required();
    cmd->add_option("--out", args->out, "Folder to write frame_NNNN.png into (NNNN: the frame number)")->required();
    cmd->add_option("--sequence", args->sequence,
                    "OBJ sequence to play on the cage (or the scene's first object): a pattern with one '*' for the frame "
                    "number, e.g. 'frames/frame_*.obj'");
    cmd->add_option("--frames", args->frames, "Frames to play, A:B inclusive (default: the scene's timeline, else its keys' range)");
    addDrawOptions(*cmd, args->draw, "EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES] (default: the scene's, or framed on every frame played)",
                   "The scheme's drawing path, as for render (plans: auto, tess, grid or cpu)");
    cmd->add_flag("--json", args->json, "Print what was played as JSON: frames, replanned_faces, update_ms_median, ...");
    cmd->callback([args, &exitCode] { exitCode = runAnimate(*args); });
}

}  // namespace qp::cli
