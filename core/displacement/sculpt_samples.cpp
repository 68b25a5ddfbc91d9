#include "displacement/sculpt_samples.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace qp {

namespace {

// Cells hold about this many samples on a flat sheet of samples.
constexpr float kSamplesPerCellSide = 4.0f;
constexpr int kCellBits = 21;
constexpr int64_t kCellBias = int64_t(1) << (kCellBits - 1);
// A displaced query with more candidate samples than this collects runs of cells on every core.
constexpr size_t kParallelQuerySamples = 8192;

// Revisions are unique across every SculptSamples, so cells built for one cache (or one that
// stood at the same address before) are never taken as current for another.
std::atomic<uint64_t> nextRevision{1};

// Squared distance from a point to a box (0 inside). Monotonic in each coordinate's gap, so a
// point in the box is never farther in float than the box is.
inline float squaredDistanceToBox(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
    const glm::vec3 gap = glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f));
    return glm::dot(gap, gap);
}

}  // namespace

BoundaryOwners computeBoundaryOwners(const SampleGridLayout& layout, const PlannedCage& planned) {
    BoundaryOwners owners;
    owners.points.assign(layout.pointCount, PointOwner{});
    owners.segments.assign(layout.segments.size(), SegmentOwner{});
    for (uint32_t s = 0; s < layout.subfaces.size(); ++s) {
        if (!planned.hasSurface(s)) continue;
        const DisplacementSubface& sf = layout.subfaces[s];
        for (uint32_t c = 0; c < 4; ++c)
            if (owners.points[sf.corners[c]].subface == kNoSite) owners.points[sf.corners[c]] = {s, c};
        for (uint32_t e = 0; e < 4; ++e) {
            const DisplacementEdge& edge = sf.edges[e];
            for (uint32_t half = 0; half < (edge.flags & kEdgeSplit ? 2u : 1u); ++half) {
                uint32_t seg = half ? edge.secondHalf : edge.segment;
                if (owners.segments[seg].subface == kNoSite) owners.segments[seg] = {s, e, half};
            }
        }
    }
    return owners;
}

glm::vec2 SegmentOwner::uv(const SampleGridLayout& layout, uint32_t k, uint32_t m) const {
    return edgePoint(edge, edgeParameter(layout.subfaces[subface].edges[edge], half, k, m));
}

std::vector<SampleSite> computeSampleSites(const DisplacementLayout& layout, const PlannedCage& planned) {
    std::vector<SampleSite> sites(layout.sampleCount);
    for (uint32_t s = 0; s < layout.sampleCount; ++s)
        if (layout.homes[s].corner < 0 && planned.hasSurface(layout.homes[s].tile)) sites[s] = sampleSite(layout, s);
    // Shared corner samples: the first tile around the corner with a surface.
    for (uint32_t t = 0; t < layout.tiles.size(); ++t) {
        if (!planned.hasSurface(t)) continue;
        const int last = int(layout.tiles[t].cells) - 1;
        for (uint32_t k = 0; k < 4; ++k) {
            const uint32_t s = layout.sampleAt(t, kCornerU[k] == 0.0f ? 0 : last, kCornerV[k] == 0.0f ? 0 : last);
            if (layout.homes[s].corner >= 0 && sites[s].subface == kNoSite) sites[s] = {t, kCornerU[k], kCornerV[k]};
        }
    }
    return sites;
}

