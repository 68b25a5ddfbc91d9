// Writing a cage (its polygons, not its limit surface) as PLY, OFF or STL, the formats
// mesh_import.h reads, so a cage can go to tools that take polygon meshes. None of them carries
// Quadplan's tags: `lost` gets one sentence per thing the file cannot hold (creases, corners,
// holes, texture coordinates, the crease method; for STL also the polygons, fanned into
// triangles, and the shared vertices). Writes are atomic (file_io.h).
#pragma once

#include <string>
#include <vector>

#include "cage.h"
#include "result.h"

namespace qp {

// `path` ends in .ply (binary little-endian), .off or .stl (binary).
Status saveMeshCage(const Cage& cage, const std::string& path, std::vector<std::string>* lost = nullptr);

}  // namespace qp
