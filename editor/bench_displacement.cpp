#include "bench_displacement.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <random>

#include "planned_cage.h"
#include "sculpt_samples.h"

namespace qp::cli {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

double medianOf(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    size_t n = values.size();
    return n == 0 ? 0.0 : n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

DisplacementBenchResult measureDisplacementDabs(const Cage& cage, uint32_t resolution, uint32_t repeats, uint32_t seed) {
    DisplacementBenchResult result;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(cage, database, PlanOptions{}, "bench");
    if (!planned) {
        result.error = planned.error().message;
        return result;
    }
    Displacement displacement = makeDisplacement(cage, planned->topology(), resolution);
    result.resolution = resolution;
    result.samples = displacement.layout.sampleCount;

    auto start = Clock::now();
    SculptSamples samples = SculptSamples::build(*planned, displacement.layout);
    result.cacheBuildMs = msSince(start);

    // The GPU copy of the samples; a mapped host-visible buffer takes the same memcpy.
    std::vector<float> mapped(displacement.samples.size(), 0.0f);
    std::vector<double> full;
    for (uint32_t r = 0; r < std::max(repeats, 3u); ++r) {
        auto copyStart = Clock::now();
        std::memcpy(mapped.data(), displacement.samples.data(), mapped.size() * sizeof(float));
        full.push_back(msSince(copyStart));
    }
    result.fullUploadMs = medianOf(full);

    // A brush a few faces wide (4% of the bounding-box diagonal) with every brush, and a big
    // one (12%, about 9 times the samples) raising.
    const float diagonal = computeBounds(cage).diagonal();
    const std::pair<BrushKind, float> brushes[] = {{BrushKind::Raise, 0.04f},   {BrushKind::Smooth, 0.04f},
                                                   {BrushKind::Flatten, 0.04f}, {BrushKind::Erase, 0.04f},
                                                   {BrushKind::Raise, 0.12f}};
    std::vector<uint32_t> sited;
    for (uint32_t i = 0; i < samples.sampleCount(); ++i)
        if (samples.hasSite(i)) sited.push_back(i);
    std::mt19937 rng(seed);

    Sculptor sculptor(displacement, samples);
    for (auto [kind, fraction] : brushes) {
        const Brush brush{kind, fraction * diagonal, kind == BrushKind::Raise ? 0.05f : 0.5f, Falloff::Smooth};
        std::vector<double> update, upload, total, bytes, reached;
        sculptor.beginStroke();
        for (uint32_t r = 0; r < repeats; ++r) {
            const glm::vec3 centre = samples.position(sited[rng() % sited.size()]);
            auto dabStart = Clock::now();
            sculptor.dab(brush, MirrorAxis::None, centre);
            const double updateMs = msSince(dabStart);

            auto uploadStart = Clock::now();
            std::vector<SampleRange> ranges = uploadRanges(sculptor.lastDabSamples());
            size_t copied = 0;
            for (const SampleRange& range : ranges) {
                std::memcpy(mapped.data() + range.first, displacement.samples.data() + range.first, range.count * sizeof(float));
                copied += range.count * sizeof(float);
            }
            const double uploadMs = msSince(uploadStart);
            update.push_back(updateMs);
            upload.push_back(uploadMs);
            total.push_back(updateMs + uploadMs);
            bytes.push_back(double(copied));
            reached.push_back(double(sculptor.lastDabSamples().size()));
        }
        sculptor.endStroke();
        if (mapped != displacement.samples) result.error = "the uploaded copy differs from the samples (upload ranges miss a change)";
        result.dabs.push_back({kind, brush.radius, repeats, medianOf(update), medianOf(upload), medianOf(total), medianOf(bytes), medianOf(reached)});
    }
    return result;
}

}  // namespace qp::cli
