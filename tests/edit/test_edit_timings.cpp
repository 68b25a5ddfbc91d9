// Timings of every editing operation on a ~2,000-face cage, for docs/editing.md. Not a
// benchmark target and not run by default (timed unit tests are banned: the machine is noisy);
// run it by hand:
//     ./build/bin/quadplan_tests --gtest_also_run_disabled_tests --gtest_filter='EditTimings.*'
// It prints a Markdown table of medians, each as wall-clock / CPU milliseconds: the CPU time
// (process CPU clock, all threads) shows the work itself when other jobs share the cores and
// stretch the wall clock. It still asserts that every edit succeeded and that the cage equals
// its rebuild at the end, so its numbers describe correct work.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <random>

#include <time.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "edit/edit_history.h"
#include "edit/picking.h"
#include "edit/selection.h"
#include "edit/transform.h"
#include "mesh/generated_cage.h"

namespace {

double cpuNow() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// Wall and CPU milliseconds since construction.
struct Stopwatch {
    std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
    double cpu = cpuNow();
    std::pair<double, double> elapsed() const {
        return {std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall).count(), cpuNow() - cpu};
    }
};
using Clock = Stopwatch;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

using Times = std::vector<std::pair<double, double>>;

struct Row {
    std::string name;
    Times operation, apply, undo;
    std::vector<double> replanned, newPlans;
};

std::string cell(const Times& times) {
    if (times.empty()) return "";
    std::vector<double> wall, cpu;
    for (auto [w, c] : times) {
        wall.push_back(w);
        cpu.push_back(c);
    }
    char text[64];
    std::snprintf(text, sizeof text, "%.3g / %.3g", median(wall), median(cpu));
    return text;
}

void print(const Row& r) {
    std::printf("| %s | %zu | %s | %s | %s | %.0f | %.0f |\n", r.name.c_str(), r.apply.size(), cell(r.operation).c_str(),
                cell(r.apply).c_str(), cell(r.undo).c_str(), median(r.replanned), median(r.newPlans));
}

}  // namespace

