// `quadplan bench editor`: frame times of the real editor through its automation hook.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "bench_editor_edits.h"
#include "bench_report.h"
#include "mesh/obj_io.h"

namespace qp::cli {

namespace {

// Issue 6 item 11: frame times of the real editor (`quadplan edit`, this executable) on the
// cage at its default tessellation, through its automation hook (`measure-frames`, medians).
// It needs a display: run under `xvfb-run -a -s "-screen 0 1280x800x24"`. "ours" is the median
// interval between frame starts while orbiting (the 3D redrawn every frame) or while dragging a
// vertex (an edit every frame, drawn in the same frame) or sculpting (a dab of the default brush
// every frame, its samples uploaded and drawn in the same frame); the baseline is frames that only redraw
// the interface (the 3D copied from its cache), measured in the same editor run.

constexpr double kEditorFrameTargetMs = 50.0;
// Issue 19's target for a frame with a brush dab in it, on catmark_car and the 2,000-face cage.
constexpr double kSculptFrameTargetMs = 25.0;
// Issue 15's targets for the frame that shows an edit: a tag edit's at most 1.5 vertex-drag
// frames, a one-face extrude's at most 2; a scheme switch or a new viewport at most 50 ms.
constexpr double kTagEditFrameRatio = 1.5, kTopologyEditFrameRatio = 2.0, kEditorSwitchTargetMs = 50.0;
constexpr uint32_t kEditorFramesPerRepeat = 8;

}  // namespace

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
    // Without the user's plan cache (core/plans/plan_cache.h): every run plans as a first run does.
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
        r.targetValue = m == &sculpt ? kSculptFrameTargetMs : kEditorFrameTargetMs;
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

}  // namespace qp::cli
