#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "osd_refiner.h"
#include "scene.h"
#include "topology.h"

namespace qp::cli {

namespace {

nlohmann::json histogramJson(const std::map<uint32_t, uint32_t>& histogram) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, count] : histogram) out[std::to_string(key)] = count;
    return out;
}

nlohmann::json statsJson(const std::string& path, const CageStats& s) {
    return {
        {"file", path},
        {"vertices", s.vertices},
        {"faces", s.faces},
        {"edges", s.edges},
        {"face_sizes", histogramJson(s.faceSizeHistogram)},
        {"valences", histogramJson(s.valenceHistogram)},
        {"boundary_edges", s.boundaryEdges},
        {"nonmanifold_edges", s.nonManifoldEdges},
        {"nonmanifold_vertices", s.nonManifoldVertices},
        {"isolated_vertices", s.isolatedVertices},
        {"extraordinary_vertices", s.extraordinaryVertices},
        {"creased_edges", s.creasedEdges},
        {"infinitely_sharp_edges", s.infinitelySharpEdges},
        {"corner_vertices", s.cornerVertices},
        {"holes", s.holes},
    };
}

std::string histogramText(const std::map<uint32_t, uint32_t>& histogram) {
    std::string text;
    for (const auto& [key, count] : histogram)
        text += (text.empty() ? "" : ", ") + std::to_string(key) + ": " + std::to_string(count);
    return text.empty() ? "-" : text;
}

void printStats(const std::string& path, const CageStats& s) {
    std::printf("%s\n", path.c_str());
    std::printf("  vertices               %u\n", s.vertices);
    std::printf("  faces                  %u\n", s.faces);
    std::printf("  edges                  %u\n", s.edges);
    std::printf("  face sizes             %s\n", histogramText(s.faceSizeHistogram).c_str());
    std::printf("  valences               %s\n", histogramText(s.valenceHistogram).c_str());
    std::printf("  boundary edges         %u\n", s.boundaryEdges);
    std::printf("  non-manifold edges     %u\n", s.nonManifoldEdges);
    std::printf("  non-manifold vertices  %u\n", s.nonManifoldVertices);
    std::printf("  isolated vertices      %u\n", s.isolatedVertices);
    std::printf("  extraordinary vertices %u\n", s.extraordinaryVertices);
    std::printf("  creased edges          %u (%u infinitely sharp)\n", s.creasedEdges, s.infinitelySharpEdges);
    std::printf("  corner vertices        %u\n", s.cornerVertices);
    std::printf("  holes                  %u\n", s.holes);
}

int runInfo(const std::string& path, bool json) {
    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(path, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 1;
    }
    const Cage& cage = scene->cage;
    // OpenSubdiv must accept the cage too, or nothing downstream can use it.
    auto refiner = createRefiner(cage, path);
    if (!refiner) {
        std::fprintf(stderr, "error: %s\n", refiner.error().message.c_str());
        return 1;
    }
    CageStats stats = computeStats(cage, buildTopology(cage));
    if (json)
        std::printf("%s\n", statsJson(path, stats).dump(2).c_str());
    else
        printStats(path, stats);
    return 0;
}

}  // namespace

void registerInfo(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("info", "Print counts and histograms of a cage or scene");
    auto path = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    cmd->add_option("file", *path, "Cage (.obj) or scene (.json)")->required();
    cmd->add_flag("--json", *json, "Print one JSON object instead of text");
    cmd->callback([path, json, &exitCode] { exitCode = runInfo(*path, *json); });
}

}  // namespace qp::cli