TEST(EditTimings, DISABLED_MediansOnA2000FaceCage) {
    qp::PlanDatabase db;
    qp::Cage start = qp::makeBenchmarkCage(2000, 1);
    auto created = qp::PlannedCage::create(start, db, {}, "generated");
    ASSERT_TRUE(created.ok());
    qp::PlannedCage planned = std::move(created).value();
    qp::EditHistory history;
    std::mt19937 rng(5);
    const int repeats = 15;
    std::printf("cage: %u faces, %u vertices, %u sub-faces\n", planned.cage().faceCount(), planned.cage().vertexCount(),
                planned.subfaceCount());
    std::printf("milliseconds as wall / CPU medians\n\n");
    std::printf("| edit | runs | operation ms | apply (re-plan) ms | undo ms | faces re-planned | new plans |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|\n");

    // A topology operation: build the edit, apply it through the history, then undo it.
    auto topology = [&](const std::string& name, const std::function<qp::Result<qp::TopologyEdit>()>& make) {
        Row row;
        row.name = name;
        for (int i = 0; i < repeats; ++i) {
            auto t0 = Clock();
            auto edit = make();
            const auto operation = t0.elapsed();
            if (!edit) continue;  // a random spot the operation refuses: try the next
            auto t1 = Clock();
            auto report = history.applyTopologyEdit(planned, name, std::move(edit).value());
            const auto apply = t1.elapsed();
            ASSERT_TRUE(report.ok()) << report.error().message;
            auto t2 = Clock();
            ASSERT_TRUE(history.undo(planned).ok());
            row.undo.push_back(t2.elapsed());
            row.operation.push_back(operation);
            row.apply.push_back(apply);
            row.replanned.push_back(report->replannedFaces);
            row.newPlans.push_back(report->newPlans);
        }
        print(row);
    };
    auto randomFace = [&] { return uint32_t(rng() % planned.cage().faceCount()); };
    auto randomEdge = [&] {
        const qp::Topology& t = planned.topology();
        const uint32_t e = rng() % t.edgeCount();
        return qp::EdgeKey{t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1]};
    };

    topology("extrude 1 face", [&] {
        uint32_t f = randomFace();
        return qp::extrudeFaces(planned.cage(), planned.topology(), {&f, 1}, 0.05f);
    });
    topology("extrude 3x3 faces (grown region)", [&] {
        qp::Selection s;
        s.mode = qp::SelectionMode::Face;
        s.faces = {randomFace()};
        s = qp::growSelection(s, planned.cage(), planned.topology());
        return qp::extrudeFaces(planned.cage(), planned.topology(), s.faces, 0.05f);
    });
    topology("delete 1 face (keep vertices)", [&] {
        uint32_t f = randomFace();
        return qp::deleteFaces(planned.cage(), planned.topology(), {&f, 1}, false);
    });
    topology("delete 3x3 faces (remove vertices)", [&] {
        qp::Selection s;
        s.mode = qp::SelectionMode::Face;
        s.faces = {randomFace()};
        s = qp::growSelection(s, planned.cage(), planned.topology());
        return qp::deleteFaces(planned.cage(), planned.topology(), s.faces, true);
    });
    topology("split face", [&] {
        uint32_t f = randomFace();
        const uint32_t* v = planned.cage().faceBegin(f);
        return qp::splitFace(planned.cage(), planned.topology(), f, v[0], v[2]);
    });
    topology("insert edge loop", [&] {
        qp::EdgeKey e = randomEdge();
        return qp::insertEdgeLoop(planned.cage(), planned.topology(), e.v0, e.v1, 0.5f);
    });
    topology("merge 2 vertices (collapse edge)", [&] {
        qp::EdgeKey e = randomEdge();
        uint32_t pair[2] = {e.v0, e.v1};
        return qp::mergeVertices(planned.cage(), planned.topology(), pair);
    });
    int deletesToUndo = 0;
    topology("make face (after deleting it)", [&]() -> qp::Result<qp::TopologyEdit> {
        uint32_t f = randomFace();
        std::vector<uint32_t> vertices(planned.cage().faceBegin(f), planned.cage().faceBegin(f) + planned.cage().faceSize(f));
        auto removed = qp::deleteFaces(planned.cage(), planned.topology(), {&f, 1}, false);
        if (!removed) return removed.error();
        if (!history.applyTopologyEdit(planned, "delete", std::move(removed).value()).ok()) return qp::Error{"refused"};
        ++deletesToUndo;
        return qp::makeFace(planned.cage(), planned.topology(), vertices);
    });
    for (; deletesToUndo > 0; --deletesToUndo) ASSERT_TRUE(history.undo(planned).ok());
    ASSERT_EQ(planned.cage().faceCount(), start.faceCount());

    // Non-topological edits.
    auto simple = [&](const std::string& name, const std::function<qp::Result<qp::EditReport>()>& run) {
        Row row;
        row.name = name;
        for (int i = 0; i < repeats; ++i) {
            auto t1 = Clock();
            auto report = run();
            const auto apply = t1.elapsed();
            ASSERT_TRUE(report.ok()) << report.error().message;
            auto t2 = Clock();
            ASSERT_TRUE(history.undo(planned).ok());
            row.undo.push_back(t2.elapsed());
            row.apply.push_back(apply);
            row.replanned.push_back(report->replannedFaces);
            row.newPlans.push_back(report->newPlans);
        }
        print(row);
    };
    simple("move 1 vertex", [&] {
        uint32_t v = rng() % planned.cage().vertexCount();
        glm::vec3 p = planned.cage().positions[v] + glm::vec3(0.01f);
        return history.moveVertices(planned, "move", {&v, 1}, {&p, 1});
    });
    simple("rotate 3x3 faces (16 vertices) about their centroid", [&] {
        qp::Selection s;
        s.mode = qp::SelectionMode::Face;
        s.faces = {randomFace()};
        s = qp::growSelection(s, planned.cage(), planned.topology());
        std::vector<uint32_t> vertices = qp::selectedVertices(s, planned.cage());
        qp::TransformFrame frame = qp::makeTransformFrame(planned.cage(), planned.topology(), vertices, qp::TransformSpace::Local);
        auto moved = qp::transformPoints(qp::positionsOf(planned.cage(), vertices), qp::rotation(frame, {0, 0, 1}, 20.0f));
        return history.moveVertices(planned, "rotate", vertices, *moved);
    });
    simple("set edge crease", [&] {
        qp::EdgeKey e = randomEdge();
        qp::EdgeCrease c{e.v0, e.v1, 2.0f + float(rng() % 8) * 0.25f};
        return history.setEdgeSharpness(planned, "crease", {&c, 1});
    });
    simple("set vertex corner", [&] {
        qp::VertexCorner c{uint32_t(rng() % planned.cage().vertexCount()), 1.5f};
        return history.setVertexSharpness(planned, "corner", {&c, 1});
    });
    simple("toggle hole", [&] {
        uint32_t f = randomFace();
        return history.setHoles(planned, "hole", {&f, 1}, !planned.cage().isHole(f));
    });
    simple("crease method (every face)", [&] {
        return history.setCreaseMethod(planned, "method",
                                       planned.cage().options.creaseMethod == qp::CreaseMethod::Normal ? qp::CreaseMethod::Chaikin
                                                                                                      : qp::CreaseMethod::Normal);
    });

    // Picking.
    Times pickerBuild, limitRay, cageBuild, cageRay, vertexPick, box, pickerUpdate;
    glm::vec3 lo = planned.cage().positions[0], hi = lo;
    for (const glm::vec3& p : planned.cage().positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    glm::mat4 projection = glm::perspective(glm::radians(40.0f), 4.0f / 3.0f, 0.1f, 100.0f);
    projection[1][1] *= -1.0f;
    const glm::vec3 centre = 0.5f * (lo + hi);
    qp::PickView view{projection * glm::lookAt(centre + glm::vec3(0.8f, 0.6f, 1.0f) * glm::length(hi - lo), centre, {0, 1, 0}), {1024, 768}};
    for (int i = 0; i < repeats; ++i) {
        auto t0 = Clock();
        qp::LimitPicker picker(planned, 8);
        pickerBuild.push_back(t0.elapsed());
        glm::vec2 pixel(float(400 + rng() % 200), float(300 + rng() % 150));
        auto t1 = Clock();
        picker.intersect(planned, view.rayThrough(pixel));
        limitRay.push_back(t1.elapsed());
        auto t2 = Clock();
        qp::CageRaycaster raycaster(planned.cage());
        cageBuild.push_back(t2.elapsed());
        auto t3 = Clock();
        qp::pickFace(raycaster, view, pixel);
        cageRay.push_back(t3.elapsed());
        qp::Occluder occluder = qp::cageOccluder(raycaster, 1e-4f * glm::length(hi - lo));
        auto t4 = Clock();
        qp::pickVertex(planned.cage(), view, pixel, 8.0f, &occluder);
        vertexPick.push_back(t4.elapsed());
        auto t5 = Clock();
        qp::boxSelect(planned.cage(), planned.topology(), qp::SelectionMode::Vertex, view, pixel, pixel + glm::vec2(200, 150), &occluder);
        box.push_back(t5.elapsed());
        uint32_t v = rng() % planned.cage().vertexCount();
        glm::vec3 p = planned.cage().positions[v] + glm::vec3(0.01f);
        auto report = planned.moveVertices({&v, 1}, {&p, 1});
        auto t6 = Clock();
        picker.update(planned, *report);
        pickerUpdate.push_back(t6.elapsed());
    }
    std::printf("\n| picking | ms (wall / CPU) |\n|---|---:|\n");
    std::printf("| LimitPicker build (9x9 samples per sub-face) | %s |\n", cell(pickerBuild).c_str());
    std::printf("| LimitPicker update after a 1-vertex move | %s |\n", cell(pickerUpdate).c_str());
    std::printf("| limit-surface ray pick (with Newton) | %s |\n", cell(limitRay).c_str());
    std::printf("| CageRaycaster build | %s |\n", cell(cageBuild).c_str());
    std::printf("| cage face pick | %s |\n", cell(cageRay).c_str());
    std::printf("| vertex pick, visible only | %s |\n", cell(vertexPick).c_str());
    std::printf("| box select 200x150 px, vertices, visible only | %s |\n", cell(box).c_str());

    std::vector<std::string> differences = planned.differencesFromRebuild();
    EXPECT_TRUE(differences.empty()) << differences[0];
}
