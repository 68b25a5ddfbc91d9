// SculptSamples: where every displacement sample lies on the limit surface, for brushes.
//
// Each sample has a site (sub-face, u, v): the centre of its home cell, or for a sample shared
// around an irregular corner that corner on the lowest-numbered tile around it with a surface (a
// sample whose tile has no surface — inside a hole — has no site and is never brushed). The
// brushes treat a sample's value as D at its site: a tile reproduces linear functions exactly,
// and a coefficient differs from D at its site by the curvature of the coefficients around it.
// The cache holds each site's limit position and unit normal, a uniform-grid spatial index
// over the positions for sphere queries, and the sample graph (the four neighbours of each cell
// in its padded block, which crosses edges into the neighbours) for smoothing.
//
// After moving cage vertices, refresh() re-evaluates the samples sited on the sub-faces whose
// limit changed (subfacesAffectedByVertices); the index is rebuilt only once samples have
// moved more than half a cell since its last build (queries widen by that much meanwhile).
// After a resolution change or a topology edit, build a new cache (the layout changed).
//
// Brushes act on the DISPLACED surface (s + D N): queryDisplaced finds the samples whose
// displaced positions lie in a sphere. The index stays filed by limit positions (D changes at
// every dab; refiling would cost a sort); a DisplacedCells, kept by the caller next to the D it
// describes, bounds per index cell where its displaced positions lie: the box around them and
// the largest |D| (its lift). Cells lifted by at most a cell are reached by widening the walk
// over the index by the largest such lift (zero on an unsculpted model: the walk is then the
// limit query's); cells lifted farther (a tall bump) are kept in a short list and tested box by
// box, so a tall bump elsewhere does not widen every query. "Farther" adapts to the sculpt: at
// least a cell, and high enough that at most kMaxFarCells cells are far when the bounds are
// built (a model lifted everywhere by a few cells is walked a few cells wider instead of
// scanning a list of every cell). Cells a stroke lifts past it join the list as it goes.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "displacement/displacement.h"
#include "plans/planned_cage.h"

namespace qp {

// Who evaluates each boundary point and segment: the lowest-numbered sub-face with a surface
// that has it (kNoSite when none). Positions on shared boundaries are evaluated by the owner
// only, so every face sharing them gets the same bits (as the renderer does).
struct PointOwner {
    uint32_t subface = kNoSite;
    uint32_t corner = 0;
};
struct SegmentOwner {
    uint32_t subface = kNoSite;
    uint32_t edge = 0;
    uint32_t half = 0;  // 1: the owner's edge is split and this is its second half
    // (u, v) on the owner of canonical point k of m intervals on the segment.
    glm::vec2 uv(const SampleGridLayout& layout, uint32_t k, uint32_t m) const;
};
struct BoundaryOwners {
    std::vector<PointOwner> points;      // by point id
    std::vector<SegmentOwner> segments;  // by segment
};
BoundaryOwners computeBoundaryOwners(const SampleGridLayout& layout, const PlannedCage& planned);

// Sites of every sample of `layout` (which must belong to planned's cage).
std::vector<SampleSite> computeSampleSites(const DisplacementLayout& layout, const PlannedCage& planned);

// Unit limit normal at (u, v). Where du x dv vanishes (a degenerate parameterisation, e.g. at
// some extraordinary corners), the normal a hair inside the sub-face is used.
glm::vec3 limitNormal(const PlannedCage& planned, uint32_t subface, float u, float v, const LimitSample& sample);

// Sub-faces whose limit surface depends on one of these cage vertices.
std::vector<uint32_t> subfacesAffectedByVertices(const PlannedCage& planned, std::span<const uint32_t> vertices);

class SculptSamples;

// Per index cell of a SculptSamples: bounds of its samples' displaced positions for one set of
// D values. Valid for the samples' current positions and index (current()); after D changed
// outside the holder's knowledge (undo, a load) rebuild it, after a dab grow it.
class DisplacedCells {
public:
    static constexpr size_t kMaxFarCells = 4096;

    // From every sample's value (values.size() == samples.sampleCount()): O(samples).
    void rebuild(const SculptSamples& samples, std::span<const float> values);
    // After the samples at these places in the index (queryDisplaced's `indexed`, each once)
    // took these values (values[i] is the new D of indexed[i]): their displaced positions are
    // kept and their cells' bounds grow to hold them (a bound, not the tightest one), except
    // that a cell whose every sample is in the list gets its exact box and lift (a long stroke
    // would otherwise stretch the boxes it passes along N, and big dabs would test sample by
    // sample cells they hold whole). Consecutive entries of one cell (as queries return them)
    // are merged first; big lists are spread over the cores, with the same result.
    void growIndexed(const SculptSamples& samples, std::span<const uint32_t> indexed, std::span<const float> values);
    // Built for the samples' present positions and index.
    bool current(const SculptSamples& samples) const;
    // The displaced position (position + D normal, those bits) of place k of the index:
    // queries and brushes read it in sequence instead of three scattered arrays.
    const glm::vec3& indexedDisplaced(uint32_t k) const { return displaced_[k]; }

private:
    friend class SculptSamples;
    // The cell's bounds take in lo .. hi and `lift`, or with `whole` become them.
    void include(uint32_t cell, const glm::vec3& lo, const glm::vec3& hi, float lift, bool whole);

