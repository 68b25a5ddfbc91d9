// Cages from the mesh formats other tools write: PLY (ASCII or binary), OFF and STL (ASCII or
// binary; its repeated vertices are welded where their positions are equal), parsed by
// OpenMesh's readers; and OpenMesh's own .om, which carries the tags (mesh_om.h).
//
// The faces go into Quadplan's own importer, not into OpenMesh's mesh kernel: the kernel
// refuses non-manifold ("complex") faces and would drop them, while a cage may be non-manifold
// (OpenSubdiv subdivides it). So every face the reader parses becomes a face of the cage, in the
// file's order and winding. The counts the file declares are checked against what was read:
// a face the reader itself skipped (fewer than three corners, an index past the vertices) makes
// the whole file an error that says so; nothing is dropped silently. Counts larger than the file
// could hold are refused before parsing (a corrupt header must not make the reader loop), and
// the cage must pass validateCage (finite positions, faces of distinct vertices, ...).
//
// PLY, OFF and STL carry no creases, corners or holes; normals, colours and texture coordinates in
// them are ignored (a subdivision surface's normals come from the surface).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

// Whether a lower-case extension (file_io.h lowercaseExtension: ".ply", ".off", ".stl", ".om") is
// one of these formats.
bool isMeshCageExtension(const std::string& extension);

Result<Cage> loadMeshCage(const std::string& path, std::vector<std::string>* warnings = nullptr);

}  // namespace qp
