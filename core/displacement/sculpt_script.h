// Scripted strokes: what `quadplan sculpt` reads, so tests and scripts reproduce strokes.
//
// A path is "x,y,z;x,y,z;..." (world space). A stroke file is JSON:
//   {"strokes": [{"brush": "raise", "radius": 0.3, "strength": 0.1,
//                 "falloff": "smooth", "mirror": "x", "spacing": 0.05,
//                 "path": [[0, 1, 0.5], [0.4, 1, 0.2]]}, ...]}
// with brush ("raise", "lower", "smooth", "flatten", "erase", "inflate", "crease", "mask",
// "unmask"; brush.h), radius, strength and path required; falloff (default "smooth"), mirror
// ("none", "x", "y", "z"; default "none") and spacing (default 0: a quarter of the radius)
// optional. An entry {"mask": "invert"} or {"mask": "clear"} is a step on the whole sculpting
// mask instead of a stroke (brush.h: invertMask, clearMask). Steps run in order, each on the
// result of the one before.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "displacement/brush.h"
#include "mesh/result.h"

namespace qp {

enum class WholeMaskStep { None, Invert, Clear };

struct ScriptedStroke {
    StrokeOptions options;
    std::vector<glm::vec3> path;
    WholeMaskStep wholeMask = WholeMaskStep::None;  // not None: this entry is that step, not a stroke
};

// Errors name the point ("point 2 ...").
Result<std::vector<glm::vec3>> parsePath(std::string_view text);

// A stroke is dabbed every `spacing` along its path; more than this many dabs (a tiny spacing
// on a long path) would run for hours, so such a stroke is refused.
inline constexpr double kMaxDabsPerStroke = 1e6;

// Refuses a stroke with more than kMaxDabsPerStroke dabs, naming the numbers.
Status checkStrokeLength(const ScriptedStroke& stroke);

// Errors read "<source>: strokes[i].<field>: <what is wrong>". Every stroke passed checkStrokeLength.
Result<std::vector<ScriptedStroke>> parseStrokeFile(std::string_view text, const std::string& source);

}  // namespace qp
