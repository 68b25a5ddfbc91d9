#include "draw_path.h"

namespace qp {

DrawPath resolveDrawPath(DrawPath requested, const VulkanContext& context) {
    if (requested != DrawPath::Auto) return requested;
    return context.isSoftware ? DrawPath::Grid : DrawPath::Tessellated;
}

const char* drawPathName(DrawPath path) {
    switch (path) {
    case DrawPath::Auto: return "auto";
    case DrawPath::Tessellated: return "tess";
    case DrawPath::Grid: return "grid";
    }
    return "?";
}

std::optional<DrawPath> parseDrawPath(std::string_view name) {
    if (name == "auto") return DrawPath::Auto;
    if (name == "tess") return DrawPath::Tessellated;
    if (name == "grid") return DrawPath::Grid;
    return std::nullopt;
}

}  // namespace qp
