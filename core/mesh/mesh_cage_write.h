// Writing a cage (its polygons, not its limit surface) as PLY, OFF, STL or OM, the formats
// mesh_import.h reads, so a cage can go to tools that take polygon meshes. OM carries every tag
// (mesh_om.h; a non-manifold cage is refused); the others carry none of them: `lost` gets one sentence per thing the file cannot hold (creases, corners,
// holes, texture coordinates, the crease method; for STL also the polygons, fanned into
// triangles, and the shared vertices). Writes are atomic (file_io.h).
#pragma once

#include <string>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

// `path` ends in .ply (binary little-endian), .off, .stl (binary), .om or .obj (obj_io.h).
Status saveMeshCage(const Cage& cage, const std::string& path, std::vector<std::string>* lost = nullptr);

// What writing `cage` to `path` would lose, one sentence each (none for .obj and .om).
std::vector<std::string> meshFormatLosses(const Cage& cage, const std::string& path);

}  // namespace qp
