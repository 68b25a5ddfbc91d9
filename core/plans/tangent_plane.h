// Where the limit surface has no tangent plane: the corners of faces at which a comparison of
// normals has nothing exact to compare with.
//
// Catmull-Clark's corner rule (a vertex that stays where it is: infinitely sharp, or where
// three or more infinitely sharp, boundary or non-manifold edges meet) splits the faces around
// the vertex into sectors, the faces between two of those edges. A sector of one quad is a
// regular corner (a B-spline patch corner, with a tangent plane). A sector of two or more
// faces has none: its subdivision matrix has, after the eigenvalue 1 of the limit position,
// either an eigenvalue above the boundary curves' 1/2 with a one-dimensional eigenspace (three
// faces: (11 + sqrt 57) / 32 = 0.580) or a defective 1/2 (two faces: a Jordan block), so the
// limit normal at the vertex depends on the direction from which the vertex is approached
// (Zorin 2000; Biermann, Levin and Zorin 2000, who give corner rules that fix it; OpenSubdiv
// and every tool that follows its rules use the standard ones). A cone point (an infinitely
// sharp vertex with no sharp edge) is the same case with a sector all around it.
// tests/plans/test_tangent_plane.cpp computes those spectra from OpenSubdiv's own refinement.
//
// Only the corner itself is affected: a point any distance inside the face has a tangent plane,
// and the exact schemes agree there to round-off.
//
// Darts (a vertex with exactly one infinitely sharp edge) do have a tangent plane, but not the
// one OpenSubdiv's limit masks give: Sdc treats a dart as a smooth vertex, and the smooth
// rule's tangent masks are not the dart's eigenvectors (valence 6: smooth 0.580, 0.580, 0.410;
// dart 0.580, 0.548, 0.441), so Far's Gregory-basis end caps carry a corner tangent plane that
// reaches the limit's only as (lambda3 / lambda2)^depth (catmark_inf_crease1's valence-6 dart:
// 4.7, 2.2 and 0.8 degrees at depths 4, 6 and 8). exactTangents computes the exact masks from the
// dart's subdivision matrix, as Far refines it; the plans' end caps and the Far reference
// (core/plans/plan_builder.cpp, core/plans/limit_reference.cpp) move their corners' edge points onto them.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <opensubdiv/far/topologyRefiner.h>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

// A corner of a sub-face in its own frame: 0 (u, v) = (0, 0), 1 (1, 0), 2 (1, 1), 3 (0, 1).
struct SubfaceCorner {
    uint32_t subface = 0;
    uint32_t corner = 0;
    auto operator<=>(const SubfaceCorner&) const = default;
};

// Every sub-face corner (sub-faces numbered as in PlannedCage) at a vertex where the limit
// surface has no tangent plane, sorted; evaluated with OpenSubdiv's own tags (boundary and
// non-manifold edges infinitely sharp, the boundary interpolation's corners).
Result<std::vector<SubfaceCorner>> cornersWithoutTangentPlane(const Cage& cage, const std::string& source);

// The limit tangent plane at a dart (or, with `smoothToo`, a smooth vertex) as masks over its
// 1-ring at level 0 of `refiner` (which must have refined the ring's faces at least twice): the
// left eigenvectors of the ring's subdivision matrix for its two dominant eigenvalues after 1
// (`left`), with the right ones (`right`, left[i] . right[j] = delta_ij) that project any
// tangent mask onto them. Nothing for other vertices (a semi-sharp tag at the vertex makes the
// matrix change from level to level), or when the spectrum has no gap after the second
// eigenvalue. The plans also keep these masks as their corners' exact tangents
// (Plan::cornerTangents).
struct ExactTangents {
    bool dart = false;                         // else a smooth vertex
    std::vector<OpenSubdiv::Far::Index> ring;  // level-0 vertices: the vertex, then its neighbours
    std::array<std::vector<double>, 2> left, right;
    // The part of `mask` (over `ring`, summing to zero) in the tangent plane's masks.
    std::vector<double> project(std::span<const double> mask) const;
};
std::optional<ExactTangents> exactTangents(const OpenSubdiv::Far::TopologyRefiner& refiner, OpenSubdiv::Far::Index vertex,
                                           bool smoothToo = false);
// The same at the centre of a level-0 face (a smooth vertex of valence n from level 1 on: an
// extraordinary one when the face is no quad), over the vertices of the faces around it.
std::optional<ExactTangents> faceCentreTangents(const OpenSubdiv::Far::TopologyRefiner& refiner, OpenSubdiv::Far::Index face);

}  // namespace qp
