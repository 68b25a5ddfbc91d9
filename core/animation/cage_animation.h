// Cage animation: the positions of a cage's vertices, and an object's transform, keyed at frames
// over a fixed topology. Every frame is then a vertex move (planned_cage.h): the plans stay and
// only control points change, so playing an animation re-plans nothing.
//
// Keys are per vertex: each vertex has its own track of (frame, position) keys, sorted by frame,
// and a vertex without keys stays at its rest position (the cage's own). Between keys a track is
// interpolated linearly or by Catmull-Rom (a cubic Hermite whose tangents are the central
// differences of the neighbouring keys, one-sided at the ends: Catmull-Rom proper for evenly
// spaced keys); before its first key and after its last a track holds that key. Tracks are
// stored flat (CSR over the vertices) so a frame is one pass over the keys.
//
// An OBJ sequence (cage_sequence.h) becomes a key per vertex per frame; the pattern is kept so
// that a scene saves the reference again while the keys are unchanged.
//
// Frames are integers (keys sit on them); evaluation takes any frame number, so playback at a
// rate other than the keys' steps interpolates between them.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "animation/object_transform.h"
#include "mesh/cage.h"
#include "mesh/result.h"
#include "mesh/topology_edits.h"

namespace qp {

enum class Interpolation : uint8_t { Linear, CatmullRom };

// Keys sit on frames within +-kMaxKeyFrame (what the scene file, sequences and commands accept).
inline constexpr int32_t kMaxKeyFrame = 1000000000;

// Per-vertex position tracks, CSR: the keys of vertex v are [offsets[v], offsets[v + 1]).
// Empty `offsets`: no vertex has keys.
struct VertexKeys {
    std::vector<uint32_t> offsets;
    std::vector<int32_t> frames;      // strictly increasing within each vertex's range
    std::vector<glm::vec3> positions;

    bool empty() const { return frames.empty(); }
    uint32_t keyCount(uint32_t vertex) const {
        return offsets.empty() ? 0 : offsets[vertex + 1] - offsets[vertex];
    }
    bool operator==(const VertexKeys&) const = default;
};

struct TransformKey {
    int32_t frame = 0;
    ObjectTransform transform;
    bool operator==(const TransformKey&) const = default;
};

struct ObjectAnimation {
    Interpolation interpolation = Interpolation::Linear;
    VertexKeys vertexKeys;                   // empty for an instance (it follows its source's cage)
    std::vector<TransformKey> transformKeys;  // strictly increasing frames
    // The OBJ sequence the vertex keys were read from (as written in the scene file), while they
    // are exactly what it gave; cleared by any change to them.
    std::string sequencePattern;

    bool empty() const { return vertexKeys.empty() && transformKeys.empty(); }
    bool operator==(const ObjectAnimation&) const = default;
};

// The frames a scene plays and how fast (scene.h stores it; optional in the file).
struct Timeline {
    double framesPerSecond = 24.0;
    int32_t firstFrame = 1, lastFrame = 1;  // inclusive
    bool operator==(const Timeline&) const = default;
};

// Checks what evaluation relies on, each failure naming `where` and the vertex or key: offsets
// of vertexCount + 1 entries, non-decreasing, ending at the key count; frames strictly increasing
// per track and per transform track ("keys out of order or at equal frames"); finite positions
// and transforms, with no zero scale.
Status validateAnimation(const ObjectAnimation& animation, uint32_t vertexCount, const std::string& where);

// Every vertex's position at `frame`: its track's value, or its rest position when it has none.
// out.size() == rest.size(); `keys` fits rest.size() vertices (validateAnimation).
void evaluatePositions(const VertexKeys& keys, Interpolation interpolation, std::span<const glm::vec3> rest,
                       double frame, std::span<glm::vec3> out);
// The transform at `frame` (translation, rotation and scale interpolated component by
// component), or `fallback` when there are no transform keys.
ObjectTransform evaluateTransform(const ObjectAnimation& animation, double frame, const ObjectTransform& fallback);

// The smallest and largest key frame of either kind; false when there are no keys.
bool keyedFrameRange(const ObjectAnimation& animation, int32_t& first, int32_t& last);
// The frames with a key of any vertex, sorted, each once (a timeline's key marks).
std::vector<int32_t> keyedFrames(const ObjectAnimation& animation);

// Sets (adds, or replaces at an equal frame) a key at `frame` for each vertex with its
// position. `vertexCount` sizes the tracks when there were none. Clears sequencePattern.
void setVertexKeys(ObjectAnimation& animation, uint32_t vertexCount, int32_t frame,
                   std::span<const uint32_t> vertices, std::span<const glm::vec3> positions);
// Removes every vertex's key at `frame` (vertices left without keys go back to rest).
void removeVertexKeysAt(ObjectAnimation& animation, int32_t frame);
void setTransformKey(ObjectAnimation& animation, int32_t frame, const ObjectTransform& transform);

// The keys of one vertex, for moving them between animations (an undo entry keeps these).
struct VertexTrack {
    uint32_t vertex = 0;
    std::vector<int32_t> frames;
    std::vector<glm::vec3> positions;
};
std::vector<VertexTrack> vertexTracks(const VertexKeys& keys, std::span<const uint32_t> vertices);
// Puts a key at `frame` into a track (replacing one at an equal frame).
void insertKey(VertexTrack& track, int32_t frame, const glm::vec3& position);
// The tracks of `vertices` (sorted, each once) with a key at `frame` at their positions.
std::vector<VertexTrack> keyedTracks(const VertexKeys& keys, int32_t frame, std::span<const uint32_t> vertices,
                                     std::span<const glm::vec3> positions);
// Replaces the tracks of the listed vertices (an empty track removes the vertex's keys).
void replaceVertexTracks(ObjectAnimation& animation, uint32_t vertexCount, std::span<const VertexTrack> tracks);

// Carries an animation through a topology edit made at `frame` from `before` (the cage as shown
// at that frame, whose rest positions are `rest`); `rest` becomes the edited cage's rest. So that
// every frame sees the edit:
//  - a kept vertex keeps its track and rest, both shifted by what the edit moved it at `frame`
//    (an extrude's distance, a merge's centroid);
//  - a new vertex follows the kept vertices it shares an edge with, weighted by inverse distance
//    at `frame` (an edge loop's vertex thus follows its edge's ends in proportion): its rest and
//    keys are its position at `frame` plus their weighted motion away from it, keyed at the union
//    of their key frames and at `frame` itself; with no animated neighbour it is static;
//  - a removed vertex's keys go.
// At `frame` the result evaluates to edit.cage's positions exactly.
void applyTopologyEditToAnimation(ObjectAnimation& animation, std::vector<glm::vec3>& rest, const Cage& before,
                                  const TopologyEdit& edit, double frame);

}  // namespace qp
