#include "bench_editor_edits.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench_stats.h"
#include "mesh/topology.h"

namespace qp::cli {

namespace {

struct Step {
    const char* label;
    EditKind kind;
};
constexpr Step kSteps[] = {
    {"crease an edge (sharpness 3)", EditKind::Tag},     {"undo the crease", EditKind::Tag},
    {"corner a vertex (sharpness 3)", EditKind::Tag},    {"undo the corner", EditKind::Tag},
    {"make a face a hole", EditKind::Tag},               {"undo the hole", EditKind::Tag},
    {"extrude one face", EditKind::Topology},            {"undo the extrude", EditKind::Topology},
    {"switch the scheme (used before)", EditKind::View}, {"show a second viewport", EditKind::View},
};

}  // namespace

std::string editorEditScript(const Cage& cage, const std::string& timingsPath, uint32_t repeats) {
    const Topology topology = buildTopology(cage);
    // An edge between two quads, away from the first faces; its first vertex and face.
    uint32_t edge = UINT32_MAX;
    for (uint32_t k = 0; k < topology.edgeCount() && edge == UINT32_MAX; ++k) {
        const uint32_t e = (topology.edgeCount() / 2 + k) % topology.edgeCount();
        const uint32_t first = topology.edgeFaceOffsets[e], count = topology.edgeFaceOffsets[e + 1] - first;
        if (count == 2 && cage.faceSize(topology.edgeFaces[first]) == 4 && cage.faceSize(topology.edgeFaces[first + 1]) == 4)
            edge = e;
    }
    if (edge == UINT32_MAX) return {};
    const uint32_t a = topology.edgeVertices[2 * edge], b = topology.edgeVertices[2 * edge + 1];
    const uint32_t face = topology.edgeFaces[topology.edgeFaceOffsets[edge]];
    const std::string ab = std::to_string(a) + "-" + std::to_string(b);
    std::ostringstream s;
    auto timed = [&](int step, const std::string& command) {
        s << "time-frame " << timingsPath << " " << kSteps[step].label << "\n" << command << "\nwait-frames 4\n";
    };
    for (uint32_t r = 0; r < repeats; ++r) {
        s << "select edge " << ab << "\nwait-frames 2\n";
        timed(0, "crease 3");
        timed(1, "undo");
        s << "select vertex " << a << "\nwait-frames 2\n";
        timed(2, "corner 3");
        timed(3, "undo");
        s << "select face " << face << "\nwait-frames 2\n";
        timed(4, "hole on");
        timed(5, "undo");
        s << "select face " << face << "\nwait-frames 2\n";
        timed(6, "extrude 0.05");
        timed(7, "undo");
    }
    s << "clear-selection\n";
    // The first use of a scheme or of a second viewport is not timed: after it, nothing may be
    // created again (pipelines are the device's: render/shared_pipelines.h).
    s << "set-scheme 0 uniform\nwait-frames 3\nset-scheme 0 plans\nwait-frames 3\n";
    for (uint32_t r = 0; r < repeats; ++r) {
        timed(8, "set-scheme 0 uniform");
        timed(8, "set-scheme 0 plans");
    }
    s << "set-viewports 2\nwait-frames 3\nset-viewports 1\nwait-frames 3\n";
    for (uint32_t r = 0; r < repeats; ++r) {
        timed(9, "set-viewports 2");
        s << "set-viewports 1\nwait-frames 4\n";
    }
    return s.str();
}

std::vector<EditorEditTiming> readEditorEditTimings(const std::string& timingsPath) {
    std::map<std::string, std::vector<nlohmann::json>> byLabel;
    std::ifstream in(timingsPath);
    for (std::string line; std::getline(in, line);) {
        nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
        if (j.is_object() && j.contains("cpu_ms")) byLabel[j["label"].get<std::string>()].push_back(j);
    }
    std::vector<EditorEditTiming> out;
    for (const Step& step : kSteps) {
        if (std::any_of(out.begin(), out.end(), [&](const EditorEditTiming& t) { return t.label == step.label; })) continue;
        auto found = byLabel.find(step.label);
        if (found == byLabel.end()) continue;
        EditorEditTiming t;
        t.label = step.label;
        t.kind = step.kind;
        std::vector<double> cpu, interval, plan;
        for (const nlohmann::json& j : found->second) {
            cpu.push_back(j["cpu_ms"].get<double>());
            interval.push_back(j["interval_ms"].get<double>());
            plan.push_back(j.value("plan_engine_ms", 0.0));
            if (!j["views"].empty()) t.viewNote = j["views"][0].value("note", std::string());
        }
        t.count = uint32_t(cpu.size());
        t.cpuMs = median(cpu);
        t.intervalMs = median(interval);
        t.planEngineMs = median(plan);
        out.push_back(t);
    }
    return out;
}

}  // namespace qp::cli
