// `quadplan bench SUITE`: benchmarks of our engine against OpenSubdiv measured in the same run,
// so ratios stay meaningful on a noisy machine. Every figure is the median of R repeats.
// Suites are a table (kSuites); `all` runs them in order. This is a measurement, not a test:
// it exits 0 when targets are missed, and the result column says so. The render suite times
// the GPU paths instead (frame time on the device, against pre-tessellated triangles); the
// schemes suite times every scheme plugin per uniform factor against the same baseline.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sched.h>
#include <filesystem>
#include <functional>
#include <fstream>
#include <memory>
#include <optional>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include "bench_displacement.h"
#include "bench_editor_edits.h"
#include "bench_stats.h"
#include "bspline_pass.h"
#include "camera.h"
#include "commands.h"
#include "draw_path.h"
#include "edit_history.h"
#include "generated_cage.h"
#include "mesh_pass.h"
#include "offscreen_target.h"
#include "obj_io.h"
#include "osd_refiner.h"
#include "plan_pass.h"
#include "plan_memory.h"
#include "planned_cage.h"
#include "scheme_host.h"
#include "topology_edits.h"
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

    double pairedRatio = NAN;  // when set: the median of per-round ratios, measured back to back

    double ratio() const { return std::isnan(pairedRatio) ? ours / baseline : pairedRatio; }
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

// One point of a chart (quadplan.bench_report draws SUITE_series.csv): `chart` names the
// picture, `series` a line or bar group in it.
struct SeriesPoint {
    std::string chart, x, series;
    double value = NAN;
    std::string unit;
};

struct Report {
    std::string suite;
    std::vector<std::string> notes;
    std::vector<Row> rows;
    std::vector<SeriesPoint> series;
    std::string appendix;  // Markdown after the table (the render suite's full measurements)
};

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
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

    // Memory in the columns of the paper's Table 4 (render/plan_memory.h).
    {
        const PlanMemory mem = measurePlanMemory(*planned);
        auto mib = [](uint64_t bytes) { return number(double(bytes) / 1048576.0); };
        if (report.appendix.empty())
            report.appendix = "GPU memory in the columns of Brainerd et al. 2016, Table 4 (MiB; render/plan_memory.h: "
                              "counted from the arrays the renderer uploads; scratch = the control points the stencil "
                              "pass writes every frame):\n\n| cage | faces | vertex | index | plans | quadtree | stencils | "
                              "scratch | total |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        const uint64_t total = mem.vertexBytes + mem.indexBytes + mem.quadtreeBytes + mem.stencilBytes + mem.scratchBytes;
        report.appendix += "| " + bench.name + " | " + std::to_string(faces) + " | " + mib(mem.vertexBytes) + " | " +
                           mib(mem.indexBytes) + " | " + std::to_string(mem.plans) + " | " + mib(mem.quadtreeBytes) +
                           " | " + mib(mem.stencilBytes) + " | " + mib(mem.scratchBytes) + " | " + mib(total) + " |\n";
        const std::pair<const char*, uint64_t> columns[] = {{"vertex", mem.vertexBytes}, {"index", mem.indexBytes},
                                                            {"quadtree", mem.quadtreeBytes}, {"stencils", mem.stencilBytes},
                                                            {"scratch", mem.scratchBytes}};
        for (auto [column, bytes] : columns)
            report.series.push_back({"memory (Table 4)", bench.name, column, double(bytes) / 1048576.0, "MiB"});
    }

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
// Frame times of PlanPass's paths (plan_pass.h, draw_path.h) against the same surface
// pre-tessellated into a triangle buffer (the fastest this device can draw it) and against
// plain B-spline patches through the tessellator (bspline_pass.h), at uniform factors, into an
// offscreen target. A frame's time is the wall time of everything the host does for it (CPU
// evaluation included) and of the submitAndWait round trip.
//
// Frames are measured in rounds: each round draws one frame of every kind back to back, and
// ratios are medians of the per-round ratios. Other work on the machine then slows a whole
// round rather than one kind of frame (measuring each kind in a block of its own made the
// baseline jump by 2-3x between factors on a busy machine). The baseline is drawn twice a
// round, first and halfway, and the round's ratios use the mean of the two.

// ~10k faces: at factor 16 the 100k cage would need ~50 M triangles a frame (seconds each on
// lavapipe, minutes for the suite) and a grid buffer of ~700 MB, over lavapipe's 128 MiB
// storage-buffer range; 20k faces is just over it too.
constexpr uint32_t kRenderGeneratedFaces = 10000;
constexpr uint32_t kRenderSize = 512;
constexpr uint32_t kRenderWarmups = 2;  // rounds: pipeline JIT, first touch of new buffers
constexpr uint32_t kRenderTargetFactor = 8;
constexpr double kRenderTargetRatio = 1.5;  // issue: default path within 1.5x of pre-tessellated

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

std::string loadAverage() {
    std::string one, five, fifteen;
    std::ifstream("/proc/loadavg") >> one >> five >> fifteen;
    return one + " " + five + " " + fifteen;
}

// One kind of frame: `host` runs first (untimed when `hostTimed` is false), then `record` is
// submitted and waited for; both count.
struct FrameKind {
    std::string name;
    std::function<Status()> host;
    std::function<void(VkCommandBuffer)> record;
    bool baseline = false;       // pre-tessellated: the round's reference
    std::vector<double> ms, ratios;
    std::vector<double> cpuRatios;  // the same with the process's CPU time instead of wall time
    uint32_t coveredPixels = 0;  // not the background in the last round: a sanity check

    double medianMs() const { return ms.empty() ? NAN : median(ms); }
    double medianRatio() const { return ratios.empty() ? NAN : median(ratios); }
    double medianCpuRatio() const { return cpuRatios.empty() ? NAN : median(cpuRatios); }
};

// CPU time of this process, every thread (lavapipe's and TBB's included), in ms.
double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

std::string cell(const FrameKind& k, bool withRatio = true) {
    if (k.ms.empty()) return "";
    return number(k.medianMs()) + (withRatio ? " (" + number(k.medianRatio()) + "x)" : "");
}

// The default path's cells also give the CPU-time ratio, which other work on the machine
// hardly moves.
std::string cellWithCpu(const FrameKind& k) {
    if (k.ms.empty()) return "";
    return number(k.medianMs()) + " (" + number(k.medianRatio()) + "x; CPU " + number(k.medianCpuRatio()) + "x)";
}

