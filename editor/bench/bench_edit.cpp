// `quadplan bench edit`: every kind of tag and topology edit against OpenSubdiv rebuilding the
// whole cage.
#include <array>
#include <functional>

#include "bench_report.h"
#include "bench_stats.h"
#include "edit/edit_history.h"
#include "mesh/topology_edits.h"
#include "plans/osd_refiner.h"

namespace qp::cli {

// Every kind of tag and topology edit the editor makes, through EditHistory on a PlannedCage
// (as the editor and the Python module do it: the topology operation, the incremental re-plan,
// the history record), against OpenSubdiv rebuilding the whole cage (refiner, adaptive
// refinement, patch table), which a renderer built on Far needs after such an edit. Each edit
// is done and undone R times on the same element; rows give the medians of the do and of the
// undo. Vertex moves are the plans suite's row (c): neither side rebuilds for them.

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

}  // namespace qp::cli
