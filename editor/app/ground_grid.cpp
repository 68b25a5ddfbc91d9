#include "ground_grid.h"

#include <algorithm>
#include <cmath>

namespace qp::editor {

namespace {

const glm::vec3 kGridColor(0.5f, 0.51f, 0.55f), kMajorColor(0.7f, 0.71f, 0.75f);  // linear
const glm::vec3 kXAxisColor(0.75f, 0.2f, 0.2f), kYAxisColor(0.3f, 0.65f, 0.2f), kZAxisColor(0.2f, 0.35f, 0.8f);
constexpr int kSegmentsPerLine = 16;  // so the fade follows the distance along each line

}  // namespace

GroundGrid groundGrid(const Bounds& model, UpAxis up, const glm::vec3& background) {
    GroundGrid grid;
    const float radius = std::max(0.5f * model.diagonal(), 1e-3f);
    // About ten lines across the model, at a round step (1, 2 or 5 times a power of ten).
    const float target = radius / 5.0f, decade = std::pow(10.0f, std::floor(std::log10(target)));
    grid.spacing = target <= decade ? decade : target <= 2.0f * decade ? 2.0f * decade : target <= 5.0f * decade ? 5.0f * decade : 10.0f * decade;
    const int half = int(std::ceil(2.0f * radius / grid.spacing));
    const int upIndex = up == UpAxis::Z ? 2 : 1, second = up == UpAxis::Z ? 1 : 2;  // the plane's axes: x and `second`
    grid.height = model.min[upIndex];
    const glm::vec3 secondAxisColor = up == UpAxis::Z ? kYAxisColor : kZAxisColor;
    const glm::vec3 centre = 0.5f * (model.min + model.max);
    // Snapped to the spacing so that lines through the origin stay on the world axes.
    const float cx = std::round(centre.x / grid.spacing) * grid.spacing;
    const float cs = std::round(centre[second] / grid.spacing) * grid.spacing;
    const float reach = float(half) * grid.spacing;
    auto point = [&](float a, float b) {
        glm::vec3 p(0.0f);
        p.x = a;
        p[second] = b;
        p[upIndex] = grid.height;
        return p;
    };
    auto fade = [&](const glm::vec3& color, float a, float b) {
        const float d = std::hypot(a - cx, b - cs) / reach;
        return glm::mix(color, background, std::clamp(d * d, 0.0f, 1.0f));
    };
    // One line along the plane's first axis (alongX) or its second, at `offset` on the other.
    auto line = [&](bool alongX, float offset, const glm::vec3& color) {
        for (int k = 0; k < kSegmentsPerLine; ++k) {
            const float t0 = -reach + 2.0f * reach * float(k) / kSegmentsPerLine;
            const float t1 = -reach + 2.0f * reach * float(k + 1) / kSegmentsPerLine;
            const float a0 = alongX ? cx + t0 : offset, b0 = alongX ? offset : cs + t0;
            const float a1 = alongX ? cx + t1 : offset, b1 = alongX ? offset : cs + t1;
            grid.lines.push_back({point(a0, b0), fade(color, a0, b0)});
            grid.lines.push_back({point(a1, b1), fade(color, a1, b1)});
        }
    };
    for (int i = -half; i <= half; ++i) {
        const float x = cx + float(i) * grid.spacing, s = cs + float(i) * grid.spacing;
        const bool xAxis = std::abs(s) < 0.5f * grid.spacing, secondAxis = std::abs(x) < 0.5f * grid.spacing;
        const bool majorX = std::lround(s / grid.spacing) % 10 == 0, majorS = std::lround(x / grid.spacing) % 10 == 0;
        line(true, s, xAxis ? kXAxisColor : majorX ? kMajorColor : kGridColor);
        line(false, x, secondAxis ? secondAxisColor : majorS ? kMajorColor : kGridColor);
    }
    return grid;
}

}  // namespace qp::editor
