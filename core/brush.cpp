#include "brush.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

template <class E>
struct Named {
    const char* name;
    E value;
};

constexpr Named<BrushKind> kBrushNames[] = {{"raise", BrushKind::Raise},
                                            {"lower", BrushKind::Lower},
                                            {"smooth", BrushKind::Smooth},
                                            {"flatten", BrushKind::Flatten},
                                            {"erase", BrushKind::Erase}};
constexpr Named<Falloff> kFalloffNames[] = {
    {"smooth", Falloff::Smooth}, {"linear", Falloff::Linear}, {"constant", Falloff::Constant}, {"sphere", Falloff::Sphere}};
constexpr Named<MirrorAxis> kMirrorNames[] = {
    {"none", MirrorAxis::None}, {"x", MirrorAxis::X}, {"y", MirrorAxis::Y}, {"z", MirrorAxis::Z}};

template <class E, size_t N>
std::optional<E> fromName(const Named<E> (&names)[N], std::string_view name) {
    for (const Named<E>& n : names)
        if (name == n.name) return n.value;
    return std::nullopt;
}

template <class E, size_t N>
const char* toName(const Named<E> (&names)[N], E value) {
    for (const Named<E>& n : names)
        if (n.value == value) return n.name;
    return "";
}

std::string number(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(value));
    return text;
}

// Values are never written as -0, so equal values always have equal bits.
float canonicalZero(float value) { return value + 0.0f; }

// Dabs reaching fewer samples run on the calling thread.
constexpr size_t kSerialDab = 8192;
// Flatten's sums and the writes: samples per chunk.
constexpr size_t kSumChunk = 4096;

}  // namespace

std::optional<BrushKind> brushKindFromName(std::string_view name) { return fromName(kBrushNames, name); }
std::optional<Falloff> falloffFromName(std::string_view name) { return fromName(kFalloffNames, name); }
std::optional<MirrorAxis> mirrorAxisFromName(std::string_view name) { return fromName(kMirrorNames, name); }
const char* brushKindName(BrushKind kind) { return toName(kBrushNames, kind); }
const char* falloffName(Falloff falloff) { return toName(kFalloffNames, falloff); }

float falloffWeight(Falloff falloff, float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    switch (falloff) {
    case Falloff::Smooth: return 1.0f - x * x * (3.0f - 2.0f * x);
    case Falloff::Linear: return 1.0f - x;
    case Falloff::Constant: return 1.0f;
    case Falloff::Sphere: return std::sqrt(1.0f - x * x);
    }
    return 0.0f;
}

Status validateBrush(const Brush& brush) {
    if (!std::isfinite(brush.radius) || brush.radius <= 0.0f)
        return Error{"brush radius must be a positive number, got " + number(brush.radius)};
    if (!std::isfinite(brush.strength) || brush.strength < 0.0f)
        return Error{"brush strength must be a number >= 0, got " + number(brush.strength)};
    bool blend = brush.kind == BrushKind::Smooth || brush.kind == BrushKind::Flatten || brush.kind == BrushKind::Erase;
    if (blend && brush.strength > 1.0f)
        return Error{std::string("the ") + brushKindName(brush.kind) + " brush blends towards a target: its strength "
                     "must be between 0 and 1, got " + number(brush.strength)};
    return success();
}

void undoStroke(Displacement& displacement, const StrokeRecord& record) {
    for (const SampleChange& c : record.changes) displacement.samples[c.sample] = c.before;
}

void redoStroke(Displacement& displacement, const StrokeRecord& record) {
    for (const SampleChange& c : record.changes) displacement.samples[c.sample] = c.after;
}