glm::vec3 limitNormal(const PlannedCage& planned, uint32_t subface, float u, float v, const LimitSample& sample) {
    glm::vec3 n = glm::cross(sample.du, sample.dv);
    float length = glm::length(n);
    float scale = glm::length(sample.du) * glm::length(sample.dv);
    if (length > 1e-6f * scale && length > 0.0f) return n / length;
    // Degenerate here: step a hair towards the sub-face centre.
    constexpr float kStep = 1e-3f;
    float nu = u + (u < 0.5f ? kStep : -kStep), nv = v + (v < 0.5f ? kStep : -kStep);
    LimitSample inside = planned.evaluate(subface, nu, nv);
    n = glm::cross(inside.du, inside.dv);
    length = glm::length(n);
    return length > 0.0f ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

std::vector<uint32_t> subfacesAffectedByVertices(const PlannedCage& planned, std::span<const uint32_t> vertices) {
    const Cage& cage = planned.cage();
    const Topology& topology = planned.topology();
    auto facesAt = [&](std::span<const uint32_t> vs) {
        std::vector<uint32_t> faces;
        for (uint32_t v : vs)
            for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k)
                faces.push_back(topology.vertexFaces[k]);
        std::sort(faces.begin(), faces.end());
        faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
        return faces;
    };
    // A face's limit depends on its 1-ring: the faces sharing a vertex with it.
    std::vector<uint32_t> ringVertices;
    for (uint32_t f : facesAt(vertices))
        ringVertices.insert(ringVertices.end(), cage.faceBegin(f), cage.faceBegin(f) + cage.faceSize(f));
    std::sort(ringVertices.begin(), ringVertices.end());
    ringVertices.erase(std::unique(ringVertices.begin(), ringVertices.end()), ringVertices.end());
    std::vector<uint32_t> subfaces;
    for (uint32_t f : facesAt(ringVertices))
        for (uint32_t s = planned.firstSubface(f); s < planned.firstSubface(f + 1); ++s) subfaces.push_back(s);
    return subfaces;
}

SculptSamples SculptSamples::build(const PlannedCage& planned, const DisplacementLayout& layout) {
    SculptSamples out;
    out.sites_ = computeSampleSites(layout, planned);
    const uint32_t count = layout.sampleCount;
    out.positions_.assign(count, glm::vec3(0.0f));
    out.normals_.assign(count, glm::vec3(0.0f));

    const uint32_t subfaces = uint32_t(layout.tiles.size());
    out.subfaceSampleOffsets_.assign(subfaces + 1, 0);
    for (const SampleSite& site : out.sites_)
        if (site.subface != kNoSite) ++out.subfaceSampleOffsets_[site.subface + 1];
    for (uint32_t s = 0; s < subfaces; ++s) out.subfaceSampleOffsets_[s + 1] += out.subfaceSampleOffsets_[s];
    out.subfaceSamples_.resize(out.subfaceSampleOffsets_.back());
    std::vector<uint32_t> fill(out.subfaceSampleOffsets_.begin(), out.subfaceSampleOffsets_.end() - 1);
    std::vector<uint32_t> sited;
    for (uint32_t i = 0; i < count; ++i)
        if (out.sites_[i].subface != kNoSite) {
            out.subfaceSamples_[fill[out.sites_[i].subface]++] = i;
            sited.push_back(i);
        }
    out.evaluateSites(planned, sited);

    // The sample graph: neighbouring cells of the padded blocks of tiles with a surface.
    std::vector<uint64_t> pairs;
    pairs.reserve(2 * size_t(layout.padded.size()));
    auto link = [&](uint32_t a, uint32_t b) {
        if (a != b) pairs.push_back(uint64_t(std::min(a, b)) << 32 | std::max(a, b));
    };
    for (uint32_t s = 0; s < subfaces; ++s) {
        if (!planned.hasSurface(s)) continue;
        const int n = int(layout.tiles[s].cells);
        for (int j = 0; j < n; ++j)
            for (int i = -1; i < n; ++i) {
                link(layout.sampleAt(s, i, j), layout.sampleAt(s, i + 1, j));
                link(layout.sampleAt(s, j, i), layout.sampleAt(s, j, i + 1));
            }
    }
    tbb::parallel_sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    out.neighbourOffsets_.assign(count + 1, 0);
    for (uint64_t p : pairs) {
        ++out.neighbourOffsets_[uint32_t(p >> 32) + 1];
        ++out.neighbourOffsets_[uint32_t(p) + 1];
    }
    for (uint32_t i = 0; i < count; ++i) out.neighbourOffsets_[i + 1] += out.neighbourOffsets_[i];
    out.neighbours_.resize(out.neighbourOffsets_.back());
    fill.assign(out.neighbourOffsets_.begin(), out.neighbourOffsets_.end() - 1);
    for (uint64_t p : pairs) {
        uint32_t a = uint32_t(p >> 32), b = uint32_t(p);
        out.neighbours_[fill[a]++] = b;
        out.neighbours_[fill[b]++] = a;
    }
    out.buildIndex();
    out.revision_ = nextRevision++;
    return out;
}

