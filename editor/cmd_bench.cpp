// `quadplan bench SUITE`: benchmarks of our engine against OpenSubdiv measured in the same run,
// so ratios stay meaningful on a noisy machine. Every figure is the median of R repeats.
// Suites are a table (kSuites); `all` runs them in order. This is a measurement, not a test:
// it exits 0 when targets are missed, and the result column says so. The render suite times
// the GPU paths instead (frame time on the device, against pre-tessellated triangles).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sched.h>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <thread>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include "bench_displacement.h"
#include "bspline_pass.h"
#include "camera.h"
#include "commands.h"
#include "draw_path.h"
#include "generated_cage.h"
#include "gpu_timer.h"
#include "mesh_pass.h"
#include "offscreen_target.h"
#include "obj_io.h"
#include "osd_refiner.h"
#include "plan_pass.h"
#include "planned_cage.h"
#include "vk_commands.h"
#if __has_include("plan_evaluator.h")
#include "plan_evaluator.h"
#define QP_HAVE_PLAN_EVALUATOR 1
#endif

namespace qp::cli {

namespace {

using namespace OpenSubdiv;
using Clock = std::chrono::steady_clock;

// Cages with more faces than this run the expensive rows (a) and (d) at most 5 times, so a large
// --repeats stays within minutes (at the default 5 the ~100k cage takes about a minute).
constexpr uint32_t kLargeCageFaces = 20000;
constexpr uint32_t kLargeCageRepeats = 5;
constexpr uint32_t kGridSide = 16;  // evaluation grid per sub-face

struct BenchArgs {
    std::string suite;
    uint32_t repeats = 5;
    std::string outDir;
    std::optional<uint32_t> generatedFaces;  // unset: the suite's own size (Suite::generatedFaces)
    std::vector<uint32_t> factors{1, 2, 4, 8, 16};  // render suite: uniform tessellation factors
    uint32_t seed = 1;
    bool noShared = false;
    std::vector<std::string> cages;
};

struct BenchCage {
    std::string name;
    Cage cage;
};

enum class Target { RatioAtMost, RatioAtLeast, OursAtMost };

struct Row {
    std::string cage;
    uint32_t faces = 0;
    std::string benchmark;  // says what "ours" and both baselines are
    uint32_t repeats = 0;
    std::string unit;       // of ours and the baselines
    double ours = 0.0;
    double baseline = NAN;  // the target's reference
    double baseline2 = NAN; // a second, informative baseline
    Target target = Target::RatioAtMost;
    double targetValue = 1.0;

