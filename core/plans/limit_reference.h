// LimitReference: OpenSubdiv's own evaluation of the limit surface (Far adaptive patch table),
// the reference subdivision plans are checked against.
//
// Built the way OpenSubdiv's own regression compares like with like: adaptive refinement to
// the same depth as the plans, Gregory-basis end caps, infinitely sharp patches. Single-crease
// patches stay off because Far::PatchTable::EvaluateBasis ignores their sharpness; Far then
// isolates semi-sharp creases instead, which is exact up to that depth.
// One change to Far's end caps, as in the plans: at a dart their corner tangents are moved onto
// the exact limit tangent plane (core/plans/tangent_plane.h); Far's are Sdc's smooth-rule masks there.
// Sub-faces are Ptex faces, numbered as in PlannedCage.
#pragma once

#include <memory>

#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "mesh/result.h"

#include <opensubdiv/version.h>

namespace OpenSubdiv {
namespace OPENSUBDIV_VERSION::Far {
class PatchTable;
class PatchMap;
}  // namespace OPENSUBDIV_VERSION::Far
using namespace OPENSUBDIV_VERSION;
}  // namespace OpenSubdiv

namespace qp {

struct ReferenceSample {
    glm::dvec3 position{0.0}, du{0.0}, dv{0.0};
};

class LimitReference {
public:
    static Result<LimitReference> create(const Cage& cage, uint32_t depth, const std::string& source);
    ~LimitReference();
    LimitReference(LimitReference&&) noexcept;
    LimitReference& operator=(LimitReference&&) noexcept;

    uint32_t subfaceCount() const { return subfaces_; }
    ReferenceSample evaluate(uint32_t subface, double u, double v) const;

private:
    LimitReference() = default;
    std::unique_ptr<OpenSubdiv::Far::PatchTable> patches_;
    std::unique_ptr<OpenSubdiv::Far::PatchMap> map_;
    std::vector<glm::dvec3> points_;  // every refined vertex, then the end-cap local points
    uint32_t subfaces_ = 0;
};

}  // namespace qp
