// The ground grid under the model: lines on the plane across the up axis through the model's
// lowest point, spaced by a power of ten of about a tenth of the model's size and reaching about
// twice its radius, fading into the background towards the rim (LinePass has no blending: the
// fade is in the vertex colours). The two world axes lying in the plane are drawn in their axis
// colours (x red, y green, z blue) where they cross the grid.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "cage.h"
#include "line_pass.h"
#include "scene.h"

namespace qp::editor {

struct GroundGrid {
    std::vector<LineVertex> lines;
    float spacing = 1.0f;  // world units between neighbouring lines
    float height = 0.0f;   // the plane's coordinate along the up axis
};

GroundGrid groundGrid(const Bounds& model, UpAxis up, const glm::vec3& background);

}  // namespace qp::editor
