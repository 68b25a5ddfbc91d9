#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "mesh/topology.h"
#include "plans/osd_refiner.h"
#include "render_setup.h"
#include "scene/scene.h"

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

void addStats(CageStats& into, const CageStats& s) {
    into.vertices += s.vertices;
    into.faces += s.faces;
    into.edges += s.edges;
    for (const auto& [k, n] : s.faceSizeHistogram) into.faceSizeHistogram[k] += n;
    for (const auto& [k, n] : s.valenceHistogram) into.valenceHistogram[k] += n;
    into.boundaryEdges += s.boundaryEdges;
    into.nonManifoldEdges += s.nonManifoldEdges;
    into.nonManifoldVertices += s.nonManifoldVertices;
    into.isolatedVertices += s.isolatedVertices;
    into.creasedEdges += s.creasedEdges;
    into.infinitelySharpEdges += s.infinitelySharpEdges;
    into.cornerVertices += s.cornerVertices;
    into.holes += s.holes;
    into.extraordinaryVertices += s.extraordinaryVertices;
}

int runInfo(const std::string& path, bool json) {
    Result<Scene> scene = loadSceneWarning(path);
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 1;
    }
    Result<std::vector<uint32_t>> owners = cageOwners(scene->objects);
    if (!owners) {
        std::fprintf(stderr, "error: %s: %s\n", path.c_str(), owners.error().message.c_str());
        return 1;
    }
    // Each distinct cage once (instances draw their source's); the scene's counts are their sums.
    std::vector<CageStats> cageStats(scene->objects.size());
    CageStats total;
    for (uint32_t i = 0; i < scene->objects.size(); ++i) {
        if ((*owners)[i] != i) continue;
        const Cage& cage = scene->objects[i].cage;
        const std::string source = scene->objects.size() == 1 ? path : path + ": object \"" + scene->objects[i].name + "\"";
        // OpenSubdiv must accept the cage too, or nothing downstream can use it.
        if (auto refiner = createRefiner(cage, source); !refiner) {
            std::fprintf(stderr, "error: %s\n", refiner.error().message.c_str());
            return 1;
        }
        cageStats[i] = computeStats(cage, buildTopology(cage));
        addStats(total, cageStats[i]);
    }
    if (json) {
        nlohmann::json out = statsJson(path, total);
        out["cages"] = std::count_if(owners->begin(), owners->end(), [&, i = 0u](uint32_t o) mutable { return o == i++; });
        out["objects"] = nlohmann::json::array();
        for (uint32_t i = 0; i < scene->objects.size(); ++i) {
            const SceneObject& o = scene->objects[i];
            nlohmann::json object = {{"name", o.name},
                                     {"instance_of", o.isInstance() ? nlohmann::json(o.instanceOf) : nlohmann::json(nullptr)},
                                     {"visible", o.visible},
                                     {"translation", {o.transform.translation.x, o.transform.translation.y, o.transform.translation.z}},
                                     {"rotation_degrees", {o.transform.rotationDegrees.x, o.transform.rotationDegrees.y, o.transform.rotationDegrees.z}},
                                     {"scale", {o.transform.scale.x, o.transform.scale.y, o.transform.scale.z}}};
            const CageStats& s = cageStats[(*owners)[i]];
            object["vertices"] = s.vertices;
            object["faces"] = s.faces;
            object["edges"] = s.edges;
            out["objects"].push_back(object);
        }
        std::printf("%s\n", out.dump(2).c_str());
        return 0;
    }
    printStats(path, total);
    if (scene->objects.size() > 1) {
        std::printf("  objects                %zu\n", scene->objects.size());
        for (uint32_t i = 0; i < scene->objects.size(); ++i) {
            const SceneObject& o = scene->objects[i];
            const CageStats& s = cageStats[(*owners)[i]];
            std::printf("    %-20s %u faces%s%s\n", o.name.c_str(), s.faces,
                        o.isInstance() ? (", instance of " + o.instanceOf).c_str() : "", o.visible ? "" : ", hidden");
        }
    }
    return 0;
}

}  // namespace

void registerInfo(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("info", "Print counts and histograms of a cage or scene");
    auto path = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    cmd->add_option("file", *path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json)")->required();
    cmd->add_flag("--json", *json, "Print one JSON object instead of text");
    cmd->callback([path, json, &exitCode] { exitCode = runInfo(*path, *json); });
}

}  // namespace qp::cli
