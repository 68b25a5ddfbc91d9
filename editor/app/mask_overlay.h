// The sculpting mask made visible: a dark dot at the displaced position of every masked sample
// (alpha by its mask value), drawn over the picture by the overlays while the sculpt tool is
// active. Gathered again only when the mask, the samples, the layout or the cage changed; at
// most kMaxMaskDots of them (every k-th masked sample beyond that), so a mask over a whole
// 128k-sample model stays a fraction of a millisecond to draw.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace qp::editor {

struct Document;

inline constexpr uint32_t kMaxMaskDots = 30000;

struct MaskDots {
    uint64_t generation = ~0ull, displacementRevision = ~0ull, sampleRevision = ~0ull, maskRevision = ~0ull,
             positionRevision = ~0ull;
    std::vector<glm::vec3> positions, normals;  // displaced position, limit normal (to skip back-facing dots)
    std::vector<float> values;                  // mask value, (0, 1]
    uint32_t masked = 0;                        // masked samples in all (more than the dots when capped)
};

// Brings the dots up to date with the document's active displacement (builds the brushes'
// samples cache if it is missing: the sites of the samples).
void updateMaskDots(MaskDots& dots, Document& document, uint64_t generation);

}  // namespace qp::editor