// The render and schemes suites' baseline at uniform `factor`: the plans grid evaluated once
// on the CPU and copied into a mesh of its own (replacing `mesh`), drawn with
// recordShadedTriangles, i.e. the limit of this device for those triangles.
Status preparePreTessellated(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, const PlannedCage& planned,
                             uint32_t factor, GpuMesh& mesh) {
    if (Status s = prepareGrid(ctx, pass, buffers, factor); !s) return s;
    evaluateGridOnCpu(planned, buffers);
    const GridLayout& layout = buffers.gridLayout;
    destroyMesh(ctx, mesh);
    Result<GpuMesh> uploaded =
        uploadMesh(ctx, {static_cast<const MeshVertex*>(buffers.grid.data), layout.slotCount()}, layout.indices);
    if (!uploaded) return uploaded.error();
    mesh = std::move(uploaded).value();
    return success();
}

void benchRender(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench render: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto skip = [&](const std::string& why) { report.notes.push_back(name + ": skipped, " + why); };
    PlanDatabase database;
    Result<PlannedCage> created = PlannedCage::create(bench.cage, database, PlanOptions{}, name);
    if (!created) return skip(created.error().message);
    PlannedCage& planned = *created;
    Result<VulkanContext> context = createBenchContext();
    if (!context) return skip(context.error().message);
    VulkanContext ctx = std::move(context).value();
    report.notes.push_back(name + ": load average at the start (1, 5, 15 min): " + loadAverage());

    // Everything below is destroyed at the end, whatever failed on the way.
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    OffscreenTarget target;
    PlanPass pass;
    BSplinePass bspline;
    PlanBuffers buffers;
    GpuMesh preMesh;
    std::string error;
    auto take = [&](auto result, auto& out) {
        if (result) out = std::move(result).value();
        else if (error.empty()) error = result.error().message;
        return bool(result);
    };
    take(createOffscreenTarget(ctx, kRenderSize, kRenderSize, format), target) &&
        take(createPlanPass(ctx, VK_NULL_HANDLE, format), pass) &&
        take(createBSplinePass(ctx, VK_NULL_HANDLE, pass), bspline) && take(uploadPlans(ctx, planned), buffers);

    const DrawPath picked = resolveDrawPath(DrawPath::Auto, ctx);
    const uint32_t subfaces = uint32_t(buffers.data.subfaces.size());
    std::string defaultTable =
        "### render: " + name + " (" + std::to_string(bench.cage.faceCount()) + " faces, " + std::to_string(subfaces) +
        " drawn sub-faces), the default path (" + drawPathName(picked) + ")\n\n"
        "| factor | grid factor | triangles | pre-tessellated ms | view frame ms | drag frame ms | edit frame ms |\n"
        "|---:|---:|---:|---:|---:|---:|---:|\n";
    std::string pathTable = "### render: " + name + ", every path (ms, and the ratio to pre-tessellated)\n\n"
                            "| factor | tess view | tess edit | grid (compute) edit | cpu edit | grid / cpu view | "
                            "grid drag | cpu drag | B-spline |\n"
                            "|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    bool coverageDiffers = false;
    if (error.empty()) {
        bindPlanBuffers(ctx, pass, buffers);
        const Bounds bounds = computeBounds(bench.cage);
        const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kRenderSize);
        const RenderTarget rt = renderTarget(target);

        // The drag: an interior vertex moving there and back, as under the editor's mouse.
        const uint32_t dragged = [&] {
            const Topology& topology = planned.topology();
            for (uint32_t k = 0; k < planned.cage().vertexCount(); ++k) {
                uint32_t v = (planned.cage().vertexCount() / 2 + k) % planned.cage().vertexCount();
                if (topology.vertexFaceCount(v) >= 3) return v;
            }
            return 0u;
        }();
        const glm::vec3 home = planned.cage().positions[dragged];
        const glm::vec3 away = home + 2e-3f * bounds.diagonal() * glm::vec3(0.3f, 0.5f, 0.8f);
        bool dragAway = true;
        auto drag = [&]() -> Status {
            const glm::vec3 to = dragAway ? away : home;
            dragAway = !dragAway;
            Result<EditReport> moved = planned.moveVertices({&dragged, 1}, {&to, 1});
            return moved ? success() : Status(moved.error());
        };

        for (uint32_t factor : args.factors) {
            const TessellationSettings settings{factor, 8.0f};
            // The grid and, from it, the pre-tessellated triangles.
            if (Status s = preparePreTessellated(ctx, pass, buffers, planned, factor, preMesh); !s) {
                report.notes.push_back(name + ", factor " + std::to_string(factor) + ": not measured, " + s.error().message);
                continue;
            }
            const GridLayout& layout = buffers.gridLayout;
            const uint32_t gridFactor = layout.maxFactor, triangles = uint32_t(layout.indices.size() / 3);

            auto dropAll = [&] {
                buffers.gridEvaluator = GridEvaluator::None;
                buffers.controlPointLevel = kNoControlPoints;
                return success();
            };
            auto drawGrid = [&](VkCommandBuffer cmd) { recordGridDraw(cmd, pass, buffers, rt, view); };
            // Order matters where kinds share state: each kind leaves what the next one needs.
            std::vector<FrameKind> kinds;
            auto add = [&](const char* kindName, std::function<Status()> host, std::function<void(VkCommandBuffer)> record) {
                FrameKind k;
                k.name = kindName;
                k.baseline = k.name == "pre-tessellated";
                k.host = std::move(host);
                k.record = std::move(record);
                kinds.push_back(std::move(k));
            };
            auto drawPre = [&](VkCommandBuffer cmd) {
                recordShadedTriangles(cmd, pass, preMesh.vertices.buffer, preMesh.indices.buffer, preMesh.indexCount, rt, view);
            };
            add("pre-tessellated", {}, drawPre);
            add("tess edit", dropAll, [&](VkCommandBuffer cmd) { recordTessellated(cmd, pass, buffers, rt, view, settings); });
            add("tess view", {}, [&](VkCommandBuffer cmd) { recordTessellated(cmd, pass, buffers, rt, view, settings); });
            add("B-spline", {}, [&](VkCommandBuffer cmd) { recordBSplinePatches(cmd, bspline, pass, buffers, rt, view, settings); });
            add("grid edit", dropAll, [&](VkCommandBuffer cmd) { recordGrid(cmd, pass, buffers, rt, view); });
            // A drag updates on the device what the device filled.
            add("grid drag", drag, [&](VkCommandBuffer cmd) {
                recordMovedVertices(cmd, pass, buffers, planned, {&dragged, 1});
                drawGrid(cmd);
            });
            // The cpu path as the editor runs it: no control points on the device.
            add("pre-tessellated", {}, drawPre);  // halfway through the round
            add("cpu edit", [&] {
                (void)dropAll();
                evaluateGridOnCpu(planned, buffers);
                return success();
            }, drawGrid);
            add("view", {}, drawGrid);
            // The CPU grid's update runs in recordMovedVertices, on the host, before the submit.
            add("cpu drag", drag, [&](VkCommandBuffer cmd) {
                recordMovedVertices(cmd, pass, buffers, planned, {&dragged, 1});
                drawGrid(cmd);
            });

            const uint32_t rounds = kRenderWarmups + args.repeats;
            for (uint32_t round = 0; round < rounds && error.empty(); ++round) {
                std::vector<double> roundMs, roundCpuMs;
                for (FrameKind& kind : kinds) {
                    const double cpuStart = processCpuMs();
                    auto start = Clock::now();
                    Status status = kind.host ? kind.host() : success();
                    if (status) status = submitAndWait(ctx, kind.record);
                    const double ms = msSince(start);
                    roundCpuMs.push_back(processCpuMs() - cpuStart);
                    if (!status) {
                        error = kind.name + ": " + status.error().message;
                        break;
                    }
                    roundMs.push_back(ms);
                    if (round + 1 == rounds) {  // untimed: what the last frame covered
                        Result<std::vector<uint8_t>> pixels = readPixels(ctx, target);
                        if (!pixels) {
                            error = pixels.error().message;
                            break;
                        }
                        const uint32_t* rgba = reinterpret_cast<const uint32_t*>(pixels->data());
                        kind.coveredPixels = 0;
                        for (size_t p = 0; p < pixels->size() / 4; ++p) kind.coveredPixels += rgba[p] != rgba[0];
                    }
                }
                if (round < kRenderWarmups || !error.empty()) continue;
                double baseSum = 0.0, baseCpuSum = 0.0, baseCount = 0.0;
                for (size_t k = 0; k < kinds.size(); ++k)
                    if (kinds[k].baseline) baseSum += roundMs[k], baseCpuSum += roundCpuMs[k], baseCount += 1.0;
                // The baseline's entries: its two frames (the same kind, twice) fold into one.
                for (size_t k = 0; k < kinds.size(); ++k) {
                    const double ms = kinds[k].baseline ? baseSum / baseCount : roundMs[k];
                    const double cpuMs = kinds[k].baseline ? baseCpuSum / baseCount : roundCpuMs[k];
                    kinds[k].ms.push_back(ms);
                    kinds[k].ratios.push_back(ms / (baseSum / baseCount));
                    kinds[k].cpuRatios.push_back(cpuMs / (baseCpuSum / baseCount));
                }
            }
            if (!error.empty()) break;
            if (Result<EditReport> back = planned.moveVertices({&dragged, 1}, {&home, 1}); back) {
                dragAway = true;
                updatePositions(buffers, planned);
            }

            auto kind = [&](const char* n) -> const FrameKind& {
                for (const FrameKind& k : kinds)
                    if (k.name == n) return k;
                std::abort();
            };
            const FrameKind& pre = kind("pre-tessellated");
            const FrameKind& defaultEdit = kind(picked == DrawPath::Tessellated ? "tess edit" : picked == DrawPath::Grid ? "grid edit" : "cpu edit");
            const FrameKind& defaultView = kind(picked == DrawPath::Tessellated ? "tess view" : "view");
            const FrameKind& defaultDrag = kind(picked == DrawPath::Grid ? "grid drag" : "cpu drag");
            // Grid factors other than the request (odd factors on cages with non-quads) draw a
            // finer surface than the pre-tessellated one at the request: compare like with like.
            for (const FrameKind& k : kinds)
                if (k.name != "B-spline" && std::abs(double(k.coveredPixels) - pre.coveredPixels) > 0.02 * pre.coveredPixels)
                    coverageDiffers = true;
            defaultTable += "| " + std::to_string(factor) + " | " + std::to_string(gridFactor) + " | " + std::to_string(triangles) +
                            " | " + cell(pre, false) + " | " + cellWithCpu(defaultView) + " | " +
                            (picked == DrawPath::Tessellated ? std::string("") : cellWithCpu(defaultDrag)) + " | " +
                            cellWithCpu(defaultEdit) + " |\n";
            pathTable += "| " + std::to_string(factor) + " | " + cell(kind("tess view")) + " | " + cell(kind("tess edit")) + " | " +
                         cell(kind("grid edit")) + " | " + cell(kind("cpu edit")) + " | " + cell(kind("view")) + " | " +
                         cell(kind("grid drag")) + " | " + cell(kind("cpu drag")) + " | " + cell(kind("B-spline")) + " |\n";
            for (const FrameKind& k : kinds)
                report.series.push_back({"frame time, " + name, std::to_string(factor), k.name, k.medianMs(), "ms"});
            std::fprintf(stderr, "  factor %u: pre %s, view %s, cpu drag %s, cpu edit %s, grid edit %s, tess view %s, tess edit %s ms\n",
                         factor, cell(pre, false).c_str(), cell(kind("view")).c_str(), cell(kind("cpu drag")).c_str(),
                         cell(kind("cpu edit")).c_str(), cell(kind("grid edit")).c_str(), cell(kind("tess view")).c_str(),
                         cell(kind("tess edit")).c_str());

            if (factor != kRenderTargetFactor) continue;
            // The target: the default path within 1.5x of pre-tessellated triangles.
            struct Target {
                const char* frame;
                const FrameKind* kind;
            };
            for (Target t : {Target{"view frame (camera moved)", &defaultView}, Target{"drag frame (one vertex moved)", &defaultDrag},
                             Target{"edit frame (everything re-evaluated)", &defaultEdit}}) {
                if (picked == DrawPath::Tessellated && t.kind == &defaultDrag) continue;
                Row r;
                r.cage = name;
                r.faces = bench.cage.faceCount();
                r.benchmark = std::string("factor 8, ") + t.frame + ": default path (" + drawPathName(picked) +
                              ") vs pre-tessellated triangles; 2nd: plain B-spline patches";
                r.repeats = args.repeats;
                r.unit = "ms";
                r.ours = t.kind->medianMs();
                r.baseline = pre.medianMs();
                r.pairedRatio = t.kind->medianRatio();
                r.baseline2 = kind("B-spline").medianMs();
                r.targetValue = kRenderTargetRatio;
                report.rows.push_back(r);
            }
            // Which path is fastest for a full re-evaluation on this device, as measured.
            const FrameKind* fastest = &kind("tess edit");
            for (const char* n : {"grid edit", "cpu edit"})
                if (kind(n).medianMs() < fastest->medianMs()) fastest = &kind(n);
            report.notes.push_back(name + ": auto picks " + drawPathName(picked) + " on '" + ctx.deviceName +
                                   "'; the fastest edit frame at factor 8 is " + fastest->name + " (" +
                                   number(fastest->medianMs()) + " ms; tess " + number(kind("tess edit").medianMs()) +
                                   ", grid " + number(kind("grid edit").medianMs()) + ", cpu " +
                                   number(kind("cpu edit").medianMs()) + ")");
        }
    }
    if (!error.empty()) report.notes.push_back(name + ": stopped, " + error);
    report.notes.push_back(name + ": load average at the end: " + loadAverage());
    if (coverageDiffers)
        report.notes.push_back(name + ": WARNING: a plans path covers more than 2% more or fewer pixels than the "
                                      "pre-tessellated triangles: the paths may not draw the same surface");
    if (report.appendix.empty())
        report.appendix =
            "Render suite: " + std::to_string(kRenderSize) + "x" + std::to_string(kRenderSize) +
            " offscreen target, camera framing the cage, uniform factors. Each round draws one frame of every kind "
            "back to back, the pre-tessellated one twice (first and halfway); medians of R rounds after " +
            std::to_string(kRenderWarmups) +
            " warm-up rounds. A frame's time is wall time: host work for the frame (CPU evaluation, updates) plus the "
            "submitAndWait round trip. Ratios (in brackets) are medians of the per-round ratios to the mean of the "
            "round's two pre-tessellated frames; CPU: the same with this process's CPU time (all threads), which other "
            "work on the machine hardly moves but which counts work on two cores twice. Pre-tessellated = the grid's "
            "vertices evaluated once, copied into a vertex and an index buffer of their own, drawn with the grid's "
            "plain-shading pipeline (the same shaders as a grid view frame). View frame: the camera moved, the cached grid is drawn (tess: "
            "the cached control points are tessellated). Drag frame: one vertex moved (PlannedCage::moveVertices, then "
            "recordMovedVertices re-evaluates the sub-faces around it), then the draw. Edit frame: everything "
            "re-evaluated (positions or factor changed), then the draw. B-spline = one bicubic patch per sub-face "
            "through the tessellator (a cost baseline, not the exact surface). Grid factor: the grid rounds odd "
            "factors up on cages with non-quads.\n\n";
    report.appendix += defaultTable + "\n" + pathTable + "\n";

    vkDeviceWaitIdle(ctx.device);
    destroyMesh(ctx, preMesh);
    destroyPlanBuffers(ctx, buffers);
    destroyBSplinePass(ctx, bspline);
    destroyPlanPass(ctx, pass);
    destroyOffscreenTarget(ctx, target);
    destroyContext(ctx);
}

