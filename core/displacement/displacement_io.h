// The scene file's "displacement" object (docs/scene-format.md): reading, with every error
// naming its JSON field, and writing.
//
// Version 2 stores the tiles' samples (displacement.h) as base64 of their raw little-endian
// float32 bytes, so a saved displacement loads back bit for bit (docs/displacement.md says why
// not decimal numbers):
//   {"version": 2, "encoding": "base64-float32-le", "resolution": R,
//    "samples": "<layout.sampleCount floats in sample order>",
//    "mask": "<as many floats, each in [0, 1]>"}          optional: absent masks nothing
// The samples' order follows from the cage and R alone (buildDisplacementLayout). "resolution" 0
// means no displacement (and then no "samples" or "mask"). A mask of zeros is written as none.
//
// Version 1 stored bilinear sample grids (sample_grids.h):
//   {"version": 1, "encoding": "base64-float32-le",
//    "subfaces": [{"resolution": R, "interior": "<(R-1)^2 floats>"}, ...],   one per sub-face
//    "points": "<V + E + F floats>", "segments": "<every segment's interior floats>", "mask": ...}
// It is read, checked as strictly as ever, and CONVERTED: the tiles (at R = the finest sub-face's
// resolution, counted in quad cells) are fitted to the grids' D and mask, with a warning; the
// next save writes version 2. Version 0 was a placeholder ({"version": 0, "faces": []}); it
// migrates to no displacement.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "displacement/displacement.h"
#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

constexpr int kDisplacementVersion = 2;

// `value` is the "displacement" object of a scene whose cage is `cage` (validated). Errors read
// "<field>: <what is wrong>" with field a JSON path such as displacement.subfaces[3].interior,
// after `at` (the path of the object holding it, "objects[2]."); `source` prefixes warnings
// about unknown fields.
Result<Displacement> readDisplacementJson(const nlohmann::json& value, const Cage& cage, const std::string& source,
                                          std::vector<std::string>* warnings = nullptr, const std::string& at = "");

// True when the displacement is empty or laid out for exactly this cage's topology (what a
// saved scene needs to load again).
bool displacementFitsCage(const Displacement& displacement, const Cage& cage);

nlohmann::ordered_json displacementJson(const Displacement& displacement);

// Base64 (RFC 4648, with padding) of floats as little-endian float32, and back; decoding fails
// on anything that is not such a string of whole floats.
std::string encodeFloats(const float* values, size_t count);
Result<std::vector<float>> decodeFloats(const std::string& text);

}  // namespace qp