std::vector<SampleRange> uploadRanges(std::span<const uint32_t> samples, uint32_t block) {
    // A bitmap of blocks (a few KiB even for millions of samples) instead of a sort.
    uint32_t end = 0;
    for (uint32_t s : samples) end = std::max(end, s + 1);
    const uint32_t blocks = (end + block - 1) / block;
    std::vector<uint64_t> marked((blocks + 63) / 64, 0);
    for (uint32_t s : samples) marked[s / block / 64] |= uint64_t(1) << (s / block % 64);
    std::vector<SampleRange> ranges;
    for (uint32_t word = 0; word < marked.size(); ++word)
        for (uint64_t bits = marked[word]; bits; bits &= bits - 1) {
            uint32_t first = (word * 64 + uint32_t(std::countr_zero(bits))) * block;
            if (!ranges.empty() && ranges.back().first + ranges.back().count == first)
                ranges.back().count += block;
            else
                ranges.push_back({first, block});
        }
    if (!ranges.empty()) ranges.back().count = std::min(ranges.back().first + ranges.back().count, end) - ranges.back().first;
    return ranges;
}

std::vector<SampleRange> uploadRanges(const StrokeRecord& record, uint32_t block) {
    std::vector<uint32_t> samples;
    samples.reserve(record.changes.size());
    for (const SampleChange& c : record.changes) samples.push_back(c.sample);
    return uploadRanges(samples, block);
}

Sculptor::Sculptor(Displacement& displacement, const SculptSamples& samples)
    : displacement_(displacement), samples_(samples), mirrorCentre_(samples.centre()) {
    touchedInStroke_.assign(displacement.samples.size(), 0);
    before_.assign(displacement.samples.size(), 0.0f);
    dabStamp_.assign(displacement.samples.size(), 0);
}

void Sculptor::beginStroke() {
    ++stroke_;
    touched_.clear();
    dabs_ = 0;
    strokePoint_.reset();
}

std::vector<uint32_t> Sculptor::changedSamples() const {
    std::vector<uint32_t> out;
    for (uint32_t s : touched_)
        if (displacement_.samples[s] != before_[s] ||
            std::signbit(displacement_.samples[s]) != std::signbit(before_[s]))
            out.push_back(s);
    std::sort(out.begin(), out.end());
    return out;
}

StrokeRecord Sculptor::endStroke() {
    StrokeRecord record;
    record.dabs = dabs_;
    for (uint32_t s : changedSamples()) record.changes.push_back({s, before_[s], displacement_.samples[s]});
    touched_.clear();
    ++stroke_;
    return record;
}