// ---- the schemes suite -----------------------------------------------------------------

constexpr uint32_t kSchemesGeneratedFaces = 2000;

// Pixels of the last frame that are not the background (the top-left pixel's colour).
Result<uint32_t> coveredPixels(const VulkanContext& ctx, const OffscreenTarget& target) {
    Result<std::vector<uint8_t>> pixels = readPixels(ctx, target);
    if (!pixels) return pixels.error();
    const uint32_t* rgba = reinterpret_cast<const uint32_t*>(pixels->data());
    uint32_t covered = 0;
    for (size_t p = 0; p < pixels->size() / 4; ++p) covered += rgba[p] != rgba[0];
    return covered;
}

// Every scheme plugin at every uniform factor, frame time against the render suite's
// pre-tessellated triangles at the same factor, measured in the same rounds.
void benchSchemes(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench schemes: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto skip = [&](const std::string& why) { report.notes.push_back(name + ": skipped, " + why); };
    PlanDatabase database;
    Result<PlannedCage> created = PlannedCage::create(bench.cage, database, PlanOptions{}, name);
    if (!created) return skip(created.error().message);
    PlannedCage& planned = *created;
    const PluginCatalog catalog = loadPlugins(pluginDirectory());
    for (const PluginProblem& p : catalog.problems) report.notes.push_back(name + ": " + p.message);
    if (catalog.plugins.empty()) return skip("no scheme plugin loaded from " + catalog.directory);
    Result<VulkanContext> context = createBenchContext();
    if (!context) return skip(context.error().message);
    VulkanContext ctx = std::move(context).value();
    report.notes.push_back(name + ": load average at the start (1, 5, 15 min): " + loadAverage());

    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    OffscreenTarget target;
    PlanPass pass;
    PlanBuffers buffers;
    GpuMesh preMesh;
    std::string error;
    auto take = [&](auto result, auto& out) {
        if (result) out = std::move(result).value();
        else if (error.empty()) error = result.error().message;
        return bool(result);
    };
    take(createOffscreenTarget(ctx, kRenderSize, kRenderSize, format), target) &&
        take(createPlanPass(ctx, VK_NULL_HANDLE, format), pass) && take(uploadPlans(ctx, planned), buffers);

    const CageFeatures features = analyzeCage(planned.cage(), planned.topology());
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, format, VK_FORMAT_D32_SFLOAT};
    std::string table = "### schemes: " + name + " (" + std::to_string(bench.cage.faceCount()) +
                        " faces), frame ms and the ratio to pre-tessellated triangles at the same factor\n\n"
                        "| scheme | factor | triangles | frame ms | pre-tessellated ms (triangles) | ratio | covered pixels vs "
                        "pre-tessellated |\n|---|---:|---:|---:|---:|---:|---:|\n";
    std::vector<std::string> noted;  // refusals and failures, each noted once
    auto noteOnce = [&](const std::string& text) {
        if (std::find(noted.begin(), noted.end(), text) == noted.end()) {
            noted.push_back(text);
            report.notes.push_back(name + ": " + text);
        }
    };
    std::vector<std::pair<std::string, std::vector<uint64_t>>> trianglesPerScheme;  // over the factors
    if (error.empty()) {
        bindPlanBuffers(ctx, pass, buffers);
        const Bounds bounds = computeBounds(bench.cage);
        const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kRenderSize);
        DrawView drawView;
        drawView.viewProjection = view.viewProjection;
        drawView.eye = camera.eye;
        drawView.pixelsPerUnit = view.pixelsPerUnit;
        const RenderTarget rt = renderTarget(target);

        for (uint32_t factor : args.factors) {
            const std::string at = ", factor " + std::to_string(factor);
            // The baseline, as in the render suite.
            if (Status s = preparePreTessellated(ctx, pass, buffers, planned, factor, preMesh); !s) {
                report.notes.push_back(name + at + ": not measured, " + s.error().message);
                continue;
            }
            const uint32_t preTriangles = uint32_t(buffers.gridLayout.indices.size() / 3);
            auto drawPre = [&](VkCommandBuffer cmd) {
                recordShadedTriangles(cmd, pass, preMesh.vertices.buffer, preMesh.indices.buffer, preMesh.indexCount, rt, view);
            };

            struct Measured {
                Measured(std::string schemeName, PreparedScheme scheme)
                    : name(std::move(schemeName)), prepared(std::move(scheme)) {}
                std::string name;
                PreparedScheme prepared;
                DrawStats draw;
                std::vector<double> ms, ratios;
                bool failed = false;
                uint32_t covered = 0;
            };
            std::vector<Measured> schemes;
            for (const auto& plugin : catalog.plugins) {
                SchemeSettings settings;
                settings.tessFactor = factor;
                Result<PreparedScheme> prepared = prepareScheme(catalog, plugin->name, planned, features, settings, gpu, name);
                if (!prepared) {
                    noteOnce("scheme " + plugin->name + " not measured: " + prepared.error().message);
                    continue;
                }
                schemes.emplace_back(plugin->name, std::move(prepared).value());
            }
            // A frame as if the cage moved every frame: the scheme's update, its record, the
            // submit and the wait.
            auto schemeFrame = [&](Measured& s) -> Result<double> {
                const auto start = Clock::now();
                Status ok = s.prepared.instance.update();
                Result<DrawStats> drawn = DrawStats{};
                if (ok) ok = submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = s.prepared.instance.record(cmd, rt, drawView); });
                if (ok && !drawn) ok = drawn.error();
                if (!ok) return ok.error();
                s.draw = *drawn;
                return msSince(start);
            };
            auto preFrame = [&]() -> Result<double> {
                const auto start = Clock::now();
                if (Status ok = submitAndWait(ctx, drawPre); !ok) return ok.error();
                return msSince(start);
            };
            // Each round: pre-tessellated, every scheme, pre-tessellated again; ratios against
            // the mean of the round's two baseline frames.
            std::vector<double> preMs;
            const uint32_t rounds = kRenderWarmups + args.repeats;
            for (uint32_t round = 0; round < rounds && error.empty(); ++round) {
                Result<double> before = preFrame();
                std::vector<double> roundMs(schemes.size(), NAN);
                for (size_t k = 0; k < schemes.size() && before; ++k) {
                    if (schemes[k].failed) continue;
                    Result<double> ms = schemeFrame(schemes[k]);
                    if (!ms) {
                        schemes[k].failed = true;
                        noteOnce("scheme " + schemes[k].name + at + ": stopped, " + ms.error().message);
                        continue;
                    }
                    roundMs[k] = *ms;
                }
                Result<double> after = before ? preFrame() : before;
                if (!after) {
                    error = "pre-tessellated" + at + ": " + after.error().message;
                    break;
                }
                if (round < kRenderWarmups) continue;
                const double base = 0.5 * (*before + *after);
                preMs.push_back(base);
                for (size_t k = 0; k < schemes.size(); ++k)
                    if (!schemes[k].failed && !std::isnan(roundMs[k])) {
                        schemes[k].ms.push_back(roundMs[k]);
                        schemes[k].ratios.push_back(roundMs[k] / base);
                    }
            }
            // Untimed: what each drew, as a sanity check that it drew the same surface.
            uint32_t preCovered = 0;
            if (error.empty()) {
                Status drawn = submitAndWait(ctx, drawPre);
                Result<uint32_t> covered = drawn ? coveredPixels(ctx, target) : Result<uint32_t>(drawn.error());
                if (covered) preCovered = *covered;
                else error = covered.error().message;
                for (Measured& s : schemes) {
                    if (s.failed || !error.empty()) continue;
                    Result<double> frame = schemeFrame(s);
                    Result<uint32_t> c = frame ? coveredPixels(ctx, target) : Result<uint32_t>(frame.error());
                    if (c) {
                        s.covered = *c;
                    } else {
                        s.failed = true;
                        noteOnce("scheme " + s.name + at + ": stopped, " + c.error().message);
                    }
                }
            }
            for (Measured& s : schemes)
                if (Status destroyed = s.prepared.instance.destroyGpu(); !destroyed)
                    noteOnce("scheme " + s.name + at + ": " + destroyed.error().message);
            if (!error.empty()) break;

            const double pre = median(preMs);
            report.series.push_back({"scheme frame time, " + name, std::to_string(factor), "pre-tessellated", pre, "ms"});
            for (const Measured& s : schemes) {
                if (s.failed || s.ms.empty()) continue;
                Row r;
                r.cage = name;
                r.faces = bench.cage.faceCount();
                // Both triangle counts in the row: a scheme that draws more is not compared like with like.
                r.benchmark = "scheme " + s.name + at + " (" + (s.draw.triangles ? std::to_string(s.draw.triangles) : std::string("?")) +
                              " triangles, " + drawnByName(s.draw.drawnBy) + "): frame (update + record + submit) vs " +
                              "pre-tessellated triangles (" + std::to_string(preTriangles) + ")";
                r.repeats = args.repeats;
                r.unit = "ms";
                r.ours = median(s.ms);
                r.baseline = pre;
                r.pairedRatio = median(s.ratios);
                r.targetValue = kRenderTargetRatio;
                report.rows.push_back(r);
                report.series.push_back({"scheme frame time, " + name, std::to_string(factor), s.name, r.ours, "ms"});
                const std::string coverage =
                    preCovered ? number(100.0 * double(s.covered) / double(preCovered)) + "%" : std::string("");
                table += "| " + s.name + " | " + std::to_string(factor) + " | " +
                         (s.draw.triangles ? std::to_string(s.draw.triangles) : std::string("?")) + " | " + number(r.ours) +
                         " | " + number(pre) + " (" + std::to_string(preTriangles) + ") | " + number(r.ratio()) + " | " +
                         coverage + " |\n";
                auto seen = std::find_if(trianglesPerScheme.begin(), trianglesPerScheme.end(),
                                         [&](const auto& entry) { return entry.first == s.name; });
                if (seen == trianglesPerScheme.end()) seen = trianglesPerScheme.insert(seen, {s.name, {}});
                seen->second.push_back(s.draw.triangles);
                std::fprintf(stderr, "  %s%s: %s ms (%sx pre-tessellated, %s ms)\n", s.name.c_str(), at.c_str(),
                             number(r.ours).c_str(), number(r.ratio()).c_str(), number(pre).c_str());
            }
        }
    }
    for (const auto& [scheme, triangles] : trianglesPerScheme)
        if (triangles.size() > 1 && triangles.front() != 0 &&
            std::all_of(triangles.begin(), triangles.end(), [&](uint64_t t) { return t == triangles.front(); }))
            report.notes.push_back(name + ": scheme " + scheme + " draws the same " + std::to_string(triangles.front()) +
                                   " triangles at every factor (it has no uniform factor)");
    if (!error.empty()) report.notes.push_back(name + ": stopped, " + error);
    report.notes.push_back(name + ": load average at the end: " + loadAverage());
    if (report.appendix.empty())
        report.appendix =
            "Schemes suite: every scheme plugin at each uniform factor (SchemeSettings::tessFactor), " +
            std::to_string(kRenderSize) + "x" + std::to_string(kRenderSize) +
            " offscreen target, camera framing the cage. A scheme frame is wall time of update() (as if the cage moved "
            "every frame), record() and the submitAndWait round trip. Pre-tessellated is the render suite's baseline: "
            "the plans grid at the same factor evaluated once into vertex and index buffers of their own and drawn "
            "with the plain-shading pipeline. Each round draws the baseline, every scheme, the baseline again; ratios "
            "are medians of the per-round ratios to the mean of the round's two baseline frames, after " +
            std::to_string(kRenderWarmups) +
            " warm-up rounds. Target: the render suite's 1.5x (issue 8 names no target per scheme; informative). "
            "Covered pixels: the scheme's last frame against the baseline's (a sanity check that both drew the "
            "cage). Triangles '?': the scheme does not report them.\n\n";
    report.appendix += table + "\n";

    vkDeviceWaitIdle(ctx.device);
    destroyMesh(ctx, preMesh);
    destroyPlanBuffers(ctx, buffers);
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
    Result<VulkanContext> context = createBenchContext();
    if (!context) {
        report.notes.push_back(bench.name + ": no Vulkan context: " + context.error().message);
        return;
    }
    const uint32_t dabs = args.repeats * kDabsPerRepeat;
    DisplacementBenchResult result = measureDisplacementDabs(*context, bench.cage, kDisplacementResolution, dabs, args.seed);
    const std::string device = context->deviceName;
    destroyContext(*context);
    if (!result.error.empty()) report.notes.push_back(bench.name + ": " + result.error);
    if (result.dabs.empty()) return;
    report.notes.push_back(bench.name + ": resolution " + std::to_string(result.resolution) + " on every sub-face, " +
                           std::to_string(result.samples) + " samples (" + number(result.samples * 4.0 / 1048576.0) +
                           " MiB); smooth falloff, dabs at random sample positions; the samples cache is built once per "
                           "layout; GPU buffers: the plans renderer's sample buffer and its CPU-path grid at factor " +
                           std::to_string(result.gridFactor) + " (" + std::to_string(result.gridSubfaces) +
                           " sub-faces), both mapped Vulkan buffers on " + device);
    for (const DabMeasurement& m : result.dabs) {
        Row r;
        r.cage = bench.name;
        r.faces = bench.cage.faceCount();
        r.benchmark = std::string(brushKindName(m.brush)) + " dab, radius " + number(m.radius) + ": CPU update " +
                      number(m.updateMs) + " ms + GPU buffers " + number(m.uploadMs) + " ms (" + number(m.bytes / 1024.0) +
                      " KiB of samples, " + number(m.gridSlots) + " grid slots of " + number(m.gridSubfaces) +
                      " sub-faces; " + number(m.samplesReached) +
                      " samples in reach) vs uploading every sample and re-evaluating the whole grid; 2nd: building "
                      "the samples cache";
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

// ---- the edit suite ---------------------------------------------------------------------
// Every kind of tag and topology edit the editor makes, through EditHistory on a PlannedCage
// (as the editor and the Python module do it: the topology operation, the incremental re-plan,
// the history record), against OpenSubdiv rebuilding the whole cage (refiner, adaptive
// refinement, patch table), which a renderer built on Far needs after such an edit. Each edit
// is done and undone R times on the same element; rows give the medians of the do and of the
// undo. Vertex moves are the plans suite's row (c): neither side rebuilds for them.

constexpr uint32_t kEditGeneratedFaces = 20000;

void benchEdit(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const PlanOptions options;
    const uint32_t repeats = args.repeats;
    std::fprintf(stderr, "bench edit: %s (%u faces)\n", bench.name.c_str(), bench.cage.faceCount());
    if (auto refiner = createRefiner(bench.cage, bench.name); !refiner) {
        report.notes.push_back(bench.name + ": skipped, " + refiner.error().message);
        return;
    }
    PlanDatabase database;
    Result<PlannedCage> created = PlannedCage::create(bench.cage, database, options, bench.name);
    if (!created) {
        report.notes.push_back(bench.name + ": skipped, " + created.error().message);
        return;
    }
    PlannedCage& planned = *created;
    std::vector<double> far;
    for (uint32_t r = 0; r < repeats; ++r) far.push_back(buildFar(planned.cage(), options).patchesMs);
    const double farMs = median(far);

    const Cage& cage = planned.cage();
    const uint32_t faces = cage.faceCount();
    uint32_t quad = faces / 2;
    while (quad + 1 < faces && cage.faceSize(quad) != 4) ++quad;
    const auto edge = interiorEdge(planned);
    const std::vector<uint32_t> quadVertices(cage.faceBegin(quad), cage.faceBegin(quad) + cage.faceSize(quad));
    const uint32_t vertex = quadVertices[0];
    const float distance = 0.01f * computeBounds(cage).diagonal();

    EditHistory history;
    auto topology = [&](const char* name, auto make) -> Result<EditReport> {
        Result<TopologyEdit> edit = make(planned.cage(), planned.topology());
        if (!edit) return edit.error();
        return history.applyTopologyEdit(planned, name, std::move(*edit));
    };
    struct EditCase {
        std::string name;
        std::function<Result<EditReport>()> apply;
        std::function<Status()> prepare;  // untimed, undone after the case (make face needs a hole)
    };
    std::vector<EditCase> cases;
    if (edge) {
        const auto [a, b] = *edge;
        const EdgeCrease crease{a, b, 2.0f};
        cases.push_back({"edge crease 2.0", [&, crease] { return history.setEdgeSharpness(planned, "Crease", {&crease, 1}); }, {}});
    }
    const VertexCorner corner{vertex, 3.0f};
    cases.push_back({"corner 3.0", [&] { return history.setVertexSharpness(planned, "Corner", {&corner, 1}); }, {}});
    cases.push_back({"hole", [&] { return history.setHoles(planned, "Hole", {&quad, 1}, true); }, {}});
    cases.push_back({"extrude one face", [&] {
                         return topology("Extrude", [&](const Cage& c, const Topology& t) { return extrudeFaces(c, t, {&quad, 1}, distance); });
                     }, {}});
    cases.push_back({"split a quad", [&] {
                         return topology("Split", [&](const Cage& c, const Topology& t) {
                             return splitFace(c, t, quad, quadVertices[0], quadVertices[2]);
                         });
                     }, {}});
    cases.push_back({"insert an edge loop", [&] {
                         return topology("Edge loop", [&](const Cage& c, const Topology& t) {
                             return insertEdgeLoop(c, t, quadVertices[0], quadVertices[1], 0.5f);
                         });
                     }, {}});
    cases.push_back({"delete one face", [&] {
                         return topology("Delete", [&](const Cage& c, const Topology& t) { return deleteFaces(c, t, {&quad, 1}, false); });
                     }, {}});
    if (edge) {
        const std::array<uint32_t, 2> ends{edge->first, edge->second};
        cases.push_back({"merge an edge's ends", [&, ends] {
                             return topology("Merge", [&](const Cage& c, const Topology& t) { return mergeVertices(c, t, ends); });
                         }, {}});
    }
    cases.push_back({"make face (fill a deleted face's hole)", [&] {
                         return topology("Make face", [&](const Cage& c, const Topology& t) { return makeFace(c, t, quadVertices); });
                     },
                     [&]() -> Status {
                         Result<EditReport> deleted =
                             topology("Delete", [&](const Cage& c, const Topology& t) { return deleteFaces(c, t, {&quad, 1}, false); });
                         if (!deleted) return deleted.error();
                         return success();
                     }});

    for (const EditCase& c : cases) {
        if (c.prepare)
            if (Status ready = c.prepare(); !ready) {
                report.notes.push_back(bench.name + ": " + c.name + " skipped, " + ready.error().message);
                continue;
            }
        std::vector<double> doMs, undoMs;
        uint32_t replanned = 0;
        std::string failure;
        for (uint32_t r = 0; r < repeats && failure.empty(); ++r) {
            auto start = Clock::now();
            Result<EditReport> done = c.apply();
            doMs.push_back(msSince(start));
            if (!done) {
                failure = done.error().message;
                break;
            }
            replanned = done->replannedFaces;
            start = Clock::now();
            Result<EditReport> undone = history.undo(planned);
            undoMs.push_back(msSince(start));
            if (!undone) failure = undone.error().message;
        }
        if (c.prepare) (void)history.undo(planned);
        if (!failure.empty()) {
            report.notes.push_back(bench.name + ": " + c.name + " skipped, " + failure);
            continue;
        }
        for (bool undo : {false, true}) {
            Row row;
            row.cage = bench.name;
            row.faces = faces;
            row.benchmark = (undo ? "undo " : "") + c.name + " (" + std::to_string(replanned) +
                            " faces re-planned) vs OSD full rebuild (refine + patch table)";
            row.repeats = repeats;
            row.unit = "ms";
            row.ours = median(undo ? undoMs : doMs);
            row.baseline = farMs;
            row.targetValue = 1.0;  // at least faster than a rebuild
            report.rows.push_back(row);
            report.series.push_back({"edit vs rebuild, " + bench.name, (undo ? "undo " : "") + c.name, "ours", row.ours, "ms"});
            report.series.push_back({"edit vs rebuild, " + bench.name, (undo ? "undo " : "") + c.name, "OpenSubdiv rebuild", farMs, "ms"});
        }
    }
    if (const std::vector<std::string> differences = planned.differencesFromRebuild(); !differences.empty())
        report.notes.push_back(bench.name + ": WARNING: after the edits and undos " + std::to_string(differences.size()) +
                               " sub-faces differ from a rebuild: " + differences.front());
}

// ---- the editor suite ---------------------------------------------------------------------
// Issue 6 item 11: frame times of the real editor (`quadplan edit`, this executable) on the
// cage at its default tessellation, through its automation hook (`measure-frames`, medians).
// It needs a display: run under `xvfb-run -a -s "-screen 0 1280x800x24"`. "ours" is the median
// interval between frame starts while orbiting (the 3D redrawn every frame) or while dragging a
// vertex (an edit every frame, drawn in the same frame) or sculpting (a dab of the default brush
// every frame, its samples uploaded and drawn in the same frame); the baseline is frames that only redraw
// the interface (the 3D copied from its cache), measured in the same editor run.

constexpr double kEditorFrameTargetMs = 50.0;
// Issue 15's targets for the frame that shows an edit: a tag edit's at most 1.5 vertex-drag
// frames, a one-face extrude's at most 2; a scheme switch or a new viewport at most 50 ms.
constexpr double kTagEditFrameRatio = 1.5, kTopologyEditFrameRatio = 2.0, kEditorSwitchTargetMs = 50.0;
constexpr uint32_t kEditorFramesPerRepeat = 8;

void benchEditor(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const char* display = std::getenv("DISPLAY");
    if (!display || !display[0]) {
        report.notes.push_back(bench.name + ": skipped, the editor needs a display (run under xvfb-run)");
        return;
    }
    std::fprintf(stderr, "bench editor: %s (%u faces)\n", bench.name.c_str(), bench.cage.faceCount());
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("quadplan-bench-editor-" + std::to_string(getpid()));
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    const std::string cagePath = (dir / "cage.obj").string();
    if (Status saved = saveObj(bench.cage, cagePath); !saved) {
        report.notes.push_back(bench.name + ": " + saved.error().message);
        return;
    }
    const std::string frames = std::to_string(args.repeats * kEditorFramesPerRepeat);
    auto out = [&](const char* name) { return (dir / name).string(); };  // the editor runs in our working directory
    // The edits come before sculpting: topology edits are refused once there is displacement.
    std::ofstream(dir / "script.txt") << "wait-idle\nwait-frames 5\nmeasure-frames " << frames << " " << out("idle.json") << "\n"
                                      << "measure-frames " << frames << " " << out("orbit.json") << " orbit\nselect-vertex 10\n"
                                      << "measure-frames " << frames << " " << out("drag.json") << " drag\n"
                                      << editorEditScript(bench.cage, out("edits.jsonl"), std::max(3u, args.repeats))
                                      << "measure-frames " << frames << " " << out("sculpt.json")
                                      << " sculpt\nquit\nclick-button Discard changes\n";
    const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();  // not the shell's
    const std::string command = "'" + self + "' edit '" + cagePath + "' --no-vsync --size 1280x800 --automation '" +
                                (dir / "script.txt").string() + "' --autosave-seconds 3600 > '" + (dir / "editor.log").string() + "' 2>&1";
    const int status = std::system(command.c_str());
    auto load = [&](const char* name) {
        std::ifstream in(dir / name);
        return in ? nlohmann::json::parse(in, nullptr, false) : nlohmann::json();
    };
    const nlohmann::json idle = load("idle.json"), orbit = load("orbit.json"), drag = load("drag.json"),
                         sculpt = load("sculpt.json");
    if (status != 0 || !idle.is_object() || !orbit.is_object() || !drag.is_object() || !sculpt.is_object()) {
        report.notes.push_back(bench.name + ": the editor failed (status " + std::to_string(status) + "), see " +
                               (dir / "editor.log").string());
        return;
    }
    auto medianOf = [](const nlohmann::json& m, const char* group, const char* what) {
        return m[group][what]["median"].get<double>();
    };
    report.notes.push_back(bench.name + ": editor at its default tessellation, plans path " +
                           orbit["plans_path"].get<std::string>() + ", factors " + orbit["factors"].dump() + ", " +
                           orbit["triangles"].dump() + " triangles, " + orbit["device"].get<std::string>());
    for (const auto& [label, m] : {std::pair{"orbit (3D redrawn every frame)", &orbit},
                                   std::pair{"drag a vertex (an edit every frame)", &drag},
                                   std::pair{"sculpt (a brush dab every frame, default brush)", &sculpt}}) {
        Row r;
        r.cage = bench.name;
        r.faces = bench.cage.faceCount();
        r.benchmark = std::string("editor frame interval, ") + label + ": CPU " + number(medianOf(*m, "all_frames", "cpu_ms")) +
                      " ms, GPU " + number(medianOf(*m, "all_frames", "gpu_ms")) + " ms, 3D drawn in " +
                      std::to_string((*m)["scene_drawn"]["cpu_ms"]["count"].get<int>()) + " of " +
                      std::to_string((*m)["frames"].get<int>()) + " frames; vs interface-only frames";
        r.repeats = (*m)["frames"].get<uint32_t>();
        r.unit = "ms";
        r.ours = medianOf(*m, "all_frames", "interval_ms");
        r.baseline = medianOf(idle, "all_frames", "interval_ms");
        r.target = Target::OursAtMost;
        r.targetValue = kEditorFrameTargetMs;
        report.rows.push_back(r);
    }
    // Issue 15: the frame that shows an edit against a vertex-drag frame of the same run (CPU).
    const double dragCpu = medianOf(drag, "all_frames", "cpu_ms");
    const std::vector<EditorEditTiming> edits = readEditorEditTimings(out("edits.jsonl"));
    if (edits.empty()) report.notes.push_back(bench.name + ": no edit was timed (no interior edge between quads?)");
    for (const EditorEditTiming& e : edits) {
        Row r;
        r.cage = bench.name;
        r.faces = bench.cage.faceCount();
        r.benchmark = "editor, the frame showing: " + e.label + ": CPU " + number(e.cpuMs) + " ms (plan engine " +
                      number(e.planEngineMs) + " ms), interval to the next " + number(e.intervalMs) + " ms" +
                      (e.viewNote.empty() || e.kind == EditKind::View ? std::string() : "; viewport 1 " + e.viewNote) +
                      (e.kind == EditKind::View ? std::string("; target 50 ms") : std::string("; vs a vertex-drag frame (CPU)"));
        r.repeats = e.count;
        r.unit = "ms";
        r.ours = e.cpuMs;
        if (e.kind == EditKind::View) {
            r.target = Target::OursAtMost;
            r.targetValue = kEditorSwitchTargetMs;
        } else {
            r.baseline = dragCpu;
            r.target = Target::RatioAtMost;
            r.targetValue = e.kind == EditKind::Tag ? kTagEditFrameRatio : kTopologyEditFrameRatio;
        }
        report.rows.push_back(r);
    }
    std::filesystem::remove_all(dir, ec);
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
    {"schemes", benchSchemes, kSchemesGeneratedFaces},
    {"edit", benchEdit, kEditGeneratedFaces},
    {"displacement", benchDisplacement, 2000},
    {"editor", benchEditor, 2000},
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
        if (!report.series.empty()) {
            std::ofstream seriesFile(args.outDir + "/" + suite.name + "_series.csv");
            seriesFile << "chart,x,series,value,unit\n";
            for (const SeriesPoint& p : report.series)
                seriesFile << csvField(p.chart) << "," << csvField(p.x) << "," << csvField(p.series) << "," << number(p.value)
                           << "," << p.unit << "\n";
        }
        if (!csvFile) {
            std::fprintf(stderr, "error: cannot write to %s\n", args.outDir.c_str());
            return 1;
        }
    }
    return 0;
}