void SculptSamples::refresh(const PlannedCage& planned, std::span<const uint32_t> subfaces) {
    std::vector<uint32_t> samples;
    for (uint32_t s : subfaces)
        samples.insert(samples.end(), subfaceSamples_.begin() + subfaceSampleOffsets_[s],
                       subfaceSamples_.begin() + subfaceSampleOffsets_[s + 1]);
    std::vector<glm::vec3> before(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) before[i] = positions_[samples[i]];
    evaluateSites(planned, samples);
    revision_ = nextRevision++;
    for (uint32_t sample : samples) {
        cellPositions_[cellIndexOfSample_[sample]] = positions_[sample];
        cellNormals_[cellIndexOfSample_[sample]] = normals_[sample];
    }
    // The index files samples by where they were when it was built; queries widen by how far
    // any sample has moved since (slack), and the index is rebuilt once that grows past half
    // a cell, so a small edit costs only the evaluation.
    float moved = 0.0f;
    for (size_t i = 0; i < samples.size(); ++i) moved = std::max(moved, glm::length(positions_[samples[i]] - before[i]));
    slack_ += moved;
    if (!(slack_ <= 0.5f * cellSize_)) {
        buildIndex();
        return;
    }
    boundsMin_ = glm::vec3(INFINITY), boundsMax_ = glm::vec3(-INFINITY);
    for (uint32_t i = 0; i < sites_.size(); ++i)
        if (sites_[i].subface != kNoSite) {
            boundsMin_ = glm::min(boundsMin_, positions_[i]);
            boundsMax_ = glm::max(boundsMax_, positions_[i]);
        }
}

void SculptSamples::evaluateSites(const PlannedCage& planned, std::span<const uint32_t> samples) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, samples.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
            uint32_t sample = samples[i];
            const SampleSite& site = sites_[sample];
            LimitSample limit = planned.evaluate(site.subface, site.u, site.v);
            positions_[sample] = limit.position;
            normals_[sample] = limitNormal(planned, site.subface, site.u, site.v, limit);
        }
    });
}

uint64_t SculptSamples::cellKey(const glm::vec3& p) const {
    uint64_t key = 0;
    for (int axis = 0; axis < 3; ++axis) {
        int64_t c = int64_t(std::floor((p[axis] - indexMin_[axis]) / cellSize_)) + kCellBias;
        key = key << kCellBits | (uint64_t(std::clamp<int64_t>(c, 0, (int64_t(1) << kCellBits) - 1)));
    }
    return key;
}

