// DisplacedDrawing: a scheme's displaced surface as a GPU mesh that brush dabs update in place.
// The schemes that draw displacement as a CPU mesh (uniform, osd-fas, and acc1, acc2, pn, stam
// through GridDrawing) build it in update() and hand Scheme::displacementChanged to
// updateDisplacedDrawing: only the sub-faces that read the changed samples are re-displaced,
// from the undisplaced frames kept per vertex (no surface evaluation: the surface did not move),
// and their vertices rewritten in the mapped vertex buffer. The bits equal a full rebuild's
// (core/displacement/displaced_mesh.h, redisplaceGrids).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "displacement/displaced_mesh.h"
#include "displacement/displacement_users.h"
#include "mesh_pass.h"
#include "scheme_api.h"

namespace qp {

struct DisplacedDrawing {
    DisplacedMesh mesh;
    DisplacementUsers users;
    std::vector<uint32_t> gridOfSubface;  // PlannedCage sub-face -> its grid in `mesh` (or UINT32_MAX)
    GpuMesh gpu;
    const VulkanContext* context = nullptr;
    const Displacement* displacement = nullptr;  // what it was built from (samples change in place)
};

// Scheme::setDisplacement's argument as a scheme keeps it: nullptr for none or an empty one.
inline const Displacement* displacementToDraw(const Displacement* displacement) {
    return displacement && !displacement->empty() ? displacement : nullptr;
}

// Builds the scheme's displaced mesh at `factor` (displacedGridFactor) and uploads it, replacing
// what `drawing` held. The scheme's evaluate() must be ready (call after its own update work).
Status buildDisplacedDrawing(DisplacedDrawing& drawing, const VulkanContext& context, const Scheme& scheme,
                             const PlannedCage& planned, const Displacement& displacement, uint32_t factor);

// `samples` of the displacement it was built from changed in place; a no-op when nothing was
// built. The device must not be using the vertex buffer (Scheme::displacementChanged's
// contract), so a scheme's displacementChanged can simply return this.
Status updateDisplacedDrawing(DisplacedDrawing& drawing, std::span<const uint32_t> samples);

void destroyDisplacedDrawing(DisplacedDrawing& drawing);

}  // namespace qp
