#include "animation/cage_animation.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <glm/geometric.hpp>

namespace qp {

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The value between keys i and i + 1 of a track (frames/values of `count` keys) at `frame`,
// which lies in [frames[i], frames[i + 1]].
template <class T>
T interpolateSegment(const int32_t* frames, const T* values, uint32_t count, uint32_t i, double frame,
                     Interpolation interpolation) {
    const double t0 = frames[i], t1 = frames[i + 1];
    const float s = float((frame - t0) / (t1 - t0));
    const T& p0 = values[i];
    const T& p1 = values[i + 1];
    if (interpolation == Interpolation::Linear) return p0 + (p1 - p0) * s;
    // Tangents per frame from the neighbouring keys (one-sided at a track's ends), scaled to the
    // segment's length: a cubic Hermite that is Catmull-Rom for evenly spaced keys.
    auto tangent = [&](uint32_t k) {
        const uint32_t a = k == 0 ? 0 : k - 1, b = k + 1 == count ? k : k + 1;
        return (values[b] - values[a]) * float((t1 - t0) / double(frames[b] - frames[a]));
    };
    const T m0 = tangent(i), m1 = tangent(i + 1);
    const float s2 = s * s, s3 = s2 * s;
    return p0 * (2 * s3 - 3 * s2 + 1) + m0 * (s3 - 2 * s2 + s) + p1 * (-2 * s3 + 3 * s2) + m1 * (s3 - s2);
}

template <class T>
T evaluateTrack(const int32_t* frames, const T* values, uint32_t count, double frame, Interpolation interpolation) {
    assert(count > 0);
    if (frame <= frames[0]) return values[0];
    if (frame >= frames[count - 1]) return values[count - 1];
    const uint32_t i = uint32_t(std::upper_bound(frames, frames + count, frame,
                                                 [](double f, int32_t k) { return f < double(k); }) -
                                frames) - 1;
    return interpolateSegment(frames, values, count, i, frame, interpolation);
}

// An object's transform as one vector to interpolate.
struct TransformValue {
    glm::vec3 t, r, s;
    TransformValue operator+(const TransformValue& o) const { return {t + o.t, r + o.r, s + o.s}; }
    TransformValue operator-(const TransformValue& o) const { return {t - o.t, r - o.r, s - o.s}; }
    TransformValue operator*(float k) const { return {t * k, r * k, s * k}; }
};

// Rebuilds CSR tracks from one list of keys per vertex.
void storeTracks(VertexKeys& keys, const std::vector<std::vector<std::pair<int32_t, glm::vec3>>>& tracks) {
    keys.offsets.assign(tracks.size() + 1, 0);
    keys.frames.clear();
    keys.positions.clear();
    for (size_t v = 0; v < tracks.size(); ++v) {
        for (const auto& [frame, position] : tracks[v]) {
            keys.frames.push_back(frame);
            keys.positions.push_back(position);
        }
        keys.offsets[v + 1] = uint32_t(keys.frames.size());
    }
    if (keys.frames.empty()) keys.offsets.clear();
}

// The keys with the tracks of `replacements` (sorted by vertex, each vertex once) in place of
// those vertices' own: one pass over the keys, copying the others' ranges as they are.
VertexKeys splicedKeys(const VertexKeys& keys, uint32_t vertexCount, std::span<const VertexTrack* const> replacements) {
    VertexKeys out;
    out.offsets.assign(size_t(vertexCount) + 1, 0);
    size_t next = 0;
    for (uint32_t v = 0; v < vertexCount; ++v) {
        if (next < replacements.size() && replacements[next]->vertex == v) {
            const VertexTrack& t = *replacements[next++];
            out.frames.insert(out.frames.end(), t.frames.begin(), t.frames.end());
            out.positions.insert(out.positions.end(), t.positions.begin(), t.positions.end());
        } else if (!keys.offsets.empty()) {
            out.frames.insert(out.frames.end(), keys.frames.begin() + keys.offsets[v], keys.frames.begin() + keys.offsets[v + 1]);
            out.positions.insert(out.positions.end(), keys.positions.begin() + keys.offsets[v],
                                 keys.positions.begin() + keys.offsets[v + 1]);
        }
        out.offsets[v + 1] = uint32_t(out.frames.size());
    }
    if (out.frames.empty()) out.offsets.clear();
    return out;
}

glm::vec3 trackValue(const VertexKeys& keys, uint32_t v, Interpolation interpolation, double frame) {
    const uint32_t begin = keys.offsets[v];
    return evaluateTrack(keys.frames.data() + begin, keys.positions.data() + begin, keys.offsets[v + 1] - begin, frame,
                         interpolation);
}

}  // namespace