    double ratio() const { return ours / baseline; }
    double ratio2() const { return ours / baseline2; }
    bool pass() const {
        switch (target) {
        case Target::RatioAtMost: return ratio() <= targetValue;
        case Target::RatioAtLeast: return ratio() >= targetValue;
        case Target::OursAtMost: return ours <= targetValue;
        }
        return false;
    }
    std::string targetText() const {
        char text[48];
        switch (target) {
        case Target::RatioAtMost: std::snprintf(text, sizeof text, "ratio <= %g", targetValue); break;
        case Target::RatioAtLeast: std::snprintf(text, sizeof text, "ratio >= %g", targetValue); break;
        case Target::OursAtMost: std::snprintf(text, sizeof text, "ours <= %g %s", targetValue, unit.c_str()); break;
        }
        return text;
    }
};

struct Report {
    std::string suite;
    std::vector<std::string> notes;
    std::vector<Row> rows;
    std::string appendix;  // Markdown after the table (the render suite's full measurements)
};

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
            return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

std::string utcNow() {
    std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    return text;
}

std::string number(double value) {
    if (std::isnan(value)) return "";
    char text[32];
    std::snprintf(text, sizeof text, std::abs(value) >= 100.0 ? "%.0f" : "%.3g", value);
    return text;
}

// ---- OpenSubdiv baselines ---------------------------------------------------------------

Far::PatchTableFactory::Options farPatchOptions(const PlanOptions& options) {
    // The options the plan builder uses (plan_builder.cpp), so both sides do the same work.
    Far::PatchTableFactory::Options patchOptions(options.maxDepth);
    patchOptions.useInfSharpPatch = true;
    patchOptions.useSingleCreasePatch = options.useCreaseNodes;
    patchOptions.generateLegacySharpCornerPatches = false;
    patchOptions.generateVaryingTables = false;
    patchOptions.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    return patchOptions;
}

struct FarBuild {
    std::unique_ptr<Far::TopologyRefiner> refiner;
    std::unique_ptr<Far::PatchTable> patches;
    std::unique_ptr<const Far::StencilTable> stencils;  // refined + local points
    double patchesMs = 0.0, stencilsMs = 0.0;          // both from the start
};

// One full rebuild; the patch-table time is taken on the way to the stencil tables, so one
// run gives both baselines.
FarBuild buildFar(const Cage& cage, const PlanOptions& options) {
    FarBuild build;
    auto start = Clock::now();
    auto patchOptions = farPatchOptions(options);
    build.refiner = std::move(createRefiner(cage, "bench").value());
    build.refiner->RefineAdaptive(patchOptions.GetRefineAdaptiveOptions());
    build.patches.reset(Far::PatchTableFactory::Create(*build.refiner, patchOptions));
    build.patchesMs = msSince(start);

    Far::StencilTableFactory::Options stencilOptions;
    stencilOptions.generateOffsets = true;
    stencilOptions.generateIntermediateLevels = true;
    build.stencils.reset(Far::StencilTableFactory::Create(*build.refiner, stencilOptions));
    if (const Far::StencilTable* local = build.patches->GetLocalPointStencilTable(); local && local->GetNumStencils())
        build.stencils.reset(
            Far::StencilTableFactory::AppendLocalPointStencilTable(*build.refiner, build.stencils.get(), local));
    build.stencilsMs = msSince(start);
    return build;
}

// The vertex type Far::StencilTable::UpdateValues needs.
struct FarPoint {
    float x, y, z;
    void Clear(void* = nullptr) { x = y = z = 0.0f; }
    void AddWithWeight(const FarPoint& p, float w) { x += w * p.x; y += w * p.y; z += w * p.z; }
};
static_assert(sizeof(FarPoint) == sizeof(glm::vec3));

struct BfrThroughput {
    double setupAndEvaluateMpts = 0.0, evaluateOnlyMpts = 0.0;
};

// Bfr at the plans' depth; every face is set up (cache on) and its patch points prepared, then
// the same number of points per face as ours: a 16 x 16 grid per Ptex sub-face.
BfrThroughput bfrThroughput(const Cage& cage, const PlanOptions& options, uint32_t repeats, double& sink) {
    auto refiner = std::move(createRefiner(cage, "bench").value());
    Bfr::RefinerSurfaceFactory<>::Options factoryOptions;
    factoryOptions.SetApproxLevelSmooth(int(options.maxDepth)).SetApproxLevelSharp(int(options.maxDepth));
    const float* positions = &cage.positions[0].x;
    std::vector<double> total, evaluateOnly;
    for (uint32_t r = 0; r < repeats; ++r) {
        Bfr::RefinerSurfaceFactory<> factory(*refiner, factoryOptions);  // fresh cache per repeat
        Bfr::Surface<float> surface;
        std::vector<float> patchPoints;
        uint64_t points = 0;
        double evaluateMs = 0.0;
        auto start = Clock::now();
        for (uint32_t f = 0; f < cage.faceCount(); ++f) {
            if (!factory.InitVertexSurface(int(f), &surface)) continue;
            patchPoints.resize(size_t(surface.GetNumPatchPoints()) * 3);
            surface.PreparePatchPoints(positions, 3, patchPoints.data(), 3);
            auto evaluateStart = Clock::now();
            Bfr::Parameterization param = surface.GetParameterization();
            uint32_t subfaces = param.HasSubFaces() ? uint32_t(param.GetFaceSize()) : 1;
            float P[3], du[3], dv[3];
            for (uint32_t k = 0; k < subfaces; ++k)
                for (uint32_t j = 0; j < kGridSide; ++j)
                    for (uint32_t i = 0; i < kGridSide; ++i) {
                        float st[2] = {float(i) / (kGridSide - 1), float(j) / (kGridSide - 1)}, uv[2] = {st[0], st[1]};
                        if (param.HasSubFaces()) param.ConvertNormalizedSubFaceToCoord(int(k), st, uv);
                        surface.Evaluate(uv, patchPoints.data(), 3, P, du, dv);
                        sink += P[0] + du[1] + dv[2];
                    }
            points += subfaces * kGridSide * kGridSide;
            evaluateMs += msSince(evaluateStart);
        }
        double ms = msSince(start);
        total.push_back(double(points) / (ms * 1e3));
        evaluateOnly.push_back(double(points) / (evaluateMs * 1e3));
    }
    return {median(total), median(evaluateOnly)};
}

// ---- the plans suite --------------------------------------------------------------------

// An edge with a face on each side and no crease, near the middle of the edge list.
std::optional<std::pair<uint32_t, uint32_t>> interiorEdge(const PlannedCage& planned) {
    const Topology& topology = planned.topology();
    uint32_t edges = topology.edgeCount();
    for (uint32_t k = 0; k < edges; ++k) {
        uint32_t e = (edges / 2 + k) % edges;
        uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
        if (topology.edgeFaceCount(e) == 2 && planned.cage().edgeSharpness(a, b) == 0.0f) return std::pair{a, b};
    }
    return std::nullopt;
}

void benchPlans(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const PlanOptions options;  // the plans' defaults: depth 6, crease nodes
    const Cage& cage = bench.cage;
    const uint32_t faces = cage.faceCount();
    const uint32_t repeats = args.repeats;
    const uint32_t heavyRepeats = faces > kLargeCageFaces ? std::min(repeats, kLargeCageRepeats) : repeats;
    auto row = [&](std::string benchmark, uint32_t r, std::string unit) {
        Row out;
        out.cage = bench.name;
        out.faces = faces;
        out.benchmark = std::move(benchmark);
        out.repeats = r;
        out.unit = std::move(unit);
        return out;
    };
    std::fprintf(stderr, "bench plans: %s (%u faces)\n", bench.name.c_str(), faces);
    if (auto refiner = createRefiner(cage, bench.name); !refiner) {
        report.notes.push_back(bench.name + ": skipped, " + refiner.error().message);
        return;
    }

    // OpenSubdiv full rebuilds: refiner + adaptive refinement + patch table (+ stencil tables).
    std::vector<double> farPatches, farStencils;
    FarBuild far;
    for (uint32_t r = 0; r < heavyRepeats; ++r) {
        far = FarBuild{};  // free the previous build outside the timing
        far = buildFar(cage, options);
        farPatches.push_back(far.patchesMs);
        farStencils.push_back(far.stencilsMs);
    }
    const double farRebuildMs = median(farPatches), farStencilsMs = median(farStencils);

    // (a) full plan build, with a fresh database each time, then with one holding every plan.
    std::unique_ptr<PlanDatabase> database;
    std::optional<PlannedCage> planned;
    std::vector<double> cold, warm;
    for (uint32_t r = 0; r < heavyRepeats; ++r) {
        planned.reset();
        database = std::make_unique<PlanDatabase>();
        auto start = Clock::now();
        Result<PlannedCage> built = PlannedCage::create(cage, *database, options, bench.name);
        cold.push_back(msSince(start));
        if (!built) {
            report.notes.push_back(bench.name + ": skipped, " + built.error().message);
            return;
        }
        planned.emplace(std::move(built).value());
    }
    for (uint32_t r = 0; r < heavyRepeats; ++r) {
        planned.reset();
        auto start = Clock::now();
        Result<PlannedCage> built = PlannedCage::create(cage, *database, options, bench.name);
        warm.push_back(msSince(start));
        planned.emplace(std::move(built).value());
    }
    const std::string plansNote = " (" + std::to_string(database->size()) + " plans)";
    Row a = row("(a) full plan build, cold: fresh database" + plansNote +
                    " vs OSD refine + patch table; 2nd: OSD + stencil tables", heavyRepeats, "ms");
    a.ours = median(cold), a.baseline = farRebuildMs, a.baseline2 = farStencilsMs;
    report.rows.push_back(a);
    a.benchmark = "(a) full plan build, warm: database already holds every plan vs OSD refine + patch table; "
                  "2nd: OSD + stencil tables";
    a.ours = median(warm);
    report.rows.push_back(a);

    // (b) one edge-sharpness change; cold = a value this edge never had, warm = one it had.
    auto edge = interiorEdge(*planned);
    if (!edge) {
        report.notes.push_back(bench.name + ": no interior uncreased edge, rows (b) and (c) skipped");
    } else {
        auto [ea, eb] = *edge;
        auto timeSharpness = [&](float sharpness, uint32_t& newPlans) {
            auto start = Clock::now();
            EditReport edit = planned->setEdgeSharpness(ea, eb, sharpness).value();
            double ms = msSince(start);
            newPlans += edit.newPlans;
            return ms;
        };
        std::vector<double> coldEdit, warmEdit;
        uint32_t coldNew = 0, warmNew = 0;
        for (uint32_t r = 0; r < repeats; ++r) coldEdit.push_back(timeSharpness(1.0f + 0.0137f * float(r + 1), coldNew));
        const float seen[2] = {2.0f, 3.0f};
        for (float s : seen) timeSharpness(s, warmNew);  // untimed: make both values known
        warmNew = 0;
        for (uint32_t r = 0; r < repeats; ++r) warmEdit.push_back(timeSharpness(seen[r % 2], warmNew));
        uint32_t unused = 0;
        timeSharpness(0.0f, unused);  // back to the original cage for (c) and (d)

        Row b = row("(b) re-plan after one edge-sharpness change, cold: new value (" + std::to_string(coldNew) +
                        " new plans) vs OSD full rebuild as (a); 2nd: + stencil tables",
                    repeats, "ms");
        b.ours = median(coldEdit), b.baseline = farRebuildMs, b.baseline2 = farStencilsMs, b.targetValue = 0.01;
        report.rows.push_back(b);
        b.benchmark = "(b) re-plan after one edge-sharpness change, warm: value seen before (" +
                      std::to_string(warmNew) + " new plans) vs OSD full rebuild as (a); 2nd: + stencil tables";
        b.ours = median(warmEdit);
        report.rows.push_back(b);

        // (c) move one vertex there and back; OpenSubdiv recomputes every refined point.
        const glm::vec3 home = planned->cage().positions[ea];
        const glm::vec3 away = home + 1e-3f * computeBounds(planned->cage()).diagonal() * glm::vec3(0.3f, 0.5f, 0.8f);
        std::vector<double> move;
        for (uint32_t r = 0; r < repeats; ++r) {
            glm::vec3 target = r % 2 ? home : away;
            auto start = Clock::now();
            (void)planned->moveVertices({&ea, 1}, {&target, 1}).value();
            move.push_back(msSince(start));
        }
        (void)planned->moveVertices({&ea, 1}, {&home, 1}).value();
        std::vector<double> update;
        std::vector<FarPoint> refined(size_t(far.stencils->GetNumStencils()));
        const FarPoint* control = reinterpret_cast<const FarPoint*>(cage.positions.data());
        for (uint32_t r = 0; r < repeats; ++r) {
            auto start = Clock::now();
            far.stencils->UpdateValues(control, refined.data());
            update.push_back(msSince(start));
        }
        Row c = row("(c) update after moving one vertex vs OSD StencilTable::UpdateValues, whole mesh", repeats, "ms");
        c.ours = median(move), c.baseline = median(update), c.target = Target::OursAtMost, c.targetValue = 1.0;
        report.rows.push_back(c);
    }
    far = FarBuild{};

    // (d) throughput over a 16 x 16 grid per sub-face; the sums keep the results alive.
    double sink = 0.0;
    const float step = 1.0f / float(kGridSide - 1);
    std::vector<double> single;
    for (uint32_t r = 0; r < heavyRepeats; ++r) {
        uint64_t points = 0;
        auto start = Clock::now();
        for (uint32_t s = 0; s < planned->subfaceCount(); ++s) {
            if (!planned->hasSurface(s)) continue;
            for (uint32_t j = 0; j < kGridSide; ++j)
                for (uint32_t i = 0; i < kGridSide; ++i) {
                    LimitSample sample = planned->evaluate(s, float(i) * step, float(j) * step);
                    sink += sample.position.x + sample.du.y + sample.dv.z;
                }
            points += kGridSide * kGridSide;
        }
        single.push_back(double(points) / (msSince(start) * 1e3));
    }
    BfrThroughput bfr = bfrThroughput(planned->cage(), options, heavyRepeats, sink);
    Row d = row("(d) evaluate 16x16 per sub-face, 1 thread: PlannedCage::evaluate vs Bfr evaluate only (levels 6/6); "
                "2nd: Bfr setup + evaluate",
                heavyRepeats, "Mpts/s");
    d.ours = median(single), d.baseline = bfr.evaluateOnlyMpts, d.baseline2 = bfr.setupAndEvaluateMpts;
    d.target = Target::RatioAtLeast;
    report.rows.push_back(d);
#ifdef QP_HAVE_PLAN_EVALUATOR
    std::vector<SampleRequest> requests;
    for (uint32_t s = 0; s < planned->subfaceCount(); ++s)
        if (planned->hasSurface(s))
            for (uint32_t j = 0; j < kGridSide; ++j)
                for (uint32_t i = 0; i < kGridSide; ++i) requests.push_back({s, float(i) * step, float(j) * step});
    // Chunks bound the output buffer (36 bytes a sample) on the large cage.
    constexpr size_t kChunk = size_t(1) << 20;
    std::vector<LimitSample> out(std::min(kChunk, requests.size()));
    std::vector<double> batched;
    for (uint32_t r = 0; r < heavyRepeats; ++r) {
        auto start = Clock::now();
        for (size_t first = 0; first < requests.size(); first += kChunk) {
            size_t count = std::min(kChunk, requests.size() - first);
            evaluateBatch(*planned, std::span(requests).subspan(first, count), std::span(out).first(count));
            sink += out[count - 1].position.x;
        }
        batched.push_back(double(requests.size()) / (msSince(start) * 1e3));
    }
    d.benchmark = "(d) evaluate 16x16 per sub-face, all threads: evaluateBatch (TBB) vs Bfr evaluate only, 1 thread; "
                  "2nd: Bfr setup + evaluate";
    d.ours = median(batched);
    report.rows.push_back(d);
#else
    report.notes.push_back("core/plan_evaluator.h is not in this build: no evaluateBatch row");
#endif
    if (sink == 0.123) std::fprintf(stderr, " ");
}

// ---- the render suite -------------------------------------------------------------------
// Frame time of PlanPass's two paths (plan_pass.h) against the same surface pre-tessellated
// into a triangle buffer (the fastest this device can draw it) and against plain B-spline
// patches through the tessellator (bspline_pass.h), at uniform factors, into an offscreen
// target. Wall = the submitAndWait round trip; GPU = timestamps around the recorded commands.

// ~10k faces: at factor 16 the 100k cage would need ~50 M triangles a frame (seconds each on
// lavapipe, minutes for the suite) and a grid buffer of ~700 MB, over lavapipe's 128 MiB
// storage-buffer range; 20k faces is just over it too.
constexpr uint32_t kRenderGeneratedFaces = 10000;
constexpr uint32_t kRenderSize = 512;
constexpr uint32_t kRenderWarmups = 2;
constexpr uint32_t kRenderTargetFactor = 8;
constexpr double kRenderTargetRatio = 1.5;  // issue: default path within 1.5x of pre-tessellated

struct FrameTime {
    double wallMs = NAN, gpuMs = NAN;
    uint32_t coveredPixels = 0;  // not the background in the last frame: a sanity check
};

// Lavapipe unless QUADPLAN_VK_DEVICE names a device (as the render tests). Validation stays
// off: it would dominate the timings.
Result<VulkanContext> createBenchContext() {
    ContextOptions options;
    if (const char* device = std::getenv("QUADPLAN_VK_DEVICE"); device && device[0]) {
        options.forceDevice = device;
    } else if (const char* icd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"; std::filesystem::exists(icd)) {
        setenv("VK_ICD_FILENAMES", icd, 1);  // before the loader looks for drivers
        setenv("VK_DRIVER_FILES", icd, 1);
    }
    return createContext(options);
}

// Median wall and GPU time of `repeats` frames after the warm-up ones (pipeline JIT, caches).
Result<FrameTime> timeFrames(const VulkanContext& ctx, const GpuTimer& timer, const OffscreenTarget& target,
                             uint32_t repeats, const std::function<void(VkCommandBuffer)>& record) {
    std::vector<double> wall, gpu;
    for (uint32_t i = 0; i < kRenderWarmups + repeats; ++i) {
        auto start = Clock::now();
        Status status = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            beginGpuTimer(cmd, timer);
            record(cmd);
            endGpuTimer(cmd, timer);
        });
        const double ms = msSince(start);
        if (!status) return status.error();
        Result<double> gpuMs = readGpuTimerMs(ctx, timer);
        if (!gpuMs) return gpuMs.error();
        if (i >= kRenderWarmups) wall.push_back(ms), gpu.push_back(*gpuMs);
    }
    FrameTime time{median(wall), median(gpu), 0};
    Result<std::vector<uint8_t>> pixels = readPixels(ctx, target);
    if (!pixels) return pixels.error();
    const uint32_t* rgba = reinterpret_cast<const uint32_t*>(pixels->data());
    for (size_t p = 0; p < pixels->size() / 4; ++p) time.coveredPixels += rgba[p] != rgba[0];  // corner: background
    return time;
}

