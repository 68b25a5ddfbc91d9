// `quadplan bench animation` (issue 22): a deforming cage played frame by frame, every vertex
// moving every frame, against OpenSubdiv's per-frame work on the same frames in the same run.
//
// The deformation is a twist about the cage's vertical axis through its centre: each vertex
// turns by an angle proportional to its height, swinging back and forth over kFrames frames, so
// every vertex but those at mid-height moves every frame. Rows per cage:
//   (a) the update: PlannedCage::moveVertices of every vertex (the control points of every
//       sub-face, re-planning nothing, on every core through TBB) against OpenSubdiv's stencils on
//       every core through TBB as well (Far::StencilTable::UpdateValues over ranges of stencils
//       in a tbb::parallel_for, which is what Osd::TbbEvaluator runs; Debian builds OpenSubdiv
//       without it, and its OpenMP evaluator fights TBB's workers for the cores: 12x slower than
//       one thread when measured so);
//  (a1) the same on one thread each: moveVertices in a one-thread TBB arena against
//       Far::StencilTable::UpdateValues (what OpenSubdiv's CPU viewers run per frame);
//   (b) the update and an evaluation of every sub-face at factor 4 (5 x 5 points, one thread):
//       PlannedCage::evaluate against Far::PatchMap + PatchTable::EvaluateBasis over the updated
//       points;
//   (c) a frame on the Vulkan device: the update, the plans scheme's updateMoved, its draw at
//       factor 4, submit and wait (the goal: 30 fps for catmark_car on lavapipe);
//   (d) faces re-planned over all frames (must be none);
//   (e) the same frames read back from an OBJ sequence (core/animation/cage_sequence.h): read, checked
//       against the cage's topology, moved.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <opensubdiv/far/patchMap.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <unistd.h>

#include "animation/cage_sequence.h"
#include "bench_far.h"
#include "bench_report.h"
#include "bench_stats.h"
#include "camera.h"
#include "mesh/obj_io.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "scheme_host.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

using namespace OpenSubdiv;

constexpr uint32_t kFrames = 24;
constexpr uint32_t kAnimationFactor = 4;

// Frame k of the twist: up to +-45 degrees between the bottom and the top.
std::vector<glm::vec3> twisted(const Cage& cage, const Bounds& bounds, uint32_t frame) {
    const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
    const float height = std::max(bounds.max.y - bounds.min.y, 1e-6f);
    const float swing = glm::radians(45.0f) * std::sin(2.0f * float(M_PI) * float(frame) / float(kFrames));
    std::vector<glm::vec3> out(cage.positions.size());
    for (size_t v = 0; v < out.size(); ++v) {
        const glm::vec3 p = cage.positions[v] - centre;
        const float angle = swing * ((p.y + 0.5f * height) / height - 0.5f) * 2.0f;
        const float c = std::cos(angle), s = std::sin(angle);
        out[v] = centre + glm::vec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
    }
    return out;
}

// OpenSubdiv's evaluation of every Ptex face (our sub-faces) at (n + 1)^2 points.
double farEvaluate(const FarBuild& far, const Far::PatchMap& map, const std::vector<FarPoint>& points, uint32_t ptexFaces,
                   uint32_t n) {
    double sink = 0.0;
    float wP[20], wDu[20], wDv[20];
    for (uint32_t face = 0; face < ptexFaces; ++face)
        for (uint32_t j = 0; j <= n; ++j)
            for (uint32_t i = 0; i <= n; ++i) {
                const float u = float(i) / float(n), v = float(j) / float(n);
                const Far::PatchTable::PatchHandle* handle = map.FindPatch(int(face), u, v);
                if (!handle) continue;
                far.patches->EvaluateBasis(*handle, u, v, wP, wDu, wDv);
                const Far::ConstIndexArray cvs = far.patches->GetPatchVertices(*handle);
                glm::vec3 p(0.0f), du(0.0f), dv(0.0f);
                for (int k = 0; k < cvs.size(); ++k) {
                    const FarPoint& c = points[size_t(cvs[k])];
                    const glm::vec3 q(c.x, c.y, c.z);
                    p += wP[k] * q, du += wDu[k] * q, dv += wDv[k] * q;
                }
                sink += p.x + du.y + dv.z;
            }
    return sink;
}

}  // namespace