// report.md and the PNG charts: python/quadplan/bench_report.py over everything in --out, run
// with the interpreter and package the build made (as `quadplan run-script` finds them).
int writeReport(const std::string& outDir) {
#ifndef QUADPLAN_PYTHON_EXECUTABLE
    std::fprintf(stderr, "note: no charts or report.md: this quadplan was built without Python (-DQUADPLAN_PYTHON=OFF)\n");
    return 0;
#else
    std::error_code error;
    const std::filesystem::path packageDir =
        std::filesystem::read_symlink("/proc/self/exe", error).parent_path().parent_path() / "python";
    if (error || !std::filesystem::exists(packageDir / "quadplan" / "bench_report.py")) {
        std::fprintf(stderr, "error: no charts: the quadplan Python package is not beside this executable (looked in %s)\n",
                     packageDir.c_str());
        return 1;
    }
    auto quoted = [](const std::string& text) {
        std::string out = "'";
        for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
        return out + "'";
    };
    const std::string command = "PYTHONPATH=" + quoted(packageDir.string()) + " " + quoted(QUADPLAN_PYTHON_EXECUTABLE) +
                                " -m quadplan.bench_report " + quoted(outDir);
    const int status = std::system(command.c_str());
    if (status != 0) {
        std::fprintf(stderr, "error: drawing the charts failed (%s)\n", command.c_str());
        return 1;
    }
    return 0;
#endif
}