void SculptSamples::buildIndex() {
    std::vector<uint32_t>& sited = scratchSited_;
    sited.clear();
    boundsMin_ = glm::vec3(INFINITY), boundsMax_ = glm::vec3(-INFINITY);
    for (uint32_t i = 0; i < sites_.size(); ++i)
        if (sites_[i].subface != kNoSite) {
            sited.push_back(i);
            boundsMin_ = glm::min(boundsMin_, positions_[i]);
            boundsMax_ = glm::max(boundsMax_, positions_[i]);
        }
    cellKeys_.clear(), cellOffsets_.assign(1, 0), cellSamples_.clear(), cellPositions_.clear(), cellNormals_.clear();
    cellIndexOfSample_.assign(sites_.size(), UINT32_MAX);
    cellOfIndexed_.clear();
    slack_ = 0.0f;
    if (sited.empty()) {
        boundsMin_ = boundsMax_ = glm::vec3(0.0f);
        return;
    }
    indexMin_ = boundsMin_, indexMax_ = boundsMax_;
    // Samples cover a surface: about sqrt(N) along the largest extent.
    glm::vec3 extent = boundsMax_ - boundsMin_;
    float largest = std::max({extent.x, extent.y, extent.z, 1e-6f});
    cellSize_ = kSamplesPerCellSide * largest / std::sqrt(float(sited.size()));
    std::vector<std::pair<uint64_t, uint32_t>>& keyed = scratchKeyed_;
    keyed.resize(sited.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, sited.size(), 4096), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) keyed[i] = {cellKey(positions_[sited[i]]), sited[i]};
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());
    cellSamples_.reserve(keyed.size());
    cellPositions_.reserve(keyed.size());
    cellNormals_.reserve(keyed.size());
    for (size_t i = 0; i < keyed.size(); ++i) {
        if (i == 0 || keyed[i].first != keyed[i - 1].first) {
            if (i) cellOffsets_.push_back(uint32_t(i));
            cellKeys_.push_back(keyed[i].first);
        }
        cellSamples_.push_back(keyed[i].second);
        cellOfIndexed_.push_back(uint32_t(cellKeys_.size() - 1));
        cellPositions_.push_back(positions_[keyed[i].second]);
        cellNormals_.push_back(normals_[keyed[i].second]);
        cellIndexOfSample_[keyed[i].second] = uint32_t(i);
    }
    cellOffsets_.push_back(uint32_t(keyed.size()));
}

template <class Visit>
void SculptSamples::forEachCellNear(const glm::vec3& centre, float reach, const Visit& visit) const {
    int64_t lo[3], hi[3];
    for (int axis = 0; axis < 3; ++axis) {
        // Clamp to the indexed range so a huge radius does not walk empty space.
        const float a = std::max(centre[axis] - reach, indexMin_[axis]);
        const float b = std::min(centre[axis] + reach, indexMax_[axis]);
        if (!(a <= b)) return;
        lo[axis] = int64_t(std::floor((a - indexMin_[axis]) / cellSize_)) + kCellBias;
        hi[axis] = int64_t(std::floor((b - indexMin_[axis]) / cellSize_)) + kCellBias;
    }
    // Columns are visited in key order: each search starts where the last one ended and
    // gallops, so a big sphere costs about one step per column, not a search of every cell.
    auto it = cellKeys_.begin();
    const auto end = cellKeys_.end();
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
        for (int64_t y = lo[1]; y <= hi[1]; ++y) {
            // Cells along z with fixed (x, y) are consecutive keys: one search per column.
            const uint64_t first = (uint64_t(x) << kCellBits | uint64_t(y)) << kCellBits | uint64_t(lo[2]);
            const uint64_t last = (uint64_t(x) << kCellBits | uint64_t(y)) << kCellBits | uint64_t(hi[2]);
            ptrdiff_t step = 1;
            while (step < end - it && it[step] < first) step *= 2;
            it = std::lower_bound(it + step / 2, it + std::min(step, ptrdiff_t(end - it)), first);
            for (; it != end && *it <= last; ++it) visit(size_t(it - cellKeys_.begin()));
        }
}

void SculptSamples::query(const glm::vec3& centre, float radius, std::vector<uint32_t>& out,
                          std::vector<uint32_t>* indexed) const {
    if (cellKeys_.empty() || !(radius >= 0.0f)) return;
    const float r2 = radius * radius;
    forEachCellNear(centre, radius + slack_, [&](size_t cell) {  // samples are filed where they were at the last build
        for (uint32_t k = cellOffsets_[cell]; k < cellOffsets_[cell + 1]; ++k) {
            const glm::vec3 d = cellPositions_[k] - centre;
            if (glm::dot(d, d) > r2) continue;
            out.push_back(cellSamples_[k]);
            if (indexed) indexed->push_back(k);
        }
    });
}

