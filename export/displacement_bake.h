// Baking a cage's sculpted displacement into texture space, for renderers that take a
// displacement map (and a tangent-space normal map) instead of our sub-face samples.
//
// Each texel whose centre lies in the UV image of a sub-face gets D at the (sub-face, u, v) that
// maps there: the sub-face's UV image (cage_uvs.h, linear or smooth) is cut into small triangles
// (about a texel each, so a smooth UV map is followed closely), each triangle is rasterised and
// its texels' (u, v) interpolated, and D is evaluated there exactly (displacement.h). Texels of
// no island stay empty; `padding` rounds of dilation then fill the empty texels next to an
// island with their filled neighbours' mean, so bilinear filtering and mipmaps at an island's
// edge do not pull in the background.
//
// Conventions: the image is square; texel (x, y) covers UV [x, x + 1] / size horizontally and
// row y = 0 is the top of the image, UV v = 1 (OBJ's origin is the bottom left; glTF's images and
// OpenEXR's rows start at the top). UVs outside [0, 1] (UDIM tiles) are not baked; the report
// counts the sub-faces that reach out of it.
// The normal map is tangent-space, OpenGL's (Blender's) convention: red along +U, green along
// +V, blue along the undisplaced limit normal; the tangent frame per texel is the limit
// surface's derivatives along U and V, orthonormalised against the normal (Gram-Schmidt), the
// bitangent's sign from the UV map's orientation. A renderer that builds its frames from the
// same UVs and the limit normals (MikkTSpace agrees to within its per-vertex interpolation)
// shades the displaced surface's normals back.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "cage_uvs.h"
#include "displacement/displacement.h"
#include "mesh/result.h"
#include "plans/planned_cage.h"
#include "scene_export.h"

namespace qp {

struct BakeOptions {
    uint32_t size = 1024;         // texels per side, 16 .. 16384
    UvMode uv = UvMode::Linear;   // Linear or Smooth
    uint32_t padding = 4;         // dilation rounds around each island
    bool normalMap = false;       // also the tangent-space normal map
};

enum class TexelCoverage : uint8_t { Empty = 0, Padding = 1, Island = 2 };

struct BakedMaps {
    uint32_t size = 0;
    std::vector<float> displacement;     // size * size, row-major from the top row
    std::vector<TexelCoverage> coverage; // per texel
    std::vector<glm::vec3> normals;      // tangent-space unit normals (empty without normalMap)
    uint64_t islandTexels = 0, paddingTexels = 0;
    uint32_t subfacesOutsideUnitSquare = 0;  // sub-faces whose UVs leave [0, 1]^2 somewhere
    float minValue = 0.0f, maxValue = 0.0f;  // over the island texels
};

// Texel (x, y)'s centre in UV space, and the texel coordinates (continuous) of a UV.
inline glm::vec2 texelCentreUv(uint32_t size, uint32_t x, uint32_t y) {
    return {(float(x) + 0.5f) / float(size), 1.0f - (float(y) + 0.5f) / float(size)};
}

// Fails when the cage has no UVs, `displacement` does not belong to it (or is empty), or the
// options are out of range. `source` names the cage in messages.
Result<BakedMaps> bakeDisplacement(const PlannedCage& planned, const Displacement& displacement, const BakeOptions& options,
                                   const std::string& source);

// The displacement as a one-channel ("Y"), 32-bit float, ZIP-compressed OpenEXR image; atomic.
Status writeDisplacementExr(const BakedMaps& maps, const std::string& path);
// The normal map as an 8-bit RGB(A) PNG (n * 0.5 + 0.5; empty texels flat blue); atomic.
Status writeNormalMapPng(const BakedMaps& maps, const std::string& path);

struct BakeReport {
    std::vector<std::string> files;   // displacement maps, then normal maps
    std::vector<std::string> notes;   // cages skipped, UVs outside the unit square
    uint64_t islandTexels = 0, paddingTexels = 0;
    float minValue = 0.0f, maxValue = 0.0f;
    double ms = 0.0;
};

// Bakes the cages of a scene that carry displacement (SceneCages: scene_export.h): to `path`
// (an .exr) when one does, else to NAME_OBJECT.exr beside it for each owner object; with a
// `normalMapPath` (a .png) the normal maps likewise. Everything is baked before anything is
// written; a scene without displacement is an error.
Result<BakeReport> bakeScene(const Scene& scene, const SceneCages& cages, const std::string& path,
                             const std::string& normalMapPath, const BakeOptions& options, const std::string& source,
                             const ExportProgress& progress = nullptr);

}  // namespace qp