uint32_t Sculptor::dab(const Brush& brush, MirrorAxis mirror, const glm::vec3& centre) {
    ++dabs_;
    glm::vec3 centres[2] = {centre, centre};
    uint32_t centreCount = 1;
    if (mirror != MirrorAxis::None) {
        int axis = int(mirror) - 1;
        centres[1][axis] = 2.0f * mirrorCentre_[axis] - centre[axis];
        // A dab on the plane is its own mirror image: once is enough.
        if (std::abs(centres[1][axis] - centre[axis]) > 1e-6f * brush.radius) centreCount = 2;
    }

    // The samples reached and where the spatial index keeps their positions and normals
    // (read from there: in sequence rather than scattered).
    affected_.clear();
    indexed_.clear();
    samples_.query(centres[0], brush.radius, affected_, &indexed_);
    if (centreCount > 1) {
        // The mirror image's samples, less those the dab itself reached.
        ++dabSerial_;
        for (uint32_t s : affected_) dabStamp_[s] = dabSerial_;
        const size_t own = affected_.size();
        samples_.query(centres[1], brush.radius, affected_, &indexed_);
        size_t kept = own;
        for (size_t k = own; k < affected_.size(); ++k)
            if (dabStamp_[affected_[k]] != dabSerial_) affected_[kept] = affected_[k], indexed_[kept++] = indexed_[k];
        affected_.resize(kept);
        indexed_.resize(kept);
    }
    if (affected_.empty()) return 0;
    const size_t count = affected_.size();

    // Big dabs spread their passes over the cores; each element depends on old values only.
    auto forEach = [count](size_t grain, const auto& body) {
        if (count < kSerialDab) {
            body(size_t(0), count);
            return;
        }
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count, grain),
                          [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
    };

    // Weights per centre (the mirror image's in the second half).
    std::vector<float>& values = displacement_.samples;
    weights_.resize(2 * count);
    auto weightAt = [&](float distance) {
        if (distance > brush.radius) return 0.0f;
        return brush.strength * falloffWeight(brush.falloff, distance / brush.radius);
    };
    auto position = [&](size_t k) -> const glm::vec3& { return samples_.indexedPosition(indexed_[k]); };
    auto normal = [&](size_t k) -> const glm::vec3& { return samples_.indexedNormal(indexed_[k]); };
    forEach(4096, [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {
            weights_[k] = weightAt(glm::length(position(k) - centres[0]));
            weights_[count + k] = centreCount > 1 ? weightAt(glm::length(position(k) - centres[1])) : 0.0f;
        }
    });
    auto displaced = [&](size_t k) { return position(k) + values[affected_[k]] * normal(k); };

    // Flatten: per centre, the plane through the weighted mean displaced point. Sums over
    // fixed chunks added in order, so the result does not depend on the threads.
    glm::vec3 planePoint[2], planeNormal[2];
    bool havePlane[2] = {false, false};
    if (brush.kind == BrushKind::Flatten) {
        struct Sums {
            glm::vec3 point{0.0f}, normal{0.0f};
            float total = 0.0f;
        };
        const size_t chunks = (count + kSumChunk - 1) / kSumChunk;
        std::vector<Sums> partial(2 * chunks);
        auto sumChunk = [&](size_t chunk) {
            for (uint32_t c = 0; c < centreCount; ++c) {
                Sums& sum = partial[c * chunks + chunk];
                for (size_t k = chunk * kSumChunk; k < std::min(count, (chunk + 1) * kSumChunk); ++k) {
                    const float w = weights_[c * count + k];
                    if (w <= 0.0f) continue;
                    sum.point += w * displaced(k);
                    sum.normal += w * normal(k);
                    sum.total += w;
                }
            }
        };
        if (chunks == 1) sumChunk(0);
        else tbb::parallel_for(size_t(0), chunks, sumChunk);
        for (uint32_t c = 0; c < centreCount; ++c) {
            Sums sum;
            for (size_t chunk = 0; chunk < chunks; ++chunk) {
                sum.point += partial[c * chunks + chunk].point;
                sum.normal += partial[c * chunks + chunk].normal;
                sum.total += partial[c * chunks + chunk].total;
            }
            if (sum.total > 0.0f && glm::length(sum.normal) > 0.0f) {
                planePoint[c] = sum.point / sum.total;
                planeNormal[c] = glm::normalize(sum.normal);
                havePlane[c] = true;
            }
        }
    }

    // New values from old ones only, then written together: the dab and its mirror image do
    // not see each other's effect, so neither order nor overlap breaks the symmetry.
    newValues_.resize(count);
    auto update = [&](size_t k) {
        const uint32_t s = affected_[k];
        const float d = values[s];
        float w[2] = {weights_[k], weights_[count + k]};
        float total = w[0] + w[1];
        float next = d;
        switch (brush.kind) {
        case BrushKind::Raise: next = d + total * brush.radius; break;
        case BrushKind::Lower: next = d - total * brush.radius; break;
        case BrushKind::Erase: next = d - std::min(total, 1.0f) * d; break;
        case BrushKind::Smooth: {
            auto neighbours = samples_.neighbours(s);
            if (neighbours.empty()) break;
            float sum = 0.0f;
            for (uint32_t n : neighbours) sum += values[n];
            next = d + std::min(total, 1.0f) * (sum / float(neighbours.size()) - d);
            break;
        }
        case BrushKind::Flatten: {
            // Blend towards each plane; weights summing past 1 are scaled to 1.
            float scale = total > 1.0f ? 1.0f / total : 1.0f;
            float delta = 0.0f;
            for (uint32_t c = 0; c < centreCount; ++c) {
                if (w[c] <= 0.0f || !havePlane[c]) continue;
                float along = glm::dot(planeNormal[c], normal(k));
                if (std::abs(along) < 0.1f) continue;  // the plane is nearly parallel to the normal
                float target = d + glm::dot(planeNormal[c], planePoint[c] - displaced(k)) / along;
                delta += scale * w[c] * (target - d);
            }
            next = d + delta;
            break;
        }
        }
        newValues_[k] = canonicalZero(next);
    };
    forEach(2048, [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) update(k);
    });

    // The writes and the stroke's bookkeeping: every sample once, so chunks run on any core;
    // samples the stroke touches for the first time join touched_ in chunk order.
    const size_t chunks = (count + kSumChunk - 1) / kSumChunk;
    firstTouches_.resize(count);
    chunkCounts_.assign(2 * chunks, 0);  // per chunk: samples changed, first touches
    auto writeChunk = [&](size_t chunk) {
        const size_t begin = chunk * kSumChunk, end = std::min(count, begin + kSumChunk);
        uint32_t changed = 0, first = 0;
        for (size_t k = begin; k < end; ++k) {
            const uint32_t s = affected_[k];
            if (newValues_[k] == values[s] && std::signbit(newValues_[k]) == std::signbit(values[s])) continue;
            if (touchedInStroke_[s] != stroke_) {
                touchedInStroke_[s] = stroke_;
                before_[s] = values[s];
                firstTouches_[begin + first++] = s;
            }
            values[s] = newValues_[k];
            ++changed;
        }
        chunkCounts_[2 * chunk] = changed;
        chunkCounts_[2 * chunk + 1] = first;
    };
    if (count < kSerialDab) {
        for (size_t chunk = 0; chunk < chunks; ++chunk) writeChunk(chunk);
    } else {
        tbb::parallel_for(size_t(0), chunks, writeChunk);
    }
    uint32_t changed = 0;
    for (size_t chunk = 0; chunk < chunks; ++chunk) {
        changed += chunkCounts_[2 * chunk];
        const auto first = firstTouches_.begin() + std::ptrdiff_t(chunk * kSumChunk);
        touched_.insert(touched_.end(), first, first + chunkCounts_[2 * chunk + 1]);
    }
    return changed;
}