// Displaced queries ---------------------------------------------------------------------------

bool DisplacedCells::current(const SculptSamples& samples) const {
    return revision_ != 0 && revision_ == samples.revision() && lift_.size() == samples.cellKeys_.size();
}

void DisplacedCells::include(uint32_t cell, const glm::vec3& lo, const glm::vec3& hi, float lift, bool whole) {
    if (whole) {  // every displaced position of the cell is in lo .. hi: the exact box
        lo_[cell] = lo, hi_[cell] = hi, lift_[cell] = lift;
    } else {
        lo_[cell] = glm::min(lo_[cell], lo);
        hi_[cell] = glm::max(hi_[cell], hi);
        if (!(lift <= lift_[cell])) lift_[cell] = lift;  // NaN lifts too: such a cell is always tested
    }
    uint32_t slot = farSlot_[cell];
    if (slot == UINT32_MAX) {
        if (lift_[cell] <= farLift_) {
            nearLift_ = std::max(nearLift_, lift_[cell]);
            return;
        }
        slot = farSlot_[cell] = uint32_t(farCells_.size());
        farCells_.push_back(cell);
        farLo_.push_back(lo_[cell]);
        farHi_.push_back(hi_[cell]);
    }
    farLo_[slot] = lo_[cell];
    farHi_[slot] = hi_[cell];
}

void DisplacedCells::rebuild(const SculptSamples& samples, std::span<const float> values) {
    const size_t cells = samples.cellKeys_.size();
    lo_.assign(cells, glm::vec3(INFINITY));
    hi_.assign(cells, glm::vec3(-INFINITY));
    lift_.assign(cells, 0.0f);
    farSlot_.assign(cells, UINT32_MAX);
    farCells_.clear(), farLo_.clear(), farHi_.clear();
    nearLift_ = 0.0f;
    revision_ = samples.revision();
    displaced_.resize(samples.cellSamples_.size());
    // Cells are independent: each one's box and lift in parallel, then the far list in order.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, cells, 256), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t cell = range.begin(); cell != range.end(); ++cell)
            for (uint32_t k = samples.cellOffsets_[cell]; k < samples.cellOffsets_[cell + 1]; ++k) {
                const float d = values[samples.cellSamples_[k]];
                const glm::vec3 p = displaced_[k] = samples.cellPositions_[k] + d * samples.cellNormals_[k];
                lo_[cell] = glm::min(lo_[cell], p);
                hi_[cell] = glm::max(hi_[cell], p);
                const float lift = std::abs(d);
                if (!(lift <= lift_[cell])) lift_[cell] = lift;
            }
    });
    // The far threshold: at least a cell, and at least the kMaxFarCells-th largest lift.
    farLift_ = samples.cellSize_;
    if (cells > kMaxFarCells) {
        std::vector<float> lifts(lift_);
        auto nth = lifts.begin() + std::ptrdiff_t(cells - kMaxFarCells);
        std::nth_element(lifts.begin(), nth, lifts.end());
        if (*nth > farLift_) farLift_ = *nth;
    }
    for (uint32_t cell = 0; cell < cells; ++cell) {
        if (!(lift_[cell] <= farLift_)) {
            farSlot_[cell] = uint32_t(farCells_.size());
            farCells_.push_back(cell);
            farLo_.push_back(lo_[cell]);
            farHi_.push_back(hi_[cell]);
        } else {
            nearLift_ = std::max(nearLift_, lift_[cell]);
        }
    }
}

