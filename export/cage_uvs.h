// CageUvs: the cage's texture coordinates over the limit surface, at (sub-face, u, v).
//
// Two ways to carry the cage's face-varying UVs onto the surface:
//   - Linear: bilinear over each face's corner UVs (an n-gon's sub-face k over corner k, the
//     midpoints of edges k and k-1 and the face's centre), as NVIDIA's RTXMG does. Exact at the
//     cage's corners, C0 across faces.
//   - Smooth: OpenSubdiv's face-varying limit surface (Bfr) with the cage's own face-varying rule
//     (Cage::fvarInterpolation), what a renderer that subdivides the cage (RenderMan, Arnold,
//     Cycles) puts on the same surface. Seams stay seams: each face sees its own UV island.
//
// A vertex that two faces share gets the UV each face gives it; on a seam those differ and the
// exporters split the vertex (limit_mesh.h). Smooth UVs from the two sides of a non-seam edge
// agree to float rounding only, so sameUv() compares with a tolerance relative to the UV extent.
#pragma once

#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "mesh/result.h"
#include "plans/planned_cage.h"

namespace qp {

enum class UvMode { None, Linear, Smooth };

// "none", "linear", "smooth"; an error names the choices.
Result<UvMode> parseUvMode(const std::string& name);
const char* uvModeName(UvMode mode);

class CageUvs {
public:
    // Fails when the cage has no texture coordinates (OBJ 'vt' with 'f v/vt') or, for Smooth,
    // when OpenSubdiv rejects the face-varying topology. `mode` must not be None.
    static Result<CageUvs> create(const PlannedCage& planned, UvMode mode, const std::string& source = "cage");
    ~CageUvs();
    CageUvs(CageUvs&&) noexcept;
    CageUvs& operator=(CageUvs&&) noexcept;

    // The UV at (u, v) of a sub-face that has a surface. Safe to call concurrently.
    glm::vec2 at(uint32_t subface, float u, float v) const;
    // Whether two UVs of one surface point are the same vertex's (not a seam).
    bool sameUv(glm::vec2 a, glm::vec2 b) const;

    UvMode mode() const { return mode_; }
    uint32_t faceOf(uint32_t subface) const { return faceOfSubface_[subface]; }

private:
    CageUvs() = default;
    glm::vec2 linearAt(uint32_t subface, float u, float v) const;

    const PlannedCage* planned_ = nullptr;
    UvMode mode_ = UvMode::None;
    std::vector<uint32_t> faceOfSubface_;
    float tolerance_ = 0.0f;
    struct SmoothSurfaces;  // Bfr's face-varying surfaces, one per face
    std::unique_ptr<SmoothSurfaces> smooth_;
};

}  // namespace qp