Status validateAnimation(const ObjectAnimation& animation, uint32_t vertexCount, const std::string& where) {
    const VertexKeys& keys = animation.vertexKeys;
    if (keys.frames.size() != keys.positions.size())
        return Error{where + ": " + std::to_string(keys.frames.size()) + " key frames but " +
                     std::to_string(keys.positions.size()) + " key positions"};
    if (!keys.offsets.empty() || !keys.frames.empty()) {
        if (keys.offsets.size() != size_t(vertexCount) + 1)
            return Error{where + ": the keys are for " + std::to_string(keys.offsets.size() ? keys.offsets.size() - 1 : 0) +
                         " vertices but the cage has " + std::to_string(vertexCount)};
        if (keys.offsets.front() != 0 || keys.offsets.back() != keys.frames.size())
            return Error{where + ": the key offsets do not cover the keys"};
        for (uint32_t v = 0; v < vertexCount; ++v) {
            if (keys.offsets[v + 1] < keys.offsets[v]) return Error{where + ": the key offsets decrease at vertex " + std::to_string(v)};
            for (uint32_t k = keys.offsets[v]; k < keys.offsets[v + 1]; ++k) {
                if (!finite(keys.positions[k]))
                    return Error{where + ": vertex " + std::to_string(v) + " has a non-finite position at frame " +
                                 std::to_string(keys.frames[k])};
                if (k > keys.offsets[v] && keys.frames[k] <= keys.frames[k - 1])
                    return Error{where + ": vertex " + std::to_string(v) + ": the key at frame " + std::to_string(keys.frames[k]) +
                                 " is not after the key at frame " + std::to_string(keys.frames[k - 1]) +
                                 " (keys must be in increasing frame order, one per frame)"};
            }
        }
    }
    const std::vector<TransformKey>& tk = animation.transformKeys;
    for (size_t k = 0; k < tk.size(); ++k) {
        const ObjectTransform& t = tk[k].transform;
        if (!finite(t.translation) || !finite(t.rotationDegrees) || !finite(t.scale))
            return Error{where + ": the transform key at frame " + std::to_string(tk[k].frame) + " is not finite"};
        if (t.scale.x == 0.0f || t.scale.y == 0.0f || t.scale.z == 0.0f)
            return Error{where + ": the transform key at frame " + std::to_string(tk[k].frame) + " has a zero scale"};
        if (k > 0 && tk[k].frame <= tk[k - 1].frame)
            return Error{where + ": the transform key at frame " + std::to_string(tk[k].frame) +
                         " is not after the key at frame " + std::to_string(tk[k - 1].frame) +
                         " (keys must be in increasing frame order, one per frame)"};
    }
    return Done{};
}

void evaluatePositions(const VertexKeys& keys, Interpolation interpolation, std::span<const glm::vec3> rest,
                       double frame, std::span<glm::vec3> out) {
    assert(out.size() == rest.size());
    assert(keys.offsets.empty() || keys.offsets.size() == rest.size() + 1);
    for (size_t v = 0; v < rest.size(); ++v)
        out[v] = keys.keyCount(uint32_t(v)) ? trackValue(keys, uint32_t(v), interpolation, frame) : rest[v];
}

ObjectTransform evaluateTransform(const ObjectAnimation& animation, double frame, const ObjectTransform& fallback) {
    const std::vector<TransformKey>& keys = animation.transformKeys;
    if (keys.empty()) return fallback;
    std::vector<int32_t> frames;
    std::vector<TransformValue> values;
    for (const TransformKey& k : keys) {
        frames.push_back(k.frame);
        values.push_back({k.transform.translation, k.transform.rotationDegrees, k.transform.scale});
    }
    const TransformValue v = evaluateTrack(frames.data(), values.data(), uint32_t(keys.size()), frame, animation.interpolation);
    return ObjectTransform{v.t, v.r, v.s};
}

bool keyedFrameRange(const ObjectAnimation& animation, int32_t& first, int32_t& last) {
    if (animation.empty()) return false;
    first = INT32_MAX;
    last = INT32_MIN;
    for (int32_t f : animation.vertexKeys.frames) first = std::min(first, f), last = std::max(last, f);
    for (const TransformKey& k : animation.transformKeys) first = std::min(first, k.frame), last = std::max(last, k.frame);
    return true;
}

