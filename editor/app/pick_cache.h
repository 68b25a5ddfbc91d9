// PickCache: the structures picking needs (core/edit/picking.h), kept in step with the document:
// the cage raycaster (rebuilt after any change: ~2 ms on 2,000 faces) and the limit-surface
// picker (built on first use; after vertex moves only the sub-faces whose 1-ring holds a moved
// vertex are re-sampled, after tag edits only the sub-faces whose plan or rotation changed, found
// by comparing them with what it was sampled from; after a topology change the kept sub-faces
// keep their samples and only new ones, re-planned ones and those whose ring moved are sampled,
// given the change (noteTopologyChange), else it is built again); and the
// displaced-surface picker the sculpt tool uses (core/displacement/displaced_picker.h), kept the same way and
// also after the samples changed: a dab re-displaces only the sub-faces reading the samples the
// document listed since (Document::takenSamples and unsyncedSamples, read as a stream), so a
// painted frame costs what the dab reached, not a pass over every sample.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "displacement/displaced_picker.h"
#include "document.h"
#include "edit/picking.h"
#include "subface_index.h"

namespace qp::editor {

struct PickCache {
    uint64_t generation = ~0ull, planRevision = ~0ull, topologyRevision = ~0ull;
    uint64_t cageRevision = ~0ull, limitRevision = ~0ull;  // positionRevision each was made for
    std::optional<CageRaycaster> cage;
    std::optional<LimitPicker> limit;
    std::vector<glm::vec3> limitPositions;  // what `limit` was sampled from
    std::vector<uint32_t> limitPlans;       // ... and each sub-face's plan and rotation then
    std::vector<uint64_t> limitRings;       // ... and a hash of each sub-face's ring positions then
    std::vector<uint32_t> replanned;        // sub-faces re-planned since `limit` was sampled
    // Topology edits since `limit` was sampled, composed (previousSubfaceOf from its numbering),
    // and the document's topologyRevision they reach: the limit picker is carried across them.
    EditReport topologySince;
    uint64_t topologySinceRevision = ~0ull;
    VertexSubfaceIndex index;               // vertex -> sub-faces seeing it
    // The displaced picker and what it was sampled from (positions, the displacement's layout
    // revision, and how far into the document's stream of changed samples it has read).
    std::optional<DisplacedPicker> displaced;
    uint64_t displacedRevision = ~0ull, displacedLayout = ~0ull, displacedSampleRevision = ~0ull;
    uint64_t displacedSampleStream = 0;
    std::vector<glm::vec3> displacedPositions;
    std::vector<uint32_t> displacedReplanned;
    double lastDisplacedMs = 0.0;
    uint32_t displacedBuilds = 0;           // times the displaced picker was built whole
    double lastLimitMs = 0.0;
    uint32_t limitBuilds = 0;               // times the limit picker was built whole
};

// Up to date for `document` (adopted as `generation`); the document must have a cage.
const CageRaycaster& cageRaycaster(PickCache& cache, const Document& document, uint64_t generation);
const LimitPicker& limitPicker(PickCache& cache, const Document& document, uint64_t generation);
// Picks the active object's displaced surface (displacementOf(document)); without displacement
// the limit surface.
const DisplacedPicker& displacedPicker(PickCache& cache, const Document& document, uint64_t generation);

// The renderer's plan change of this frame (takeUnsyncedPlanChange), so that the limit picker
// can follow a topology edit instead of being built again.
void noteTopologyChange(PickCache& cache, const Document& document, const EditReport& change);

// Scale for visibility tolerances: the cage's bounding-box diagonal.
float pickTolerance(const Document& document);

}  // namespace qp::editor
