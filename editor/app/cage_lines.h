// The cage's edges as the viewport draws them (plain and creased lines, render/line_pass.h),
// kept per edge so that the frame after a vertex move or a tag edit rewrites only the edges it
// touched instead of every edge of the cage (13-20 ms at 100k faces).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "line_pass.h"
#include "mesh/cage.h"
#include "mesh/topology.h"

namespace qp::editor {

struct CageLines {
    static constexpr uint32_t kNotShown = UINT32_MAX, kCreased = 1u << 31;
    std::vector<LineVertex> plain, creased;  // two vertices per line
    std::vector<uint32_t> lineOf;            // per topology edge: its line (| kCreased), or kNotShown
    std::vector<uint32_t> plainEdge, creasedEdge;  // per line: its edge
    // What changed since takeChanges: lines of each set (sorted, unique on taking), or the set whole.
    std::vector<uint32_t> changedPlain, changedCreased;
    bool wholePlain = true, wholeCreased = true;
    // For plainLinesReadable, as of the last rebuild: the 90th percentile of the plain edges'
    // lengths.
    float longPlainEdge = 0.0f;
};

// Plain edges must draw this long, in pixels, near the eye for plain lines to be drawn: 2-pixel
// lines (kCageLineWidth) along edges shorter than 8 pixels cover half the surface or more.
inline constexpr float kReadableEdgePixels = 8.0f;

// Whether the plain lines are worth drawing in a view (`viewProjection`, `eye` and
// `pixelsPerUnit` as plan_pass.h's DrawView has them): the longer plain edges (longPlainEdge)
// would draw at least kReadableEdgePixels long at the point of the cage's box (`cageBounds`)
// nearest the eye.
// Denser than that, plain lines only darken the surface under them, and on lavapipe a million
// faces' two million lines cost more than the surface (docs/editor.md). Creased lines are
// always drawn; an eye inside the box always sees plain lines.
bool plainLinesReadable(const CageLines& lines, const Bounds& cageBounds, const glm::mat4& viewProjection,
                        const glm::vec3& eye, float pixelsPerUnit);

// Every edge that `shown` accepts (an empty function: every edge), in edge order.
void rebuildCageLines(CageLines& lines, const Cage& cage, const Topology& topology,
                      const std::function<bool(uint32_t edge)>& shown);

// The lines at `vertices` follow their new positions.
void moveCageLines(CageLines& lines, const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices);

// The edges of `faces` take their sharpness now: colour, and the creased set or the plain one.
// Every edge whose sharpness a tag edit changed is an edge of a face it re-planned.
void retagCageLines(CageLines& lines, const Cage& cage, const Topology& topology, std::span<const uint32_t> faces);

}  // namespace qp::editor