    std::vector<glm::vec3> displaced_;  // in the index's order (SculptSamples::cellSamples_)
    std::vector<glm::vec3> lo_, hi_;    // per cell: the box around its displaced positions
    std::vector<float> lift_;         // per cell: the largest |D| of its samples
    std::vector<uint32_t> farSlot_;   // per cell: its place in farCells_, or UINT32_MAX (near)
    // Far cells and copies of their boxes, side by side: queries scan them in sequence.
    std::vector<uint32_t> farCells_;
    std::vector<glm::vec3> farLo_, farHi_;
    float farLift_ = 0.0f;   // lifts above it make a far cell
    float nearLift_ = 0.0f;  // the largest lift of the other cells
    uint64_t revision_ = 0;  // SculptSamples::revision() when built; 0: never
    // growIndexed's scratch: per chunk of the list, its cells' new bounds.
    struct Run {
        uint32_t cell;
        float lift;
        glm::vec3 lo, hi;
        bool whole;  // the run holds every sample of the cell
    };
    std::vector<std::vector<Run>> runs_;
    std::vector<size_t> chunkStarts_;
};

class SculptSamples {
public:
    static SculptSamples build(const PlannedCage& planned, const DisplacementLayout& layout);

    // Re-evaluates the samples sited on these sub-faces (positions moved, not topology).
    void refresh(const PlannedCage& planned, std::span<const uint32_t> subfaces);

    uint32_t sampleCount() const { return uint32_t(sites_.size()); }
    const SampleSite& site(uint32_t sample) const { return sites_[sample]; }
    bool hasSite(uint32_t sample) const { return sites_[sample].subface != kNoSite; }
    const glm::vec3& position(uint32_t sample) const { return positions_[sample]; }
    const glm::vec3& normal(uint32_t sample) const { return normals_[sample]; }
    std::span<const uint32_t> neighbours(uint32_t sample) const {
        return {neighbours_.data() + neighbourOffsets_[sample], neighbours_.data() + neighbourOffsets_[sample + 1]};
    }

    // Appends every sited sample whose position lies within `radius` of `centre` (unordered),
    // and with `indexed` where each is in the spatial index (indexedPosition, indexedNormal).
    void query(const glm::vec3& centre, float radius, std::vector<uint32_t>& out,
               std::vector<uint32_t>* indexed = nullptr) const;
    // Appends every sited sample whose DISPLACED position, position + D * normal(sample), lies
    // within `radius` of `centre` (unordered), with `indexed` as query's. D is the values `cells`
    // was built and grown with (it keeps the displaced positions in the index's order, read in
    // sequence): cells must be current() and rebuilt or grown with every change of D since.
    void queryDisplaced(const glm::vec3& centre, float radius, const DisplacedCells& cells, std::vector<uint32_t>& out,
                        std::vector<uint32_t>* indexed = nullptr) const;
    // Bumped whenever positions or the index change (build, refresh): DisplacedCells built
    // before are stale.
    uint64_t revision() const { return revision_; }
    // The index's copies of position(sample) and normal(sample), same bits, in the order of its
    // cells: what a query finds lies close together there, not scattered over the samples.
    const glm::vec3& indexedPosition(uint32_t k) const { return cellPositions_[k]; }
    const glm::vec3& indexedNormal(uint32_t k) const { return cellNormals_[k]; }

    // Centre of the positions' bounding box (the mirror planes pass through it).
    glm::vec3 centre() const { return 0.5f * (boundsMin_ + boundsMax_); }

private:
    friend class DisplacedCells;
    void evaluateSites(const PlannedCage& planned, std::span<const uint32_t> samples);
    void buildIndex();
    uint64_t cellKey(const glm::vec3& p) const;
    // Calls visit(cell) for every filed cell within `reach` of `centre` along each axis (nothing
    // when that box misses the indexed range).
    template <class Visit>
    void forEachCellNear(const glm::vec3& centre, float reach, const Visit& visit) const;

    std::vector<SampleSite> sites_;
    std::vector<glm::vec3> positions_, normals_;
    std::vector<uint32_t> subfaceSampleOffsets_, subfaceSamples_;  // CSR: samples sited on a sub-face
    std::vector<uint32_t> neighbourOffsets_, neighbours_;          // CSR: the sample graph

    // Spatial index: sited samples sorted by cell; cells sorted by key. Cells are filed from
    // the positions at the last build (indexMin_ .. indexMax_); slack_ bounds how far any
    // sample moved since.
    glm::vec3 boundsMin_{0.0f}, boundsMax_{0.0f};
    glm::vec3 indexMin_{0.0f}, indexMax_{0.0f};
    float cellSize_ = 1.0f, slack_ = 0.0f;
    std::vector<uint64_t> cellKeys_;
    std::vector<uint32_t> cellOffsets_, cellSamples_;
    // The positions and normals of cellSamples_ in their order, and where each sited sample
    // is in it.
    std::vector<glm::vec3> cellPositions_, cellNormals_;
    std::vector<uint32_t> cellIndexOfSample_;
    std::vector<uint32_t> cellOfIndexed_;  // per entry of cellSamples_: its cell
    uint64_t revision_ = 0;
    // Kept between index builds: fresh allocations of this size cost page faults every time.
    std::vector<uint32_t> scratchSited_;
    std::vector<std::pair<uint64_t, uint32_t>> scratchKeyed_;
};

}  // namespace qp
