// The harness every `quadplan bench` suite shares (bench_report.h): the cages a suite runs on,
// and the report written once for all of them: the Markdown table with the machine and build,
// CSV, chart series, and report.md with PNG charts.
#include "bench_report.h"

#include <ctime>
#include <filesystem>
#include <fstream>
#include <sched.h>
#include <thread>

#include <opensubdiv/version.h>

#include "mesh/generated_cage.h"
#include "mesh/obj_io.h"

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

std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

}  // namespace

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

std::string csv(const Report& report) {
    std::string out = "suite,cage,faces,benchmark,repeats,unit,ours,baseline,ratio,target,result,baseline2,ratio2\n";
    for (const Row& r : report.rows)
        out += report.suite + "," + csvField(r.cage) + "," + std::to_string(r.faces) + "," + csvField(r.benchmark) + "," +
               std::to_string(r.repeats) + "," + r.unit + "," + number(r.ours) + "," + number(r.baseline) + "," +
               number(r.ratio()) + "," + csvField(r.targetText()) + "," + (r.target == Target::Informative ? "informative" : r.pass() ? "pass" : "miss") + "," +
               number(r.baseline2) + "," + number(r.ratio2()) + "\n";
    return out;
}

Status writeSuiteFiles(const Report& report, const BenchArgs& args, const std::string& markdownText) {
    if (args.outDir.empty()) return success();
    std::error_code ec;
    std::filesystem::create_directories(args.outDir, ec);
    std::ofstream(args.outDir + "/" + report.suite + ".md") << markdownText;
    std::ofstream csvFile(args.outDir + "/" + report.suite + ".csv");
    csvFile << csv(report);
    if (!report.series.empty()) {
        std::ofstream seriesFile(args.outDir + "/" + report.suite + "_series.csv");
        seriesFile << "chart,x,series,value,unit\n";
        for (const SeriesPoint& p : report.series)
            seriesFile << csvField(p.chart) << "," << csvField(p.x) << "," << csvField(p.series) << "," << number(p.value)
                       << "," << p.unit << "\n";
    }
    if (!csvFile) return Error{"cannot write to " + args.outDir};
    return success();
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

}  // namespace qp::cli
