#include "schemes.h"

#include <algorithm>

namespace qp::editor {

namespace {
constexpr const char* kSchemes[] = {"plans"};
constexpr const char* kColorModes[] = {"shading", "node-kind", "depth", "sharpness"};
}  // namespace

std::span<const char* const> availableSchemes() { return kSchemes; }

bool isSchemeAvailable(std::string_view scheme) {
    return std::any_of(std::begin(kSchemes), std::end(kSchemes), [&](const char* s) { return scheme == s; });
}

std::span<const char* const> colorModeNames() { return kColorModes; }

std::optional<ColorBy> parseColorMode(std::string_view name) {
    if (name == "shading") return ColorBy::Shading;
    if (name == "node-kind" || name == "patch-kind") return ColorBy::NodeKind;
    if (name == "depth" || name == "plan-depth") return ColorBy::PlanDepth;
    if (name == "sharpness") return ColorBy::Sharpness;
    return std::nullopt;
}

const char* colorModeName(ColorBy mode) { return kColorModes[uint32_t(mode)]; }

}  // namespace qp::editor
