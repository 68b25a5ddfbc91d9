// Cages in OpenMesh's own binary format (.om), the one mesh format besides OBJ that carries
// Quadplan's tags: they travel as named OpenMesh properties, so OpenMesh-based tools keep them
// and a round trip through .om gives back the same cage (faces in order, each from its first
// corner, positions bit for bit, every tag and option):
//   quadplan:crease   edge, float    semi-sharp crease sharpness (0: none)
//   quadplan:corner   vertex, float  corner sharpness (0: none)
//   quadplan:hole     face, int      1 for a hole
//   quadplan:uv       half-edge, vec2f   the UV of the half-edge's start corner in its face
//   quadplan:uv_index half-edge, int     that UV's index (so UV seams survive exactly)
//   quadplan:uvs, quadplan:boundary, quadplan:crease_method, quadplan:triangles, quadplan:fvar,
//   quadplan:fvar_corners              mesh, int: whether UVs are present, and the options
//
// OpenMesh's half-edge kernel cannot hold non-manifold faces (an edge with three faces, a face
// that visits a vertex twice): writing such a cage is refused with the faces named (OBJ keeps
// it). Reading never builds a kernel: the file is walked first (mesh_file_check.h checkOmFile),
// then OpenMesh's reader hands its half-edge records to Quadplan's importer, which walks each
// face's loop with every index checked, so a corrupt file is refused, naming the face, and no
// face is dropped.
#pragma once

#include <string>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

Result<Cage> loadOmCage(const std::string& path, const std::string& bytes);
Result<std::string> omCageBytes(const Cage& cage, const std::string& path);

}  // namespace qp
