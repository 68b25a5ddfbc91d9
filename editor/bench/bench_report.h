// The harness every `quadplan bench` suite shares: what a suite is given (BenchArgs, BenchCage)
// and fills in (Report, Row), the cages and the report written once (bench_report.cpp), and the
// suites, one file each in this folder; editor/cmd_bench.cpp is the command and the suite table.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "offscreen_target.h"
#include "plans/planned_cage.h"
#include "scheme_api.h"
#include "vk_context.h"

namespace qp::cli {

using Clock = std::chrono::steady_clock;

struct BenchArgs {
    std::string suite;
    uint32_t repeats = 5;
    std::string outDir;
    std::optional<uint32_t> generatedFaces;  // unset: the suite's own size (Suite::generatedFaces)
    std::vector<uint32_t> factors;  // uniform tessellation factors; empty: the suite's own
    uint64_t maxTriangles = 4'000'000;  // fas suite: factors whose frames draw more are skipped
    uint32_t seed = 1;
    bool noShared = false;
    std::vector<std::string> cages;

    std::vector<uint32_t> factorsOr(std::vector<uint32_t> suiteDefault) const {
        return factors.empty() ? suiteDefault : factors;
    }
};

struct BenchCage {
    std::string name;
    Cage cage;
};

enum class Target { RatioAtMost, RatioAtLeast, OursAtMost, Informative };

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
    const char* result() const { return target == Target::Informative ? "-" : pass() ? "pass" : "**miss**"; }
    bool pass() const {
        switch (target) {
        case Target::RatioAtMost: return ratio() <= targetValue;
        case Target::RatioAtLeast: return ratio() >= targetValue;
        case Target::OursAtMost: return ours <= targetValue;
        case Target::Informative: return true;
        }
        return false;
    }
    std::string targetText() const {
        char text[48];
        switch (target) {
        case Target::RatioAtMost: std::snprintf(text, sizeof text, "ratio <= %g", targetValue); break;
        case Target::RatioAtLeast: std::snprintf(text, sizeof text, "ratio >= %g", targetValue); break;
        case Target::OursAtMost: std::snprintf(text, sizeof text, "ours <= %g %s", targetValue, unit.c_str()); break;
        case Target::Informative: return "informative";
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

inline double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

inline std::string number(double value) {
    if (std::isnan(value)) return "";
    char text[32];
    std::snprintf(text, sizeof text, std::abs(value) >= 100.0 ? "%.0f" : "%.3g", value);
    return text;
}

// ../shared beside the project as configured (QUADPLAN_SHARED_DIR), or "".
std::string benchSharedDir();
// A suite's cages: the shared ones it names (from ../shared; missing ones become notes), the
// generated cage of defaultFaces unless --generated-faces says otherwise, then --cage files (one
// that does not load is an error).
Result<std::vector<BenchCage>> loadBenchCages(const BenchArgs& args, uint32_t defaultFaces,
                                              std::span<const char* const> sharedCages, Report& report);
// The report of one suite: a Markdown table headed by the machine, the build and the notes; CSV.
std::string markdown(const Report& report, const BenchArgs& args);
std::string csv(const Report& report);
// With --out: SUITE.md, SUITE.csv and SUITE_series.csv there.
Status writeSuiteFiles(const Report& report, const BenchArgs& args, const std::string& markdownText);
// report.md and the PNG charts of everything in outDir, drawn by the quadplan Python package.
int writeReport(const std::string& outDir);

// Lavapipe unless QUADPLAN_VK_DEVICE names a device; validation off (it would dominate timings).
Result<VulkanContext> createBenchContext();
// That device and an RGBA8 target of width x height to draw into (with a D32 depth image).
struct BenchDevice {
    VulkanContext ctx;
    OffscreenTarget target;  // R8G8B8A8_UNORM colour, D32 depth
};
Result<BenchDevice> createBenchDevice(uint32_t width, uint32_t height);
// What a scheme plugin is prepared with to draw into the device's target.
inline GpuContext gpuContextOf(const BenchDevice& device) {
    return GpuContext{&device.ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
}
void destroyBenchDevice(BenchDevice& device);
// "1, 5, 15 min" load averages, for the notes.
std::string loadAverage();

// Cages with more faces than this run the plans suite's expensive rows (a) and (d) at most 5
// times, so a large --repeats stays within minutes (at the default 5 the ~100k cage takes about a
// minute).
inline constexpr uint32_t kLargeCageFaces = 20000;
inline constexpr uint32_t kLargeCageRepeats = 5;

// The animation suite (a deforming cage played frame by frame against Far's per-frame work):
// bench_animation.cpp.
void benchAnimation(const BenchCage& bench, const BenchArgs& args, Report& report);
// The scale suite (a production-size cage from planning to the edited frame): bench_scale.cpp.
void benchScale(const BenchCage& bench, const BenchArgs& args, Report& report);
// The macro suite (macro faces against single faces, B16 §9.4): bench_macro.cpp.
void benchMacro(const BenchCage& bench, const BenchArgs& args, Report& report);

// The edit suite (tag and topology edits against a Far rebuild): bench_edit.cpp.
inline constexpr uint32_t kEditGeneratedFaces = 20000;
void benchEdit(const BenchCage& bench, const BenchArgs& args, Report& report);
// The displacement suite (brush dabs and their buffer updates): bench_displacement.cpp.
void benchDisplacement(const BenchCage& bench, const BenchArgs& args, Report& report);
// The editor suite (the real editor's frames; needs a display): bench_editor.cpp.
void benchEditor(const BenchCage& bench, const BenchArgs& args, Report& report);

// The plans suite (plan engine against OpenSubdiv Far and Bfr): bench_plans.cpp.
void benchPlans(const BenchCage& bench, const BenchArgs& args, Report& report);
// One full Far rebuild (refiner, adaptive refinement, patch table) with the plan builder's
// options: its patch-table milliseconds (the edit suite's baseline).
double farPatchTableMs(const Cage& cage, const PlanOptions& options);
// An edge with a face on each side and no crease, near the middle of the edge list.
std::optional<std::pair<uint32_t, uint32_t>> interiorEdge(const PlannedCage& planned);

// Generated-cage sizes of those suites. Render: ~10k faces, because at factor 16 the 100k cage
// would need ~50 M triangles a frame (seconds each on lavapipe, minutes for the suite) and a grid
// of ~700 MB (drawn, but by address: plan_pass.h).
inline constexpr uint32_t kRenderGeneratedFaces = 10000;
inline constexpr uint32_t kSchemesGeneratedFaces = 2000;

// The render suite (every plan path against pre-tessellated triangles) and the schemes suite
// (every scheme plugin against the same baseline): bench_gpu.cpp.
inline constexpr uint32_t kRenderSize = 512;  // their offscreen target, and the fas suite's
void benchRender(const BenchCage& bench, const BenchArgs& args, Report& report);
// A scene of many objects: instances, distinct cages, one plan database (bench_scene.cpp).
void benchScene(const BenchCage& bench, const BenchArgs& args, Report& report);
void benchSchemes(const BenchCage& bench, const BenchArgs& args, Report& report);
// The fas suite (plans against OpenSubdiv's feature-adaptive patches, B16 §9.1): bench_fas.cpp.
void benchFas(const BenchCage& bench, const BenchArgs& args, Report& report);

}  // namespace qp::cli