std::string msCell(const FrameTime& t) { return number(t.wallMs) + " / " + number(t.gpuMs); }
std::string ratioCell(const FrameTime& t, const FrameTime& base) {
    return number(t.wallMs / base.wallMs) + " / " + number(t.gpuMs / base.gpuMs);
}

void benchRender(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench render: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto skip = [&](const std::string& why) { report.notes.push_back(name + ": skipped, " + why); };
    if (report.appendix.empty()) {  // first cage: other work on the machine skews a CPU device's timings
        std::string one, five, fifteen;
        std::ifstream("/proc/loadavg") >> one >> five >> fifteen;
        report.notes.push_back("load average at the start (1, 5, 15 min): " + one + " " + five + " " + fifteen);
    }
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(bench.cage, database, PlanOptions{}, name);
    if (!planned) return skip(planned.error().message);
    Result<VulkanContext> created = createBenchContext();
    if (!created) return skip(created.error().message);
    VulkanContext ctx = std::move(created).value();

    // Everything below is destroyed at the end, whatever failed on the way.
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    OffscreenTarget target;
    PlanPass pass;
    MeshPass meshPass;
    BSplinePass bspline;
    GpuTimer timer;
    PlanBuffers buffers;
    std::string error;
    auto take = [&](auto result, auto& out) {
        if (result) out = std::move(result).value();
        else if (error.empty()) error = result.error().message;
        return bool(result);
    };
    take(createOffscreenTarget(ctx, kRenderSize, kRenderSize, format), target) &&
        take(createPlanPass(ctx, VK_NULL_HANDLE, format), pass) &&
        take(createMeshPass(ctx, VK_NULL_HANDLE, format), meshPass) &&
        take(createBSplinePass(ctx, VK_NULL_HANDLE, pass), bspline) && take(createGpuTimer(ctx), timer) &&
        take(uploadPlans(ctx, *planned), buffers);

    const DrawPath picked = resolveDrawPath(DrawPath::Auto, ctx);
    const uint32_t subfaces = uint32_t(buffers.data.subfaces.size());
    std::string table = "### render: " + name + " (" + std::to_string(bench.cage.faceCount()) + " faces, " +
                        std::to_string(subfaces) + " drawn sub-faces)\n\n"
                        "| factor | grid factor | triangles | pre-tessellated ms | tess path ms | tess / pre | "
                        "grid path ms | grid / pre | B-spline ms | B-spline / pre |\n"
                        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::optional<FrameTime> tessAtTarget, gridAtTarget, preAtTarget;
    bool coverageDiffers = false;
    if (error.empty()) {
        bindPlanBuffers(ctx, pass, buffers);
        const Bounds bounds = computeBounds(bench.cage);
        const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kRenderSize);
        const MeshView meshView{view.viewProjection, camera.eye, view.background};
        bool anyNgon = false;  // prepareGrid rounds odd factors up to even ones then
        for (uint32_t i = 0; i < subfaces; ++i) anyNgon |= gridFactorOf(buffers.data, i, 2) == 1;

        for (uint32_t factor : args.factors) {
            const TessellationSettings settings{factor, 8.0f};
            auto measure = [&](const std::function<void(VkCommandBuffer)>& record) {
                Result<FrameTime> t = timeFrames(ctx, timer, target, args.repeats, record);
                if (!t && error.empty()) error = t.error().message;
                return t ? *t : FrameTime{};
            };
            // (1) tessellated path, stencil compute pass included.
            FrameTime tess = measure([&](VkCommandBuffer cmd) { recordTessellated(cmd, pass, buffers, renderTarget(target), view, settings); });
            // (2) grid path, if its vertex buffer fits the device's storage-buffer range.
            const uint32_t gridFactor = anyNgon && factor % 2 ? factor + 1 : factor;
            const VkDeviceSize gridBytes = VkDeviceSize(gridVerticesPerSubface(gridFactor)) * subfaces * sizeof(GridVertex);
            FrameTime grid, pre;
            uint32_t triangles = 0;
            if (gridBytes + 16 > ctx.properties.limits.maxStorageBufferRange) {
                report.notes.push_back(name + ", factor " + std::to_string(factor) + ": no grid or pre-tessellated rows, the grid (" +
                                       std::to_string(gridBytes >> 20) + " MiB) exceeds maxStorageBufferRange");
            } else if (Status prepared = prepareGrid(ctx, pass, buffers, factor); !prepared) {
                if (error.empty()) error = prepared.error().message;
            } else {
                grid = measure([&](VkCommandBuffer cmd) { recordGrid(cmd, pass, buffers, renderTarget(target), view); });
                // (3) the grid evaluated once, copied into an ordinary vertex buffer (the grid
                // buffer is storage-only) with its index buffer: then only the drawing is timed.
                (void)submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGridEvaluation(cmd, pass, buffers); });
                const auto* vertices = static_cast<const MeshVertex*>(buffers.grid.data);
                const auto* indices = static_cast<const uint32_t*>(pass.gridIndices.data);
                const size_t indexCount = pass.gridIndices.size / sizeof(uint32_t);
                triangles = uint32_t(indexCount / 3);
                Result<GpuMesh> mesh = uploadMesh(ctx, {vertices, gridBytes / sizeof(MeshVertex)}, {indices, indexCount});
                if (mesh) {
                    const MeshDraw draw{&*mesh};
                    pre = measure([&](VkCommandBuffer cmd) { recordMeshPass(cmd, meshPass, renderTarget(target), meshView, {&draw, 1}); });
                    destroyMesh(ctx, *mesh);
                } else if (error.empty()) {
                    error = mesh.error().message;
                }
            }
            // (4) plain B-spline patches; the control points are those the grid evaluation (or
            // the tessellated path) just computed for this factor.
            FrameTime plain = measure([&](VkCommandBuffer cmd) {
                recordBSplinePatches(cmd, bspline, pass, buffers, renderTarget(target), view, settings);
            });
            if (!error.empty()) break;

            // The grid (and so the pre-tessellated mesh) is coarser than factor 1 on cages with
            // non-quads: compare only like with like.
            for (const FrameTime* t : {&tess, &grid})
                if (gridFactor == factor && pre.coveredPixels && std::abs(double(t->coveredPixels) - pre.coveredPixels) > 0.02 * pre.coveredPixels)
                    coverageDiffers = true;
            table += "| " + std::to_string(factor) + " | " + (triangles ? std::to_string(gridFactor) : "") + " | " +
                     (triangles ? std::to_string(triangles) : "") + " | " + msCell(pre) + " | " + msCell(tess) + " | " +
                     ratioCell(tess, pre) + " | " + msCell(grid) + " | " + ratioCell(grid, pre) + " | " + msCell(plain) +
                     " | " + ratioCell(plain, pre) + " |\n";
            std::fprintf(stderr, "  factor %u: pre %s, tess %s, grid %s, B-spline %s ms (wall / GPU); covered pixels %u %u %u %u\n",
                         factor, msCell(pre).c_str(), msCell(tess).c_str(), msCell(grid).c_str(), msCell(plain).c_str(),
                         pre.coveredPixels, tess.coveredPixels, grid.coveredPixels, plain.coveredPixels);
            if (factor == kRenderTargetFactor) tessAtTarget = tess, gridAtTarget = grid, preAtTarget = pre;
        }
    }
    if (!error.empty()) report.notes.push_back(name + ": stopped, " + error);

    if (tessAtTarget && preAtTarget && !std::isnan(preAtTarget->wallMs)) {
        // The target: the default path within 1.5x of pre-tessellated triangles.
        const FrameTime& chosen = picked == DrawPath::Grid ? *gridAtTarget : *tessAtTarget;
        const FrameTime& other = picked == DrawPath::Grid ? *tessAtTarget : *gridAtTarget;
        const DrawPath otherPath = picked == DrawPath::Grid ? DrawPath::Tessellated : DrawPath::Grid;
        for (bool wall : {true, false}) {
            Row r;
            r.cage = name;
            r.faces = bench.cage.faceCount();
            r.benchmark = std::string("frame at factor 8, ") + (wall ? "wall" : "GPU") + ": default path (" +
                          drawPathName(picked) + ", what auto picks) vs pre-tessellated triangles; 2nd: the " +
                          drawPathName(otherPath) + " path";
            r.repeats = args.repeats;
            r.unit = "ms";
            r.ours = wall ? chosen.wallMs : chosen.gpuMs;
            r.baseline = wall ? preAtTarget->wallMs : preAtTarget->gpuMs;
            r.baseline2 = wall ? other.wallMs : other.gpuMs;
            r.targetValue = kRenderTargetRatio;
            report.rows.push_back(r);
        }
        const bool faster = chosen.wallMs <= other.wallMs;
        report.notes.push_back(name + ": auto picks " + drawPathName(picked) + " on '" + ctx.deviceName + "'; at factor 8 it is " +
                               (faster ? "the faster path" : "NOT the faster path") + " (" + drawPathName(picked) + " " +
                               number(chosen.wallMs) + " ms vs " + drawPathName(otherPath) + " " + number(other.wallMs) +
                               " ms, wall)");
    } else if (error.empty()) {
        report.notes.push_back(name + ": factor 8 not measured (--factors): no target rows");
    }
    if (coverageDiffers)
        report.notes.push_back(name + ": WARNING: a plans path covers more than 2% more or fewer pixels than the "
                                      "pre-tessellated triangles: the paths may not draw the same surface");
    if (report.appendix.empty())
        report.appendix = "Render suite: " + std::to_string(kRenderSize) + "x" + std::to_string(kRenderSize) +
                          " offscreen target, camera framing the cage, uniform factors; median of R frames after " +
                          std::to_string(kRenderWarmups) + " warm-up frames. Cells: wall / GPU ms (wall = "
                          "submitAndWait round trip, GPU = timestamps); ratios are each path / pre-tessellated "
                          "triangles, wall / GPU. Pre-tessellated = the grid path's vertices evaluated once, drawn by "
                          "MeshPass. B-spline = one bicubic patch per sub-face through the tessellator (a cost "
                          "baseline, not the exact surface). Grid factor: the grid path rounds odd factors up on "
                          "cages with non-quads.\n\n";
    report.appendix += table + "\n";

    vkDeviceWaitIdle(ctx.device);
    destroyPlanBuffers(ctx, buffers);
    destroyGpuTimer(ctx, timer);
    destroyBSplinePass(ctx, bspline);
    destroyMeshPass(ctx, meshPass);
    destroyPlanPass(ctx, pass);
    destroyOffscreenTarget(ctx, target);
    destroyContext(ctx);
}