std::vector<int32_t> keyedFrames(const ObjectAnimation& animation) {
    std::vector<int32_t> frames = animation.vertexKeys.frames;
    for (const TransformKey& k : animation.transformKeys) frames.push_back(k.frame);
    std::sort(frames.begin(), frames.end());
    frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
    return frames;
}

void setVertexKeys(ObjectAnimation& animation, uint32_t vertexCount, int32_t frame, std::span<const uint32_t> vertices,
                   std::span<const glm::vec3> positions) {
    if (vertices.empty()) return;
    replaceVertexTracks(animation, vertexCount, keyedTracks(animation.vertexKeys, frame, vertices, positions));
}

void removeVertexKeysAt(ObjectAnimation& animation, int32_t frame) {
    VertexKeys& keys = animation.vertexKeys;
    if (keys.empty()) return;
    size_t kept = 0;
    uint32_t begin = 0;
    for (size_t v = 0; v + 1 < keys.offsets.size(); ++v) {
        const uint32_t end = keys.offsets[v + 1];
        for (uint32_t k = begin; k < end; ++k)
            if (keys.frames[k] != frame) keys.frames[kept] = keys.frames[k], keys.positions[kept++] = keys.positions[k];
        begin = end;
        keys.offsets[v + 1] = uint32_t(kept);
    }
    keys.frames.resize(kept);
    keys.positions.resize(kept);
    if (kept == 0) keys.offsets.clear();
    animation.sequencePattern.clear();
}

void setTransformKey(ObjectAnimation& animation, int32_t frame, const ObjectTransform& transform) {
    auto& keys = animation.transformKeys;
    auto at = std::lower_bound(keys.begin(), keys.end(), frame, [](const TransformKey& k, int32_t f) { return k.frame < f; });
    if (at != keys.end() && at->frame == frame) at->transform = transform;
    else keys.insert(at, TransformKey{frame, transform});
}

void insertKey(VertexTrack& track, int32_t frame, const glm::vec3& position) {
    const auto at = std::lower_bound(track.frames.begin(), track.frames.end(), frame);
    const size_t i = size_t(at - track.frames.begin());
    if (at != track.frames.end() && *at == frame) {
        track.positions[i] = position;
    } else {
        track.frames.insert(at, frame);
        track.positions.insert(track.positions.begin() + long(i), position);
    }
}

std::vector<VertexTrack> keyedTracks(const VertexKeys& keys, int32_t frame, std::span<const uint32_t> vertices,
                                     std::span<const glm::vec3> positions) {
    assert(vertices.size() == positions.size());
    std::vector<uint32_t> sorted(vertices.begin(), vertices.end());
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    std::vector<VertexTrack> tracks = vertexTracks(keys, sorted);
    for (size_t i = 0; i < vertices.size(); ++i) {
        const size_t t = size_t(std::lower_bound(sorted.begin(), sorted.end(), vertices[i]) - sorted.begin());
        insertKey(tracks[t], frame, positions[i]);
    }
    return tracks;
}

std::vector<VertexTrack> vertexTracks(const VertexKeys& keys, std::span<const uint32_t> vertices) {
    std::vector<VertexTrack> tracks;
    for (uint32_t v : vertices) {
        VertexTrack track{v, {}, {}};
        if (!keys.offsets.empty()) {
            track.frames.assign(keys.frames.begin() + keys.offsets[v], keys.frames.begin() + keys.offsets[v + 1]);
            track.positions.assign(keys.positions.begin() + keys.offsets[v], keys.positions.begin() + keys.offsets[v + 1]);
        }
        tracks.push_back(std::move(track));
    }
    return tracks;
}

void replaceVertexTracks(ObjectAnimation& animation, uint32_t vertexCount, std::span<const VertexTrack> replacements) {
    if (replacements.empty()) return;
    std::vector<const VertexTrack*> byVertex;
    for (const VertexTrack& t : replacements) byVertex.push_back(&t);
    // Sorted by vertex; of a vertex listed twice the last one counts.
    std::stable_sort(byVertex.begin(), byVertex.end(), [](const VertexTrack* a, const VertexTrack* b) { return a->vertex < b->vertex; });
    std::vector<const VertexTrack*> unique;
    for (const VertexTrack* t : byVertex) {
        assert(t->vertex < vertexCount);
        if (!unique.empty() && unique.back()->vertex == t->vertex) unique.back() = t;
        else unique.push_back(t);
    }
    animation.vertexKeys = splicedKeys(animation.vertexKeys, vertexCount, unique);
    animation.sequencePattern.clear();
}