uint32_t Sculptor::dabTo(const StrokeOptions& options, const glm::vec3& point, std::vector<uint32_t>* reached) {
    auto dabAt = [&](const glm::vec3& centre) {
        const uint32_t changed = dab(options.brush, options.mirror, centre);
        if (reached) reached->insert(reached->end(), affected_.begin(), affected_.end());
        return changed;
    };
    const double spacing = options.spacing > 0.0f ? options.spacing : 0.25 * double(options.brush.radius);
    if (!strokePoint_) {
        strokePoint_ = point;
        untilNext_ = spacing;
        return dabAt(point);
    }
    // Dab k of the segment sits at untilNext_ + k * spacing, computed from k in double: summing
    // spacings in float stops advancing once the sum dwarfs the spacing, and the loop would
    // never end.
    const glm::vec3 a = *strokePoint_, b = point;
    strokePoint_ = point;
    const double length = glm::length(glm::dvec3(b) - glm::dvec3(a));
    if (length < untilNext_) {
        untilNext_ -= length;
        return 0;
    }
    // A dab that rounding puts a hair past the segment's end still counts (paths through grid
    // points at whole spacings get the dab at each point).
    const uint64_t dabs = uint64_t((length - untilNext_) / spacing + 1e-5) + 1;
    uint32_t changed = 0;
    for (uint64_t k = 0; k < dabs; ++k) {
        const double at = untilNext_ + double(k) * spacing;
        changed += dabAt(a + (b - a) * float(at / length));
    }
    untilNext_ = untilNext_ + double(dabs) * spacing - length;
    return changed;
}

uint32_t Sculptor::dabsAlong(const StrokeOptions& options, std::span<const glm::vec3> path) {
    uint32_t changed = 0;
    for (const glm::vec3& point : path) changed += dabTo(options, point);
    return changed;
}

StrokeRecord applyStroke(Displacement& displacement, const SculptSamples& samples, const StrokeOptions& options,
                         std::span<const glm::vec3> path) {
    Sculptor sculptor(displacement, samples);
    sculptor.beginStroke();
    sculptor.dabsAlong(options, path);
    return sculptor.endStroke();
}

}  // namespace qp
