// The edits `quadplan bench editor` times in the real editor (issue 15): a crease, a corner, a
// hole and a one-face extrude, the undo of each, a scheme switch and a second viewport. Each is
// one automation command preceded by `time-frame` (docs/editor.md), so what is timed is the
// frame that applied the edit and drew it: the plan engine, every viewport's scheme update (in
// place or a rebuild), recording. bench_editor.cpp compares the medians with the vertex-drag frames
// of the same editor run.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/cage.h"

namespace qp::cli {

enum class EditKind { Tag, Topology, View };

// Automation lines that make every timed step `repeats` times on `cage` (as the editor loads
// it), appending their timings to `timingsPath`; empty when the cage has no interior edge
// between two quads to edit.
std::string editorEditScript(const Cage& cage, const std::string& timingsPath, uint32_t repeats);

struct EditorEditTiming {
    std::string label;
    EditKind kind = EditKind::Tag;
    uint32_t count = 0;
    double cpuMs = 0.0, intervalMs = 0.0, planEngineMs = 0.0;  // medians
    std::string viewNote;  // how the first viewport took the last one (in place, rebuilt: why)
};

// Medians per step, in the script's order; a step with no timing is left out.
std::vector<EditorEditTiming> readEditorEditTimings(const std::string& timingsPath);

}  // namespace qp::cli
