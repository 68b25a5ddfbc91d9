// The structure checks a PLY, OFF or STL file passes before OpenMesh's readers parse it
// (mesh_import.h). Those readers trust the file: a property before any element crashed the PLY
// header parser, and a face list count read from garbage made the OFF reader allocate gigabytes
// (both found by fuzz_mesh_import). So the whole file is walked here first, cheaply and without
// building anything: the header against the format's grammar, then every record against the
// header — numbers that parse and are finite, face lists of 3 to kMaxFaceCorners corners naming
// vertices that exist, binary records that fit in the bytes there are. Only a file that passes
// reaches OpenMesh. Each error names the file and the line, record or byte where it went wrong.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mesh/result.h"

namespace qp {

inline constexpr uint32_t kMaxFaceCorners = 1024;

struct DeclaredCounts {
    long long vertices = -1, faces = -1;  // -1: the format declares none (ASCII STL)
};

Result<DeclaredCounts> checkPlyFile(const std::string& bytes, const std::string& source);
// Plain OFF only (the NOFF, COFF, STOFF and binary variants are refused by name); comments only
// before the counts.
Result<DeclaredCounts> checkOffFile(const std::string& bytes, const std::string& source);
Result<DeclaredCounts> checkStlFile(const std::string& bytes, const std::string& source);

// OpenMesh's binary format (.om, versions up to kOmVersion): the header's counts, then every
// chunk's size as OpenMesh's reader will consume it (which reads fixed-size vectors whatever a
// chunk's header claims, and loops over the header's counts without looking for the file's end),
// so each chunk must fit in the bytes left and the last must end where the file does. Chunks the
// reader would refuse (an unknown entity, positions that are neither floats nor doubles) are
// refused here by name. What the topology chunks say is checked after reading (mesh_om.h).
inline constexpr uint8_t kOmVersion = (2 << 5) | 2;  // 2.2, what OpenMesh 9 writes
struct OmCounts {
    uint32_t vertices = 0, faces = 0, edges = 0;
    uint8_t version = 0;
    char meshType = 'P';  // 'T' triangles, 'Q' quads, 'P' polygons
    // Custom-property chunks of variable-sized types (std::vector, std::string), [first, end)
    // in the file: OpenMesh sizes them from counts inside their data, unchecked (a vector of
    // 4 GB from a 16-byte block), and no cage needs them, so the reader leaves them out.
    std::vector<std::pair<size_t, size_t>> skippedChunks;
};
Result<OmCounts> checkOmFile(const std::string& bytes, const std::string& source);

}  // namespace qp