void DisplacedCells::growIndexed(const SculptSamples& samples, std::span<const uint32_t> indexed,
                                 std::span<const float> values) {
    assert(indexed.size() == values.size());
    // Chunks end where a cell does, so every run of one cell lies in one chunk and the runs are
    // those of one pass over the list; include() then takes them in the list's order (the far
    // list's order, and so the queries' output order, is that of a serial pass).
    constexpr size_t kChunk = 8192;
    const size_t count = indexed.size();
    chunkStarts_.clear();
    for (size_t begin = 0; begin < count;) {
        chunkStarts_.push_back(begin);
        size_t end = std::min(count, begin + kChunk);
        while (end < count && samples.cellOfIndexed_[indexed[end]] == samples.cellOfIndexed_[indexed[end - 1]]) ++end;
        begin = end;
    }
    chunkStarts_.push_back(count);
    const size_t chunks = chunkStarts_.size() - 1;
    if (runs_.size() < chunks) runs_.resize(chunks);
    auto boundChunk = [&](size_t chunk) {
        std::vector<Run>& runs = runs_[chunk];
        runs.clear();
        for (size_t i = chunkStarts_[chunk]; i < chunkStarts_[chunk + 1];) {
            Run run{samples.cellOfIndexed_[indexed[i]], 0.0f, glm::vec3(INFINITY), glm::vec3(-INFINITY), false};
            const size_t first = i;
            for (; i < chunkStarts_[chunk + 1] && samples.cellOfIndexed_[indexed[i]] == run.cell; ++i) {
                const uint32_t k = indexed[i];
                const float d = values[i];
                const glm::vec3 p = displaced_[k] = samples.cellPositions_[k] + d * samples.cellNormals_[k];
                run.lo = glm::min(run.lo, p), run.hi = glm::max(run.hi, p);
                if (!(std::abs(d) <= run.lift)) run.lift = std::abs(d);
            }
            // Entries are unique: a run as long as its cell holds all of the cell's samples.
            run.whole = i - first == samples.cellOffsets_[run.cell + 1] - samples.cellOffsets_[run.cell];
            runs.push_back(run);
        }
    };
    if (chunks > 1) tbb::parallel_for(size_t(0), chunks, boundChunk);
    else if (chunks == 1) boundChunk(0);
    for (size_t chunk = 0; chunk < chunks; ++chunk)
        for (const Run& run : runs_[chunk]) include(run.cell, run.lo, run.hi, run.lift, run.whole);
}

