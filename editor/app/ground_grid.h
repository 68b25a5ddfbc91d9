// The ground grid under the model: lines on the plane across the up axis through the model's
// lowest point, about ten across the model at a round step (1, 2 or 5 times a power of ten),
// every tenth line brighter, reaching about twice its radius and fading into the background
// towards the rim (LinePass has no blending: the fade is in the vertex colours). The two world
// axes lying in the plane are drawn in their axis colours (x red, y green, z blue).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "line_pass.h"
#include "mesh/cage.h"
#include "scene/scene.h"

namespace qp::editor {

struct GroundGrid {
    std::vector<LineVertex> lines;
    float spacing = 1.0f;  // world units between neighbouring lines
    float height = 0.0f;   // the plane's coordinate along the up axis
};

GroundGrid groundGrid(const Bounds& model, UpAxis up, const glm::vec3& background);

}  // namespace qp::editor
