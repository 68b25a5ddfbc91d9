#include "schemes.h"

namespace qp::editor {

std::string canonicalColorMode(std::string_view name) {
    if (name.empty()) return "shading";
    if (name == "patch-kind") return "node-kind";
    if (name == "plan-depth") return "depth";
    return std::string(name);
}

}  // namespace qp::editor
