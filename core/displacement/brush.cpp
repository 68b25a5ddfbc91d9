#include "displacement/brush.h"

#include <algorithm>
#include <bit>
#include <cassert>
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
                                            {"erase", BrushKind::Erase},
                                            {"inflate", BrushKind::Inflate},
                                            {"crease", BrushKind::Crease},
                                            {"mask", BrushKind::Mask},
                                            {"unmask", BrushKind::Unmask}};
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
// Inflate's 1 / (n_d . N) is capped here (a slope of about 75 degrees): steeper slopes would
// shoot samples out along N.
constexpr float kMaxInflateFactor = 4.0f;
// Crease's pinch: p = min(kMaxPinch, kPinchPerStrength * strength) * falloff.
constexpr float kMaxPinch = 0.5f;
constexpr float kPinchPerStrength = 4.0f;

}  // namespace

std::optional<BrushKind> brushKindFromName(std::string_view name) { return fromName(kBrushNames, name); }
std::optional<Falloff> falloffFromName(std::string_view name) { return fromName(kFalloffNames, name); }
std::optional<MirrorAxis> mirrorAxisFromName(std::string_view name) { return fromName(kMirrorNames, name); }
const char* brushKindName(BrushKind kind) { return toName(kBrushNames, kind); }
const char* falloffName(Falloff falloff) { return toName(kFalloffNames, falloff); }

Status validateBrush(const Brush& brush) {
    if (!std::isfinite(brush.radius) || brush.radius <= 0.0f)
        return Error{"brush radius must be a positive number, got " + number(brush.radius)};
    if (brush.radius > kMaxBrushRadius)
        return Error{"brush radius " + number(brush.radius) + " is absurdly large (at most " + number(kMaxBrushRadius) +
                     "): check the units"};
    if (!std::isfinite(brush.strength) || brush.strength < 0.0f)
        return Error{"brush strength must be a number >= 0, got " + number(brush.strength)};
    const bool blend = brush.kind == BrushKind::Smooth || brush.kind == BrushKind::Flatten || brush.kind == BrushKind::Erase;
    if (blend && brush.strength > 1.0f)
        return Error{std::string("the ") + brushKindName(brush.kind) + " brush blends towards a target: its strength "
                     "must be between 0 and 1, got " + number(brush.strength)};
    if (isMaskBrush(brush.kind) && brush.strength > 1.0f)
        return Error{std::string("the ") + brushKindName(brush.kind) + " brush changes mask values between 0 and 1: its "
                     "strength must be between 0 and 1, got " + number(brush.strength)};
    if (brush.strength > kMaxHeightStrength)
        return Error{std::string("the ") + brushKindName(brush.kind) + " brush's strength is a height per dab in radii: "
                     "at most " + number(kMaxHeightStrength) + ", got " + number(brush.strength)};
    return success();
}

Status checkBrushRadiusForModel(float radius, float diagonal) {
    if (std::isfinite(diagonal) && diagonal > 0.0f && !(double(radius) <= 1e6 * double(diagonal)))
        return Error{"brush radius " + number(radius) + " is more than a million times the model's size (bounding-box "
                     "diagonal " + number(diagonal) + "): check the units"};
    return success();
}

