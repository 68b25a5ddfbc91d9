// Names a viewport can show: patching schemes and colour modes. Scene files keep both as
// open-ended strings (plugins add schemes); until the scheme plugins land, `plans` is the only
// scheme this build draws, and a viewport naming another says so instead of drawing.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "plan_pass.h"

namespace qp::editor {

std::span<const char* const> availableSchemes();
bool isSchemeAvailable(std::string_view scheme);

// Colour modes offered in the UI, in order: shading, node-kind, depth, sharpness.
std::span<const char* const> colorModeNames();
// Also accepts the scene format's older spellings ("patch-kind", "plan-depth").
std::optional<ColorBy> parseColorMode(std::string_view name);
const char* colorModeName(ColorBy mode);

}  // namespace qp::editor