std::string benchSharedDir() {
#ifdef QUADPLAN_SHARED_DIR
    return QUADPLAN_SHARED_DIR;
#else
    return "";
#endif
}

// The suite's cages: catmark_car from ../shared, the generated cage, then --cage files.
// Missing shared files are a note; a --cage that does not load is an error.
Result<std::vector<BenchCage>> loadBenchCages(const BenchArgs& args, uint32_t defaultFaces, Report& report) {
    std::vector<BenchCage> cages;
    if (args.noShared) {
        report.notes.push_back("catmark_car: skipped (--no-shared)");
    } else {
        std::string path = benchSharedDir() + "/shapes/catmark_car.obj";
        if (Result<Cage> car = loadObj(path); car)
            cages.push_back({"catmark_car", std::move(car).value()});
        else
            report.notes.push_back("catmark_car: skipped, " + car.error().message);
    }
    if (const uint32_t faces = args.generatedFaces.value_or(defaultFaces); faces > 0) {
        cages.push_back({"generated (" + std::to_string(faces) + ", seed " + std::to_string(args.seed) + ")",
                         makeBenchmarkCage(faces, args.seed)});
    }
    for (const std::string& path : args.cages) {
        Result<Cage> cage = loadObj(path);
        if (!cage) return cage.error();
        cages.push_back({std::filesystem::path(path).filename().string(), std::move(cage).value()});
    }
    return cages;
}