void SculptSamples::queryDisplaced(const glm::vec3& centre, float radius, const DisplacedCells& cells,
                                   std::vector<uint32_t>& out, std::vector<uint32_t>* indexed) const {
    if (cellKeys_.empty() || !(radius >= 0.0f)) return;
    assert(cells.current(*this) && "DisplacedCells built for other samples or an older index");
    const float r2 = radius * radius;
    // First the cells whose box meets the sphere, in visiting order, each marked whole when the
    // box lies in the sphere: each coordinate of a point in the box is no farther from the
    // centre's than the box's farther side, in float too (rounding is monotonic), so its samples
    // are taken without testing them (most cells of a big dab).
    constexpr uint32_t kWhole = 1u << 31;
    // The list is borrowed from this thread's spare one and given back on return (the crease
    // brush queries once per sample on every core; a nested query would find no spare and make
    // its own).
    thread_local std::vector<uint32_t> spare;
    struct Borrowed {
        std::vector<uint32_t> list;
        ~Borrowed() { spare = std::move(list); }
    } borrowed{std::move(spare)};
    std::vector<uint32_t>& reached = borrowed.list;
    reached.clear();
    size_t candidates = 0;
    auto consider = [&](size_t cell) {
        const glm::vec3 &lo = cells.lo_[cell], &hi = cells.hi_[cell];
        if (squaredDistanceToBox(centre, lo, hi) > r2) return;
        const glm::vec3 farthest = glm::max(glm::abs(lo - centre), glm::abs(hi - centre));
        reached.push_back(uint32_t(cell) | (glm::dot(farthest, farthest) > r2 ? 0u : kWhole));
        candidates += cellOffsets_[cell + 1] - cellOffsets_[cell];
    };
    // Near cells: a displaced position within the radius has its limit position within
    // radius + lift of the centre, and that within slack of where the index filed it.
    forEachCellNear(centre, radius + slack_ + cells.nearLift_, [&](size_t cell) {
        if (cells.farSlot_[cell] == UINT32_MAX) consider(cell);
    });
    // Far cells: each box on its own, wherever the cell is filed.
    for (size_t slot = 0; slot < cells.farCells_.size(); ++slot)
        if (squaredDistanceToBox(centre, cells.farLo_[slot], cells.farHi_[slot]) <= r2) consider(cells.farCells_[slot]);

    // Appends the samples of reached cells [first, last) to `samples` (and their places in the
    // index to `places`).
    auto collect = [&](size_t first, size_t last, std::vector<uint32_t>& samples, std::vector<uint32_t>* places) {
        for (size_t r = first; r < last; ++r) {
            const uint32_t cell = reached[r] & ~kWhole, begin = cellOffsets_[cell], end = cellOffsets_[cell + 1];
            if (reached[r] & kWhole) {
                samples.insert(samples.end(), cellSamples_.begin() + begin, cellSamples_.begin() + end);
                if (places) {
                    const size_t at = places->size();
                    places->resize(at + (end - begin));
                    std::iota(places->begin() + std::ptrdiff_t(at), places->end(), begin);
                }
                continue;
            }
            for (uint32_t k = begin; k < end; ++k) {
                const glm::vec3 d = cells.displaced_[k] - centre;
                if (glm::dot(d, d) > r2) continue;
                samples.push_back(cellSamples_[k]);
                if (places) places->push_back(k);
            }
        }
    };
    if (candidates < kParallelQuerySamples) {
        collect(0, reached.size(), out, indexed);
        return;
    }
    // A big dab: runs of consecutive cells with about kParallelQuerySamples candidates each,
    // collected on any core and joined in order, so the result is the serial one.
    std::vector<size_t> runStarts{0};
    for (size_t r = 0, inRun = 0; r < reached.size(); ++r) {
        const uint32_t cell = reached[r] & ~kWhole;
        inRun += cellOffsets_[cell + 1] - cellOffsets_[cell];
        if (inRun >= kParallelQuerySamples) runStarts.push_back(r + 1), inRun = 0;
    }
    if (runStarts.back() != reached.size()) runStarts.push_back(reached.size());
    const size_t runs = runStarts.size() - 1;
    std::vector<std::vector<uint32_t>> runSamples(runs), runPlaces(indexed ? runs : 0);
    tbb::parallel_for(size_t(0), runs, [&](size_t run) {
        runSamples[run].reserve(kParallelQuerySamples + kParallelQuerySamples / 4);
        if (indexed) runPlaces[run].reserve(kParallelQuerySamples + kParallelQuerySamples / 4);
        collect(runStarts[run], runStarts[run + 1], runSamples[run], indexed ? &runPlaces[run] : nullptr);
    });
    std::vector<size_t> at(runs + 1, out.size());
    for (size_t run = 0; run < runs; ++run) at[run + 1] = at[run] + runSamples[run].size();
    const size_t indexedBase = indexed ? indexed->size() : 0;
    out.resize(at[runs]);
    if (indexed) indexed->resize(indexedBase + (at[runs] - at[0]));
    tbb::parallel_for(size_t(0), runs, [&](size_t run) {
        std::copy(runSamples[run].begin(), runSamples[run].end(), out.begin() + std::ptrdiff_t(at[run]));
        if (indexed)
            std::copy(runPlaces[run].begin(), runPlaces[run].end(),
                      indexed->begin() + std::ptrdiff_t(indexedBase + (at[run] - at[0])));
    });
}

}  // namespace qp