Status validateStroke(const StrokeOptions& options, std::span<const glm::vec3> path) {
    if (Status valid = validateBrush(options.brush); !valid) return valid;
    if (!std::isfinite(options.spacing) || options.spacing < 0.0f)
        return Error{"stroke spacing must be a number >= 0 (0: a quarter of the radius), got " + number(options.spacing)};
    for (size_t i = 0; i < path.size(); ++i) {
        const glm::vec3& p = path[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return Error{"stroke point " + std::to_string(i + 1) + " (" + number(p.x) + ", " + number(p.y) + ", " +
                         number(p.z) + ") is not a finite point"};
    }
    return success();
}

Status checkMaskable(const Displacement& displacement) {
    if (displacement.empty() || displacement.samples.empty())
        return Error{"the scene has no sculpted displacement to mask: sculpt first or set a resolution"};
    return success();
}

namespace {

std::vector<float>& recordTarget(Displacement& displacement, const StrokeRecord& record) {
    if (!record.mask) return displacement.samples;
    if (displacement.mask.size() != displacement.samples.size()) displacement.mask.assign(displacement.samples.size(), 0.0f);
    return displacement.mask;
}

// A mask record setting every sample to f(old), from the mask as it is (zeros if none).
template <class F>
Result<StrokeRecord> rewriteMask(Displacement& displacement, F f) {
    if (Status ok = checkMaskable(displacement); !ok) return ok.error();
    StrokeRecord record;
    record.mask = true;
    std::vector<float>& mask = recordTarget(displacement, record);
    for (uint32_t s = 0; s < mask.size(); ++s) {
        const float before = mask[s], after = canonicalZero(f(before));
        if (std::bit_cast<uint32_t>(before) == std::bit_cast<uint32_t>(after)) continue;
        record.changes.push_back({s, before, after});
        mask[s] = after;
    }
    return record;
}

}  // namespace

void undoStroke(Displacement& displacement, const StrokeRecord& record) {
    std::vector<float>& values = recordTarget(displacement, record);
    for (const SampleChange& c : record.changes) values[c.sample] = c.before;
}

void redoStroke(Displacement& displacement, const StrokeRecord& record) {
    std::vector<float>& values = recordTarget(displacement, record);
    for (const SampleChange& c : record.changes) values[c.sample] = c.after;
}

Result<StrokeRecord> invertMask(Displacement& displacement) {
    return rewriteMask(displacement, [](float m) { return 1.0f - m; });
}

Result<StrokeRecord> clearMask(Displacement& displacement) {
    return rewriteMask(displacement, [](float) { return 0.0f; });
}

std::vector<SampleRange> uploadRanges(const SampleBits& samples, uint32_t block) {
    assert(block > 0 && 64 % block == 0);
    const uint64_t group = block == 64 ? ~uint64_t(0) : (uint64_t(1) << block) - 1;
    std::vector<SampleRange> ranges;
    uint32_t end = 0;  // past the last sample in the set, as the list version clamps
    for (uint32_t word = 0; word < samples.words.size(); ++word) {
        const uint64_t bits = samples.words[word];
        if (!bits) continue;
        end = word * 64 + 64 - uint32_t(std::countl_zero(bits));
        for (uint32_t g = 0; g < 64 / block; ++g) {
            if (!(bits >> (g * block) & group)) continue;
            const uint32_t first = word * 64 + g * block;
            if (!ranges.empty() && ranges.back().first + ranges.back().count == first)
                ranges.back().count += block;
            else
                ranges.push_back({first, block});
        }
    }
    if (!ranges.empty()) ranges.back().count = std::min(ranges.back().first + ranges.back().count, end) - ranges.back().first;
    return ranges;
}

Sculptor::Sculptor(Displacement& displacement, const SculptSamples& samples)
    : displacement_(displacement), samples_(samples), mirrorCentre_(samples.centre()) {
    firstValues_.assign(displacement.samples.size(), FirstValue{});
    dabStamp_.assign(displacement.samples.size(), 0);
}

void Sculptor::beginStroke() {
    ++stroke_;
    touched_.clear();
    dabs_ = 0;
    strokePoint_.reset();
    strokeMask_ = false;
    // D may have changed between strokes (undo, redo, a replaced displacement with the same
    // layout): the displaced bounds are rebuilt at the stroke's first dab.
    cellsStale_ = true;
}

std::vector<uint32_t> Sculptor::changedSamples() const {
    const std::vector<float>& values = strokeValues();
    std::vector<uint32_t> out;
    for (uint32_t s : touched_)
        if (const float before = firstValues_[s].value; values[s] != before || std::signbit(values[s]) != std::signbit(before))
            out.push_back(s);
    std::sort(out.begin(), out.end());
    return out;
}

StrokeRecord Sculptor::endStroke() {
    StrokeRecord record;
    record.dabs = dabs_;
    record.mask = strokeMask_;
    const std::vector<float>& values = strokeValues();
    for (uint32_t s : changedSamples()) record.changes.push_back({s, firstValues_[s].value, values[s]});
    touched_.clear();
    ++stroke_;
    return record;
}

void Sculptor::gatherDab(const glm::vec3* centres, uint32_t centreCount, float radius) {
    // The samples reached and where the spatial index keeps their positions and normals
    // (read from there: in sequence rather than scattered).
    affected_.clear();
    indexed_.clear();
    samples_.queryDisplaced(centres[0], radius, cells_, affected_, &indexed_);
    if (centreCount > 1) {
        // The mirror image's samples, less those the dab itself reached.
        ++dabSerial_;
        for (uint32_t s : affected_) dabStamp_[s] = dabSerial_;
        const size_t own = affected_.size();
        samples_.queryDisplaced(centres[1], radius, cells_, affected_, &indexed_);
        size_t kept = own;
        for (size_t k = own; k < affected_.size(); ++k)
            if (dabStamp_[affected_[k]] != dabSerial_) affected_[kept] = affected_[k], indexed_[kept++] = indexed_[k];
        affected_.resize(kept);
        indexed_.resize(kept);
    }
}

void Sculptor::growDisplacedCells() { cells_.growIndexed(samples_, indexed_, newValues_); }

float Sculptor::sampleSpacing(uint32_t sample) const {
    float spacing = 0.0f;
    for (uint32_t n : samples_.neighbours(sample))
        spacing = std::max(spacing, glm::length(samples_.position(n) - samples_.position(sample)));
    return spacing;
}

float Sculptor::interpolateOldD(const glm::vec3& point, float spacing, float fallback) const {
    if (!(spacing > 0.0f)) return fallback;
    // One list per thread: big dabs interpolate on every core.
    thread_local std::vector<uint32_t> found;
    found.clear();
    const std::vector<float>& heights = displacement_.samples;
    samples_.queryDisplaced(point, spacing, cells_, found);
    const float exact = 1e-6f * spacing;
    double weights = 0.0, sum = 0.0;
    for (uint32_t s : found) {
        const glm::vec3 d = samples_.position(s) + heights[s] * samples_.normal(s) - point;
        const float d2 = glm::dot(d, d);
        if (d2 <= exact * exact) return heights[s];
        weights += 1.0 / double(d2);
        sum += double(heights[s]) / double(d2);
    }
    return weights > 0.0 ? float(sum / weights) : fallback;
}

float Sculptor::inflateFactor(uint32_t sample) const {
    // Least-squares gradient of D in the tangent plane of N: minimise sum (g . t_n - dD_n)^2
    // over the graph neighbours n, t_n their limit offsets projected on the plane.
    const glm::vec3& N = samples_.normal(sample);
    const glm::vec3 e1 = glm::normalize(glm::cross(N, std::abs(N.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
    const glm::vec3 e2 = glm::cross(N, e1);
    const std::vector<float>& heights = displacement_.samples;
    float a11 = 0.0f, a12 = 0.0f, a22 = 0.0f, b1 = 0.0f, b2 = 0.0f;
    for (uint32_t n : samples_.neighbours(sample)) {
        const glm::vec3 offset = samples_.position(n) - samples_.position(sample);
        const float t1 = glm::dot(offset, e1), t2 = glm::dot(offset, e2), dD = heights[n] - heights[sample];
        a11 += t1 * t1, a12 += t1 * t2, a22 += t2 * t2;
        b1 += t1 * dD, b2 += t2 * dD;
    }
    const float det = a11 * a22 - a12 * a12;
    if (!(det > 1e-6f * (a11 + a22) * (a11 + a22))) return 1.0f;  // neighbours along one line (or none)
    const float g1 = (a22 * b1 - a12 * b2) / det, g2 = (a11 * b2 - a12 * b1) / det;
    return std::min(kMaxInflateFactor, std::sqrt(1.0f + g1 * g1 + g2 * g2));
}

uint32_t Sculptor::dab(const Brush& brush, MirrorAxis mirror, const glm::vec3& centre) {
    // Refused input changes nothing (callers report why: validateStroke).
    if (!validateBrush(brush) || !std::isfinite(centre.x) || !std::isfinite(centre.y) || !std::isfinite(centre.z))
        return 0;
    const bool maskBrush = isMaskBrush(brush.kind);
    if (dabs_ > 0 && maskBrush != strokeMask_) return 0;  // a stroke changes one array
    if (displacement_.samples.empty()) return 0;
    if (dabs_ == 0) strokeMask_ = maskBrush;
    ++dabs_;
    const size_t sampleCount = displacement_.samples.size();
    if (maskBrush && displacement_.mask.size() != sampleCount) displacement_.mask.assign(sampleCount, 0.0f);
    if (cellsStale_ || !cells_.current(samples_)) {
        cells_.rebuild(samples_, displacement_.samples);
        cellsStale_ = false;
    }

    glm::vec3 centres[2] = {centre, centre};
    uint32_t centreCount = 1;
    if (mirror != MirrorAxis::None) {
        int axis = int(mirror) - 1;
        centres[1][axis] = 2.0f * mirrorCentre_[axis] - centre[axis];
        // A dab on the plane is its own mirror image: once is enough.
        if (std::abs(centres[1][axis] - centre[axis]) > 1e-6f * brush.radius) centreCount = 2;
    }
    gatherDab(centres, centreCount, brush.radius);
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

    // The array this stroke changes (D or the mask); the mask scales D's changes.
    std::vector<float>& values = strokeValues();
    const float* mask = !maskBrush && displacement_.mask.size() == sampleCount ? displacement_.mask.data() : nullptr;

    // Weights per centre, from the displaced positions the spatial index keeps (before this dab:
    // it grows them after the writes). Flatten needs them all for its planes before any new
    // value (weights_, the mirror image's in the second half); the others weigh each sample
    // where they update it.
    auto displacedAt = [&](size_t k) -> const glm::vec3& { return cells_.indexedDisplaced(indexed_[k]); };
    auto weightAt = [&](float distance) {
        if (distance > brush.radius) return 0.0f;
        return brush.strength * falloffWeight(brush.falloff, distance / brush.radius);
    };
    auto weighSample = [&](size_t k, float* w) {
        const glm::vec3& p = displacedAt(k);
        w[0] = weightAt(glm::length(p - centres[0]));
        w[1] = centreCount > 1 ? weightAt(glm::length(p - centres[1])) : 0.0f;
    };
    auto normal = [&](size_t k) -> const glm::vec3& { return samples_.indexedNormal(indexed_[k]); };
    const bool weighFirst = brush.kind == BrushKind::Flatten;
    if (weighFirst) {
        weights_.resize(2 * count);
        forEach(4096, [&](size_t begin, size_t end) {
            for (size_t k = begin; k < end; ++k) {
                float w[2];
                weighSample(k, w);
                weights_[k] = w[0], weights_[count + k] = w[1];
            }
        });
    }

    // Flatten: per centre, the plane through the weighted mean displaced point (mask or not:
    // masked samples are part of the surface the plane fits). Sums over fixed chunks added in
    // order, so the result does not depend on the threads.
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
                    sum.point += w * displacedAt(k);
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

    // Crease's pinch pulls by up to this fraction of a sample's distance from the centre.
    const float pinch = std::min(kMaxPinch, kPinchPerStrength * brush.strength);

    // New values from old ones only, then written together: the dab and its mirror image do
    // not see each other's effect, so neither order nor overlap breaks the symmetry.
    newValues_.resize(count);
    auto update = [&](size_t k) {
        const uint32_t s = affected_[k];
        const float d = values[s];
        // A fully masked sample keeps its bits; a partly masked one takes part of the change.
        const float keep = mask ? 1.0f - mask[s] : 1.0f;
        if (!(keep > 0.0f)) {
            newValues_[k] = d;
            return;
        }
        float w[2];
        if (weighFirst) w[0] = weights_[k], w[1] = weights_[count + k];
        else weighSample(k, w);
        w[0] *= keep, w[1] *= keep;
        float total = w[0] + w[1];
        float next = d;
        switch (brush.kind) {
        case BrushKind::Raise: next = d + total * brush.radius; break;
        case BrushKind::Lower: next = d - total * brush.radius; break;
        case BrushKind::Erase: next = d - std::min(total, 1.0f) * d; break;
        case BrushKind::Inflate: next = d + total * brush.radius * inflateFactor(s); break;
        case BrushKind::Mask: next = std::clamp(d + total, 0.0f, 1.0f); break;
        case BrushKind::Unmask: next = std::clamp(d - total, 0.0f, 1.0f); break;
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
                float target = d + glm::dot(planeNormal[c], planePoint[c] - displacedAt(k)) / along;
                delta += scale * w[c] * (target - d);
            }
            next = d + delta;
            break;
        }
        case BrushKind::Crease: {
            // Pinch (old D from a point farther out), then the cut with its cusp profile.
            float pinched = d, cut = 0.0f;
            for (uint32_t c = 0; c < centreCount; ++c) {
                if (w[c] <= 0.0f) continue;
                const glm::vec3 offset = displacedAt(k) - centres[c];
                const float x = std::min(glm::length(offset) / brush.radius, 1.0f);
                const float pulled = pinch * falloffWeight(brush.falloff, x) * keep;
                if (pulled > 0.0f)
                    pinched += interpolateOldD(centres[c] + offset * (1.0f + pulled), sampleSpacing(s), d) - d;
                cut += w[c] * (1.0f - x) * (1.0f - x);
            }
            next = pinched - cut * brush.radius;
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
            if (FirstValue& firstValue = firstValues_[s]; firstValue.stroke != stroke_) {
                firstValue = {stroke_, values[s]};
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
    // Displaced positions moved: later dabs of the stroke must find them where they are now.
    if (changed && !strokeMask_) growDisplacedCells();
    return changed;
}

uint32_t Sculptor::dabTo(const StrokeOptions& options, const glm::vec3& point, std::vector<uint32_t>* reached) {
    // A non-finite point would poison the path's length (and the dab count); it is skipped.
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z)) return 0;
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
    if (!validateStroke(options, path)) return {};
    Sculptor sculptor(displacement, samples);
    sculptor.beginStroke();
    sculptor.dabsAlong(options, path);
    return sculptor.endStroke();
}

}  // namespace qp