// ---- output ----------------------------------------------------------------------------

std::string markdown(const Report& report, const BenchArgs& args) {
    cpu_set_t cpus;
    int threads = sched_getaffinity(0, sizeof cpus, &cpus) == 0 ? CPU_COUNT(&cpus) : int(std::thread::hardware_concurrency());
    std::string md = "## quadplan bench " + report.suite + "\n\n";
    md += "- machine: " + std::to_string(threads) + " cores (nproc), " + cpuModel() + "; " + utcNow() + "\n";
#ifdef NDEBUG
    md += "- build: optimised, assertions off; OpenSubdiv " + std::to_string(OPENSUBDIV_VERSION_NUMBER) + "\n";
#else
    md += "- build: ASSERTIONS ON (not a Release build): timings are pessimistic\n";
#endif
    if (report.suite == "plans") {
        md += "- medians of R repeats (--repeats " + std::to_string(args.repeats) + "; cages over " +
              std::to_string(kLargeCageFaces) + " faces run (a) and (d) " + std::to_string(kLargeCageRepeats) +
              " times at most); ratio = ours / baseline\n";
        md += "- ours plans faces on all cores (TBB); OpenSubdiv and Bfr run on one thread\n";
    }
    for (const std::string& note : report.notes) md += "- " + note + "\n";
    md += "\n| cage | faces | benchmark | R | ours | baseline | ratio | target | result | 2nd baseline | 2nd ratio |\n";
    md += "|---|---:|---|---:|---:|---:|---:|---|---|---:|---:|\n";
    for (const Row& r : report.rows) {
        md += "| " + r.cage + " | " + std::to_string(r.faces) + " | " + r.benchmark + " | " + std::to_string(r.repeats) +
              " | " + number(r.ours) + " " + r.unit + " | " + number(r.baseline) + " " + r.unit + " | " +
              number(r.ratio()) + " | " + r.targetText() + " | " + (r.pass() ? "pass" : "**miss**") + " | " +
              (std::isnan(r.baseline2) ? "" : number(r.baseline2) + " " + r.unit) + " | " + number(r.ratio2()) + " |\n";
    }
    if (!report.appendix.empty()) md += "\n" + report.appendix;
    return md;
}

