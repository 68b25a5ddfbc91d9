// A cage animation as a sequence of OBJ files with one topology (frame_0001.obj, frame_0002.obj,
// ...), the form most tools export a deforming mesh in. Each frame gives positions only: the
// first frame's (or the scene's) faces, tags and UVs hold for all of them, so playing the
// sequence is a vertex move per frame and re-plans nothing.
//
// Files come from a pattern with one '*' standing for the frame number ("frames/frame_*.obj"):
// every regular file in the pattern's folder whose name is the pattern with digits for the '*', sorted
// by that number. A number missing between the first and the last is an error naming it; so is a
// frame whose vertex count or faces differ from the reference (naming the frame and the first
// differing face) or that fails to load (NaN coordinates included: obj_io.h).
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "animation/cage_animation.h"
#include "mesh/cage.h"
#include "mesh/result.h"

namespace qp {

struct SequenceFile {
    uint64_t number;   // the digits that stand for the '*'
    std::string path;
};

Result<std::vector<SequenceFile>> sequenceFiles(const std::string& pattern);

// One frame's positions; `reference` gives the faces the frame must have.
Result<std::vector<glm::vec3>> loadSequenceFrame(const std::string& path, const Cage& reference);

// Every frame of the sequence as keys of every vertex of `reference` at the file's number, all
// read and checked before anything is returned. Errors name the frame and its file ("frame 7
// (walk/frame_0007.obj): ..."), a number beyond kMaxKeyFrame included.
Result<VertexKeys> loadSequenceKeys(const std::string& pattern, const Cage& reference);

}  // namespace qp
