// `quadplan bake`: a cage's or scene's sculpted displacement as a 32-bit float OpenEXR map in
// UV space, and with --normal-map a tangent-space normal map (export/displacement_bake.h).
//
// Exit status: 0 written; 1 bad input or a failure (nothing written).
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "displacement_bake.h"
#include "render_setup.h"

namespace qp::cli {

namespace {

struct BakeArgs {
    std::string path, out, normalMap, uv = "linear";
    uint32_t size = 1024, padding = 4, depth = 6;
    bool json = false;
};

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

int runBake(const BakeArgs& args) {
    PlanDatabase database;
    Result<PlannedFile> file = loadAndPlan(args.path, database, PlanOptions{args.depth, true});
    if (!file) return fail(file.error().message);
    BakeOptions options;
    options.size = args.size;
    options.uv = *parseUvMode(args.uv);
    options.padding = args.padding;
    options.normalMap = !args.normalMap.empty();
    Result<BakeReport> report = bakeScene(file->scene, sceneCages(file->planned), args.out, args.normalMap, options, args.path);
    if (!report) return fail(report.error().message);
    for (const std::string& note : report->notes) std::fprintf(stderr, "note: %s\n", note.c_str());
    const BakeReport& r = *report;
    if (args.json) {
        const nlohmann::json out = {{"files", r.files},          {"size", args.size},
                                    {"uv", args.uv},             {"padding", args.padding},
                                    {"island_texels", r.islandTexels}, {"padding_texels", r.paddingTexels},
                                    {"min", r.minValue},         {"max", r.maxValue},
                                    {"ms", r.ms}};
        std::printf("%s\n", out.dump(2).c_str());
        return 0;
    }
    for (const std::string& file : r.files) std::printf("wrote %s\n", file.c_str());
    std::printf("%u x %u texels, %llu in UV islands and %llu of padding, displacement %.6g to %.6g, %.0f ms\n", args.size,
                args.size, (unsigned long long)r.islandTexels, (unsigned long long)r.paddingTexels, double(r.minValue),
                double(r.maxValue), r.ms);
    return 0;
}

}  // namespace

void registerBake(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("bake", "Bake the sculpted displacement into a 32-bit float OpenEXR map in UV space");
    auto args = std::make_shared<BakeArgs>();
    cmd->add_option("file", args->path, "Scene (.json) with sculpted displacement; the cage needs UVs")->required();
    cmd->add_option("--out", args->out, "The displacement map to write (.exr); one per object, NAME_OBJECT.exr, when several objects are sculpted")
        ->required();
    cmd->add_option("--size", args->size, "Texels per side (default 1024)")->check(CLI::Range(16u, 16384u));
    cmd->add_option("--uv", args->uv,
                    "linear (default): the cage's UVs bilinear over each face; smooth: OpenSubdiv's face-varying limit")
        ->check(CLI::IsMember({"linear", "smooth"}));
    cmd->add_option("--normal-map", args->normalMap, "Also write the tangent-space normal map (.png, OpenGL convention: green up)");
    cmd->add_option("--padding", args->padding, "Texels of padding grown around each UV island (default 4)")->check(CLI::Range(0u, 64u));
    cmd->add_option("--depth", args->depth, "Plan depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--json", args->json, "Print what was written as JSON");
    cmd->callback([args, &exitCode] { exitCode = runBake(*args); });
}

}  // namespace qp::cli
