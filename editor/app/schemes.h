// Colour-mode names a viewport can ask its scheme for. Scene files keep schemes and colour
// modes as open-ended strings (each scheme plugin lists its own modes: Scheme::colorModes);
// this maps the scene format's older spellings to the plugins' names.
#pragma once

#include <string>
#include <string_view>

namespace qp::editor {

// "patch-kind" -> "node-kind", "plan-depth" -> "depth"; anything else as it is ("shading" when empty).
std::string canonicalColorMode(std::string_view name);

}  // namespace qp::editor