std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

std::string csv(const Report& report) {
    std::string out = "suite,cage,faces,benchmark,repeats,unit,ours,baseline,ratio,target,result,baseline2,ratio2\n";
    for (const Row& r : report.rows)
        out += report.suite + "," + csvField(r.cage) + "," + std::to_string(r.faces) + "," + csvField(r.benchmark) + "," +
               std::to_string(r.repeats) + "," + r.unit + "," + number(r.ours) + "," + number(r.baseline) + "," +
               number(r.ratio()) + "," + csvField(r.targetText()) + "," + (r.pass() ? "pass" : "miss") + "," +
               number(r.baseline2) + "," + number(r.ratio2()) + "\n";
    return out;
}

// ---- the displacement suite (measurements in bench_displacement.cpp) --------------------

constexpr uint32_t kDisplacementResolution = 16;  // per sub-face
constexpr uint32_t kDabsPerRepeat = 20;           // dabs are cheap: many per repeat

void benchDisplacement(const BenchCage& bench, const BenchArgs& args, Report& report) {
    std::fprintf(stderr, "bench displacement: %s (%u faces)\n", bench.name.c_str(), bench.cage.faceCount());
    const uint32_t dabs = args.repeats * kDabsPerRepeat;
    DisplacementBenchResult result = measureDisplacementDabs(bench.cage, kDisplacementResolution, dabs, args.seed);
    if (!result.error.empty()) report.notes.push_back(bench.name + ": " + result.error);
    if (result.dabs.empty()) return;
    report.notes.push_back(bench.name + ": resolution " + std::to_string(result.resolution) + " on every sub-face, " +
                           std::to_string(result.samples) + " samples (" + number(result.samples * 4.0 / 1048576.0) +
                           " MiB); smooth falloff, dabs at random sample positions; the samples cache is built once per "
                           "layout");
    for (const DabMeasurement& m : result.dabs) {
        Row r;
        r.cage = bench.name;
        r.faces = bench.cage.faceCount();
        r.benchmark = std::string(brushKindName(m.brush)) + " dab, radius " + number(m.radius) + ": CPU update " + number(m.updateMs) + " ms + upload copy " +
                      number(m.uploadMs) + " ms of " + number(m.bytes / 1024.0) + " KiB (" + number(m.samplesReached) +
                      " samples in reach) vs copying the whole buffer; 2nd: building the samples cache";
        r.repeats = m.repeats;
        r.unit = "ms";
        r.ours = m.totalMs;
        r.baseline = result.fullUploadMs;
        r.baseline2 = result.cacheBuildMs;
        r.target = Target::OursAtMost;
        r.targetValue = 5.0;
        report.rows.push_back(r);
    }
}

