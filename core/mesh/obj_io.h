// Wavefront OBJ import/export that keeps OpenSubdiv's subdivision tags.
//
// Besides `v`, `vt` and `f`, OpenSubdiv's shapes carry tag lines
//     t <name> <nInts>/<nFloats>/<nStrings> <ints...> <floats...> <strings...>
// for creases, corners, holes and the subdivision options; they are read into the Cage's tag
// lists and options and written back, so load -> save -> load is lossless.
//
// Normals (`vn`) are not kept: a subdivision surface derives its own.
// Repeated consecutive face vertices (OpenSubdiv writes `f 4 3 5 5` for a triangle) are
// collapsed, and faces left with fewer than 3 vertices dropped, with a warning; a face that
// visits a vertex twice non-consecutively is kept (non-manifold, as OpenSubdiv keeps it).
// `t interpolateboundary` uses OpenSubdiv's regression numbering: 0 none, 1 edges and corners,
// 2 edges only; without the tag a file means edges only, as OpenSubdiv reads it.
// Hierarchical edits (`vertexedit`, `edgeedit`, `faceedit`) and other unknown tags are
// skipped with a warning.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

// Parses OBJ text. `source` (usually the path) prefixes every message; errors name the line:
// "<source>:<line>: ...". Warnings (things skipped or repaired) are appended to *warnings when
// given. The result has passed normalizeTags() and validateCage().
Result<Cage> parseObj(std::string_view text, const std::string& source,
                      std::vector<std::string>* warnings = nullptr);

// Reads `path` and parses it; messages are prefixed with the path.
Result<Cage> loadObj(const std::string& path, std::vector<std::string>* warnings = nullptr);

// Writes v, vt, f (v/vt when the cage has UVs), then t lines: crease, corner, hole, options.
// Floats are written in their shortest round-trip form, so parseObj gives back the same floats.
std::string formatObj(const Cage& cage);

// formatObj + writeFileAtomically: the file is either replaced whole or left untouched.
Status saveObj(const Cage& cage, const std::string& path);

}  // namespace qp
