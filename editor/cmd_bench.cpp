// `quadplan bench SUITE`: benchmarks of our engine against OpenSubdiv measured in the same run,
// so ratios stay meaningful on a noisy machine. Every figure is the median of R repeats.
// Suites are a table (kSuites), each in a file of its own in bench/ behind one harness
// (bench/bench_report.h: cages, rows, medians, the report); `all` runs them in order. This is a
// measurement, not a test: it exits 0 when targets are missed, and the result column says so.
#include <cstdio>
#include <memory>
#include <span>

#include "bench/bench_report.h"
#include "commands.h"

namespace qp::cli {

namespace {

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

    const std::string md = markdown(report, args);
    std::printf("%s\n", md.c_str());
    std::fflush(stdout);
    if (Status written = writeSuiteFiles(report, args, md); !written) {
        std::fprintf(stderr, "error: %s\n", written.error().message.c_str());
        return 1;
    }
    return 0;
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