// ---- suites ----------------------------------------------------------------------------

struct Suite {
    const char* name;
    void (*benchCage)(const BenchCage&, const BenchArgs&, Report&);
    uint32_t generatedFaces;  // size of the generated cage unless --generated-faces says otherwise
};

constexpr Suite kSuites[] = {
    {"plans", benchPlans, 100000},
    {"render", benchRender, kRenderGeneratedFaces},
    {"displacement", benchDisplacement, 2000},
};

int runSuite(const Suite& suite, const BenchArgs& args) {
    Report report;
    report.suite = suite.name;
    Result<std::vector<BenchCage>> cages = loadBenchCages(args, suite.generatedFaces, report);
    if (!cages) {
        std::fprintf(stderr, "error: %s\n", cages.error().message.c_str());
        return 1;
    }
    if (cages->empty()) report.notes.push_back("no cages to benchmark");
    for (const BenchCage& cage : *cages) suite.benchCage(cage, args, report);

    std::string md = markdown(report, args);
    std::printf("%s\n", md.c_str());
    std::fflush(stdout);
    if (!args.outDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(args.outDir, ec);
        std::ofstream(args.outDir + "/" + suite.name + ".md") << md;
        std::ofstream csvFile(args.outDir + "/" + suite.name + ".csv");
        csvFile << csv(report);
        if (!csvFile) {
            std::fprintf(stderr, "error: cannot write to %s\n", args.outDir.c_str());
            return 1;
        }
    }
    return 0;
}

