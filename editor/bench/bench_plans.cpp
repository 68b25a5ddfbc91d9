// `quadplan bench plans`: the plan engine against OpenSubdiv Far and Bfr on the same cages in the
// same run (plan and rebuild times, memory, evaluation throughput); cmd_bench.cpp runs it and
// writes the report (bench_report.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include "bench_far.h"
#include "bench_stats.h"
#include "plan_memory.h"
#include "plans/osd_refiner.h"
#include "plans/planned_cage.h"
#if __has_include("plan_evaluator.h")
#include "plans/plan_evaluator.h"
#define QP_HAVE_PLAN_EVALUATOR 1
#endif
#include "bench_report.h"

namespace qp::cli {

namespace {

using namespace OpenSubdiv;

constexpr uint32_t kGridSide = 16;  // evaluation grid per sub-face

// ---- OpenSubdiv baselines ---------------------------------------------------------------

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

}  // namespace

// ---- the plans suite --------------------------------------------------------------------

double farPatchTableMs(const Cage& cage, const PlanOptions& options) { return buildFar(cage, options).patchesMs; }

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
    report.notes.push_back("core/plans/plan_evaluator.h is not in this build: no evaluateBatch row");
#endif
    if (sink == 0.123) std::fprintf(stderr, " ");
}

}  // namespace qp::cli