int runBench(const BenchArgs& args) {
    for (const Suite& suite : kSuites)
        if (args.suite == "all" || args.suite == suite.name)
            if (int status = runSuite(suite, args); status != 0) return status;
    return args.outDir.empty() ? 0 : writeReport(args.outDir);
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
    cmd->add_option("--out", args->outDir,
                    "Also write SUITE.md, SUITE.csv, SUITE_series.csv, PNG charts and report.md (all suites there) "
                    "into this directory");
    cmd->add_option("--generated-faces", args->generatedFaces,
                    "Faces of the generated torus cage (0: none; default: plans 100000, render " +
                        std::to_string(kRenderGeneratedFaces) + ", schemes " + std::to_string(kSchemesGeneratedFaces) + ", edit " + std::to_string(kEditGeneratedFaces) +
                        ", displacement 2000, editor 2000)");
    cmd->add_option("--factors", args->factors, "render, schemes: uniform tessellation factors (default 1,2,4,8,16)")
        ->delimiter(',')
        ->check(CLI::Range(1u, 64u));
    cmd->add_option("--seed", args->seed, "Seed of the generated cage");
    cmd->add_flag("--no-shared", args->noShared, "Skip catmark_car from ../shared/shapes");
    cmd->add_option("--cage", args->cages, "Also benchmark this cage (.obj); with --no-shared --generated-faces 0 "
                                           "only these");
    cmd->callback([args, &exitCode] { exitCode = runBench(*args); });
}

}  // namespace qp::cli