void applyTopologyEditToAnimation(ObjectAnimation& animation, std::vector<glm::vec3>& rest, const Cage& before,
                                  const TopologyEdit& edit, double frame) {
    const Cage& after = edit.cage;
    const uint32_t newCount = uint32_t(after.positions.size());
    const VertexKeys& oldKeys = animation.vertexKeys;
    const bool animated = !oldKeys.empty();
    std::vector<std::vector<std::pair<int32_t, glm::vec3>>> tracks(newCount);
    std::vector<glm::vec3> newRest(newCount);

    // Kept vertices: their keys and rest, shifted by what the edit moved them.
    for (uint32_t v = 0; v < newCount; ++v) {
        const uint32_t old = edit.oldVertexOf[v];
        if (old == kNewElement) continue;
        const glm::vec3 shift = after.positions[v] - before.positions[old];
        newRest[v] = rest[old] + shift;
        if (animated)
            for (uint32_t k = oldKeys.offsets[old]; k < oldKeys.offsets[old + 1]; ++k)
                tracks[v].push_back({oldKeys.frames[k], oldKeys.positions[k] + shift});
    }

    // New vertices follow their kept edge neighbours (in the edited cage).
    std::vector<std::vector<uint32_t>> neighbours;
    bool anyNew = false;
    for (uint32_t v = 0; v < newCount; ++v) anyNew |= edit.oldVertexOf[v] == kNewElement;
    if (anyNew) {
        neighbours.resize(newCount);
        for (uint32_t f = 0; f < after.faceCount(); ++f) {
            const uint32_t begin = after.faceOffsets[f], n = after.faceOffsets[f + 1] - begin;
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t a = after.faceVertices[begin + i], b = after.faceVertices[begin + (i + 1) % n];
                if (edit.oldVertexOf[a] == kNewElement && edit.oldVertexOf[b] != kNewElement) neighbours[a].push_back(b);
                if (edit.oldVertexOf[b] == kNewElement && edit.oldVertexOf[a] != kNewElement) neighbours[b].push_back(a);
            }
        }
    }
    const std::vector<std::vector<std::pair<int32_t, glm::vec3>>> keptTracks = tracks;
    auto keptValue = [&](uint32_t v, double at) {
        const auto& track = keptTracks[v];
        if (track.empty()) return newRest[v];
        std::vector<int32_t> frames;
        std::vector<glm::vec3> values;
        for (const auto& [f, p] : track) frames.push_back(f), values.push_back(p);
        return evaluateTrack(frames.data(), values.data(), uint32_t(frames.size()), at, animation.interpolation);
    };
    for (uint32_t v = 0; v < newCount; ++v) {
        if (edit.oldVertexOf[v] != kNewElement) continue;
        std::vector<uint32_t>& sources = neighbours[v];
        std::sort(sources.begin(), sources.end());
        sources.erase(std::unique(sources.begin(), sources.end()), sources.end());
        std::vector<float> weights;
        float total = 0.0f;
        for (uint32_t s : sources) {
            const float d = glm::length(after.positions[v] - after.positions[s]);
            weights.push_back(1.0f / std::max(d, 1e-20f));
            total += weights.back();
        }
        std::vector<int32_t> frames;
        for (uint32_t s : sources)
            for (const auto& key : keptTracks[s]) frames.push_back(key.first);
        // Motion of the sources away from where they are at `frame`.
        auto motion = [&](double at) {
            glm::vec3 sum(0.0f);
            for (size_t i = 0; i < sources.size(); ++i)
                sum += (weights[i] / total) * (keptValue(sources[i], at) - keptValue(sources[i], frame));
            return sum;
        };
        const glm::vec3 here = after.positions[v];
        if (frames.empty()) {
            newRest[v] = here;
            continue;
        }
        if (frame == std::floor(frame)) frames.push_back(int32_t(frame));
        std::sort(frames.begin(), frames.end());
        frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
        for (int32_t f : frames) tracks[v].push_back({f, here + motion(f)});
        // Where the vertex rests: as far from its sources' rest as it is from them at `frame`.
        glm::vec3 restMotion(0.0f);
        for (size_t i = 0; i < sources.size(); ++i)
            restMotion += (weights[i] / total) * (newRest[sources[i]] - keptValue(sources[i], frame));
        newRest[v] = here + restMotion;
    }

    storeTracks(animation.vertexKeys, tracks);
    animation.sequencePattern.clear();
    rest = std::move(newRest);
}

}  // namespace qp