int runBench(const BenchArgs& args) {
    for (const Suite& suite : kSuites)
        if (args.suite == "all" || args.suite == suite.name)
            if (int status = runSuite(suite, args); status != 0) return status;
    return 0;
}

}  // namespace

void registerBench(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("bench", "Benchmark against OpenSubdiv in the same run; prints a Markdown table");
    auto args = std::make_shared<BenchArgs>();
    std::vector<std::string> suites{"all"};
    for (const Suite& suite : kSuites) suites.push_back(suite.name);
    cmd->add_option("suite", args->suite, "Suite to run")->required()->check(CLI::IsMember(suites));
    cmd->add_option("--repeats", args->repeats, "Repeats per measurement (the median is reported)")
        ->check(CLI::Range(1u, 1000u));
    cmd->add_option("--out", args->outDir, "Also write SUITE.md and SUITE.csv into this directory");
    cmd->add_option("--generated-faces", args->generatedFaces,
                    "Faces of the generated torus cage (0: none; default: plans 100000, render " +
                        std::to_string(kRenderGeneratedFaces) + ", displacement 2000)");
    cmd->add_option("--factors", args->factors, "render: uniform tessellation factors (default 1,2,4,8,16)")
        ->delimiter(',')
        ->check(CLI::Range(1u, 64u));
    cmd->add_option("--seed", args->seed, "Seed of the generated cage");
    cmd->add_flag("--no-shared", args->noShared, "Skip catmark_car from ../shared/shapes");
    cmd->add_option("--cage", args->cages, "Also benchmark this cage (.obj); with --no-shared --generated-faces 0 "
                                           "only these");
    cmd->callback([args, &exitCode] { exitCode = runBench(*args); });
}

}  // namespace qp::cli
