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
#include <span>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <opensubdiv/far/patchTableFactory.h>

#include "bench_displacement.h"
#include "bench_editor_edits.h"
#include "bench_report.h"
#include "bench_stats.h"
#include "commands.h"
#include "edit_history.h"
#include "generated_cage.h"
#include "obj_io.h"
#include "osd_refiner.h"
#include "planned_cage.h"
#include "topology_edits.h"

namespace qp::cli {

std::string benchSharedDir() {
#ifdef QUADPLAN_SHARED_DIR
    return QUADPLAN_SHARED_DIR;
#else
    return "";
#endif
}

namespace {

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


// The suite's cages: catmark_car and the suite's other shared cages from ../shared, the
// generated cage, then --cage files. Missing shared files are a note; a --cage that does not
// load is an error.
Result<std::vector<BenchCage>> loadBenchCages(const BenchArgs& args, uint32_t defaultFaces,
                                              std::span<const char* const> sharedCages, Report& report) {
    std::vector<BenchCage> cages;
    for (const char* shared : sharedCages) {
        if (args.noShared) {
            report.notes.push_back(std::string(shared) + ": skipped (--no-shared)");
            continue;
        }
        std::string path = benchSharedDir() + "/shapes/" + shared + ".obj";
        if (Result<Cage> cage = loadObj(path); cage)
            cages.push_back({shared, std::move(cage).value()});
        else
            report.notes.push_back(std::string(shared) + ": skipped, " + cage.error().message);
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
              number(r.ratio()) + " | " + r.targetText() + " | " + r.result() + " | " +
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
               number(r.ratio()) + "," + csvField(r.targetText()) + "," + (r.target == Target::Informative ? "informative" : r.pass() ? "pass" : "miss") + "," +
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
    for (uint32_t r = 0; r < repeats; ++r) far.push_back(farPatchTableMs(planned.cage(), options));
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
    // The edits come before sculpting, so the edit rows time cages without displacement.
    std::ofstream(dir / "script.txt") << "wait-idle\nwait-frames 5\nmeasure-frames " << frames << " " << out("idle.json") << "\n"
                                      << "measure-frames " << frames << " " << out("orbit.json") << " orbit\nselect-vertex 10\n"
                                      << "measure-frames " << frames << " " << out("drag.json") << " drag\n"
                                      << editorEditScript(bench.cage, out("edits.jsonl"), std::max(3u, args.repeats))
                                      << "measure-frames " << frames << " " << out("sculpt.json")
                                      << " sculpt\nquit\nclick-button Discard changes\n";
    const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();  // not the shell's
    // Without the user's plan cache (core/plan_cache.h): every run plans as a first run does.
    const std::string command = "QUADPLAN_PLAN_CACHE=off '" + self + "' edit '" + cagePath + "' --no-vsync --size 1280x800 --automation '" +
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

constexpr const char* kCarOnly[] = {"catmark_car"};

struct Suite {
    const char* name;
    void (*benchCage)(const BenchCage&, const BenchArgs&, Report&);
    uint32_t generatedFaces;  // size of the generated cage unless --generated-faces says otherwise
    std::span<const char* const> sharedCages = kCarOnly;
};

// B16 §9.1's kinds of cage: a character, a smooth one with creases and poles, one dense in
// extraordinary vertices (104 among 434 faces); and the generated 100k-face cage.
constexpr const char* kFasCages[] = {"catmark_car", "catmark_pawn", "catmark_righthanded"};

constexpr Suite kSuites[] = {
    {"plans", benchPlans, 100000},
    {"render", benchRender, kRenderGeneratedFaces},
    {"schemes", benchSchemes, kSchemesGeneratedFaces},
    {"fas", benchFas, 100000, kFasCages},
    {"edit", benchEdit, kEditGeneratedFaces},
    {"displacement", benchDisplacement, 2000},
    {"editor", benchEditor, 2000},
    {"scene", benchScene, 0},
    {"animation", benchAnimation, 100000},
    {"scale", benchScale, 100000, {}},
    {"macro", benchMacro, 10000},
};

int runSuite(const Suite& suite, const BenchArgs& args) {
    Report report;
    report.suite = suite.name;
    Result<std::vector<BenchCage>> cages = loadBenchCages(args, suite.generatedFaces, suite.sharedCages, report);
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
                        std::to_string(kRenderGeneratedFaces) + ", schemes " + std::to_string(kSchemesGeneratedFaces) + ", fas 100000, edit " + std::to_string(kEditGeneratedFaces) +
                        ", displacement 2000, editor 2000, scale 100000, macro 10000)");
    cmd->add_option("--factors", args->factors,
                    "render, schemes, fas: uniform tessellation factors (default 1,2,4,8,16; fas 1,2,4,8,16,32,64)")
        ->delimiter(',')
        ->check(CLI::Range(1u, 64u));
    cmd->add_option("--max-triangles", args->maxTriangles,
                    "fas: skip factors at which the plans would draw more triangles a frame (default 4000000)");
    cmd->add_option("--seed", args->seed, "Seed of the generated cage");
    cmd->add_flag("--no-shared", args->noShared, "Skip the shared cages (catmark_car; fas: also catmark_pawn, catmark_righthanded)");
    cmd->add_option("--cage", args->cages, "Also benchmark this cage (.obj); with --no-shared --generated-faces 0 "
                                           "only these");
    cmd->callback([args, &exitCode] { exitCode = runBench(*args); });
}

}  // namespace qp::cli
