#include "animation/animation_playback.h"

namespace qp {

std::vector<glm::vec3> positionsAtFrame(const ObjectAnimation& animation, std::span<const glm::vec3> rest, double frame) {
    std::vector<glm::vec3> positions(rest.size());
    evaluatePositions(animation.vertexKeys, animation.interpolation, rest, frame, positions);
    return positions;
}

Result<EditReport> showFrame(PlannedCage& planned, const ObjectAnimation& animation, std::span<const glm::vec3> rest,
                             double frame) {
    const std::vector<glm::vec3>& shown = planned.cage().positions;
    if (rest.size() != shown.size())
        return Error{"the animation's rest positions are for " + std::to_string(rest.size()) +
                     " vertices but the cage has " + std::to_string(shown.size())};
    std::vector<glm::vec3> positions = positionsAtFrame(animation, rest, frame);
    std::vector<uint32_t> moved;
    for (uint32_t v = 0; v < positions.size(); ++v)
        if (positions[v] != shown[v]) moved.push_back(v);
    if (moved.size() == positions.size()) return planned.moveVertices(moved, positions);
    std::vector<glm::vec3> movedPositions;
    movedPositions.reserve(moved.size());
    for (uint32_t v : moved) movedPositions.push_back(positions[v]);
    return planned.moveVertices(moved, movedPositions);
}

}  // namespace qp