void benchAnimation(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench animation: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto skip = [&](const std::string& why) { report.notes.push_back(name + ": skipped, " + why); };
    const PlanOptions options{};
    PlanDatabase database;
    Result<PlannedCage> created = PlannedCage::create(bench.cage, database, options, name);
    if (!created) return skip(created.error().message);
    PlannedCage& planned = *created;
    const Bounds bounds = computeBounds(bench.cage);
    std::vector<std::vector<glm::vec3>> frames;
    for (uint32_t k = 0; k < kFrames; ++k) frames.push_back(twisted(bench.cage, bounds, k));
    std::vector<uint32_t> all(bench.cage.vertexCount());
    for (uint32_t v = 0; v < all.size(); ++v) all[v] = v;
    const FarBuild far = buildFar(bench.cage, options);
    const Far::PatchMap map(*far.patches);
    std::vector<FarPoint> refined(size_t(far.stencils->GetNumStencils()));
    // Every row plays all kFrames frames per round; the large cages play them once (the 100k cage's
    // single-threaded evaluation takes about a second a frame).
    const uint32_t rounds = bench.cage.faceCount() > kLargeCageFaces ? 1u : std::max(1u, args.repeats);
    auto row = [&](std::string benchmark, std::string unit) {
        Row r;
        r.cage = name, r.faces = bench.cage.faceCount(), r.benchmark = std::move(benchmark), r.repeats = rounds * kFrames;
        r.unit = std::move(unit);
        return r;
    };

    // (a) and (a1): like with like, every core against every core, one thread against one.
    const Far::StencilTable& table = *far.stencils;
    tbb::task_arena oneThread(1);
    std::vector<double> oursParallel, osdParallel, oursSerial, farSerial;
    for (uint32_t r = 0; r < rounds; ++r)
        for (uint32_t k = 0; k < kFrames; ++k) {
            auto start = Clock::now();
            if (Result<EditReport> moved = planned.moveVertices(all, frames[k]); !moved) return skip(moved.error().message);
            oursParallel.push_back(msSince(start));
            start = Clock::now();
            tbb::parallel_for(tbb::blocked_range<int>(0, table.GetNumStencils(), 256), [&](const tbb::blocked_range<int>& range) {
                table.UpdateValues(reinterpret_cast<const FarPoint*>(frames[k].data()), refined.data(), range.begin(), range.end());
            });
            osdParallel.push_back(msSince(start));
            start = Clock::now();
            oneThread.execute([&] { (void)planned.moveVertices(all, frames[(k + 1) % kFrames]); });
            oursSerial.push_back(msSince(start));
            start = Clock::now();
            far.stencils->UpdateValues(reinterpret_cast<const FarPoint*>(frames[(k + 1) % kFrames].data()), refined.data());
            farSerial.push_back(msSince(start));
        }
    Row a = row("(a) update per frame, every vertex moving, on every core: PlannedCage::moveVertices (control points of every "
                "sub-face, TBB) vs Far StencilTable::UpdateValues over ranges in a TBB parallel_for (as Osd::TbbEvaluator)", "ms");
    a.ours = median(oursParallel), a.baseline = median(osdParallel), a.target = Target::RatioAtMost, a.targetValue = 0.25;
    report.rows.push_back(a);
    Row a1 = row("(a1) the same on one thread: moveVertices in a one-thread arena vs Far StencilTable::UpdateValues", "ms");
    a1.ours = median(oursSerial), a1.baseline = median(farSerial), a1.target = Target::RatioAtMost, a1.targetValue = 0.25;
    report.rows.push_back(a1);

    // (b) and (d): each frame of each round, ours and Far's back to back.
    std::vector<double> oursFrame, farFrame;
    uint64_t replanned = 0;
    double sink = 0.0;
    for (uint32_t r = 0; r < rounds; ++r)
        for (uint32_t k = 0; k < kFrames; ++k) {
            auto start = Clock::now();
            Result<EditReport> moved = Error{""};
            oneThread.execute([&] { moved = planned.moveVertices(all, frames[k]); });
            if (!moved) return skip(moved.error().message);
            replanned += moved->replannedFaces;
            for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
                if (!planned.hasSurface(s)) continue;
                for (uint32_t j = 0; j <= kAnimationFactor; ++j)
                    for (uint32_t i = 0; i <= kAnimationFactor; ++i) {
                        const LimitSample sample = planned.evaluate(s, float(i) / kAnimationFactor, float(j) / kAnimationFactor);
                        sink += sample.position.x + sample.du.y + sample.dv.z;
                    }
            }
            oursFrame.push_back(msSince(start));

            start = Clock::now();
            far.stencils->UpdateValues(reinterpret_cast<const FarPoint*>(frames[k].data()), refined.data());
            sink += farEvaluate(far, map, refined, planned.subfaceCount(), kAnimationFactor);
            farFrame.push_back(msSince(start));
        }
    Row b = row("(b) update + evaluation at factor 4 (5 x 5 points per sub-face), both on 1 thread: moveVertices + "
                "PlannedCage::evaluate vs UpdateValues + PatchMap + PatchTable::EvaluateBasis", "ms");
    b.ours = median(oursFrame), b.baseline = median(farFrame), b.target = Target::Informative;
    report.rows.push_back(b);
    Row d = row("(d) faces re-planned over all frames (playback must re-plan nothing)", "faces");
    d.ours = double(replanned), d.target = Target::OursAtMost, d.targetValue = 0.0;
    report.rows.push_back(d);
    if (sink == 1.2345) std::fprintf(stderr, " ");  // keeps the evaluations

    // (e) the same frames from an OBJ sequence on disk.
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("quadplan_bench_sequence_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    Cage frameCage = bench.cage;
    for (uint32_t k = 0; k < kFrames; ++k) {
        frameCage.positions = frames[k];
        char file[32];
        std::snprintf(file, sizeof file, "frame_%04u.obj", k + 1);
        if (Status saved = saveObj(frameCage, (dir / file).string()); !saved) return skip(saved.error().message);
    }
    Result<std::vector<SequenceFile>> files = sequenceFiles((dir / "frame_*.obj").string());
    if (!files) return skip(files.error().message);
    std::vector<double> sequenceMs;
    float worst = 0.0f;
    for (uint32_t r = 0; r < rounds; ++r)
        for (uint32_t k = 0; k < files->size(); ++k) {
            const auto start = Clock::now();
            Result<std::vector<glm::vec3>> positions = loadSequenceFrame((*files)[k].path, bench.cage);
            if (!positions) return skip(positions.error().message);
            if (Result<EditReport> moved = planned.moveVertices(all, *positions); !moved) return skip(moved.error().message);
            sequenceMs.push_back(msSince(start));
            for (size_t v = 0; v < positions->size(); ++v) worst = std::max(worst, glm::length((*positions)[v] - frames[k][v]));
        }
    std::filesystem::remove_all(dir);
    Row e = row("(e) a frame from an OBJ sequence: read, topology checked, moveVertices", "ms");
    e.ours = median(sequenceMs), e.target = Target::Informative;
    report.rows.push_back(e);
    report.notes.push_back(name + ": the OBJ sequence's frames read back within " + number(double(worst)) +
                           " of the generated positions (OBJ's decimal text)");

    // (c) frames on the device: the plans scheme at factor 4.
    const PluginCatalog catalog = loadPlugins(pluginDirectory());
    Result<VulkanContext> context = createBenchContext();
    if (!context) return report.notes.push_back(name + ": (c) not measured, " + context.error().message);
    VulkanContext ctx = std::move(context).value();
    {
        const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
        Result<OffscreenTarget> target = createOffscreenTarget(ctx, kRenderSize, kRenderSize, format);
        SchemeSettings settings;
        settings.tessFactor = kAnimationFactor;
        const GpuContext gpu{&ctx, VK_NULL_HANDLE, format, VK_FORMAT_D32_SFLOAT};
        Result<PreparedScheme> prepared =
            target ? prepareScheme(catalog, "plans", planned, analyzeCage(planned.cage(), planned.topology()), settings, gpu, name)
                   : Result<PreparedScheme>(target.error());
        if (!prepared) {
            report.notes.push_back(name + ": (c) not measured, " + prepared.error().message);
        } else {
            const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
            DrawView view;
            view.viewProjection = viewProjection(camera);
            view.eye = camera.eye;
            view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kRenderSize);
            const RenderTarget rt = renderTarget(*target);
            std::vector<double> frameMs;
            DrawStats drawn;
            std::string failure;
            for (uint32_t r = 0; r < rounds + 1 && failure.empty(); ++r)  // the first round warms up
                for (uint32_t k = 0; k < kFrames && failure.empty(); ++k) {
                    const auto start = Clock::now();
                    Status ok = planned.moveVertices(all, frames[k]) ? success() : Status(Error{"moveVertices failed"});
                    if (ok) ok = prepared->instance.updateMoved(all);
                    Result<DrawStats> recorded = DrawStats{};
                    if (ok) ok = submitAndWait(ctx, [&](VkCommandBuffer cmd) { recorded = prepared->instance.record(cmd, rt, view); });
                    if (ok && !recorded) ok = recorded.error();
                    if (ok) drawn = *recorded;
                    if (!ok) failure = ok.error().message;
                    else if (r > 0) frameMs.push_back(msSince(start));
                }
            (void)prepared->instance.destroyGpu();
            if (!failure.empty()) {
                report.notes.push_back(name + ": (c) failed, " + failure);
            } else {
                Row c = row("(c) frame on " + std::string(ctx.deviceName) + " at factor 4: update + updateMoved + draw + submit + wait (plans, " +
                                std::to_string(drawn.triangles) + " triangles)", "ms");
                c.ours = median(frameMs);
                c.target = name == "catmark_car" ? Target::OursAtMost : Target::Informative;
                c.targetValue = 1000.0 / 30.0;
                report.rows.push_back(c);
            }
        }
        if (target) destroyOffscreenTarget(ctx, *target);
    }
    destroyContext(ctx);
}

}  // namespace qp::cli
