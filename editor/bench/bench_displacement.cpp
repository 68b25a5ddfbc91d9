#include "bench_displacement.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <numeric>
#include <random>

#include "bench_report.h"
#include "bench_stats.h"
#include "displacement/displaced_mesh.h"
#include "displacement/sculpt_samples.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"

namespace qp::cli {

DisplacementBenchResult measureDisplacementDabs(const VulkanContext& ctx, const Cage& cage, uint32_t resolution,
                                                uint32_t repeats, uint32_t seed) {
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

    // The plans renderer's buffers with the displacement, its grid at the factor the tiles need.
    Result<PlanPass> pass = createPlanPass(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM);
    if (!pass) {
        result.error = pass.error().message;
        return result;
    }
    Result<PlanBuffers> uploaded = uploadPlans(ctx, *planned);
    if (!uploaded) {
        result.error = uploaded.error().message;
        destroyPlanPass(ctx, *pass);
        return result;
    }
    PlanBuffers& buffers = *uploaded;
    result.gridFactor = std::min(requiredMeshFactor(*planned, displacement.layout), 64u);
    Status ready = bindPlanBuffers(ctx, *pass, buffers);
    if (ready) ready = setPlanDisplacement(ctx, *pass, buffers, &displacement);
    if (ready) ready = prepareGrid(ctx, *pass, buffers, result.gridFactor);
    if (!ready) {
        result.error = ready.error().message;
        destroyPlanBuffers(ctx, buffers);
        destroyPlanPass(ctx, *pass);
        return result;
    }
    result.gridSubfaces = uint32_t(buffers.data.subfaces.size());
    std::vector<uint32_t> everything(displacement.layout.sampleCount);
    std::iota(everything.begin(), everything.end(), 0u);
    std::vector<double> full;
    for (uint32_t r = 0; r < std::max(repeats / 20, 3u); ++r) {
        auto fullStart = Clock::now();
        buffers.gridEvaluator = GridEvaluator::None;
        recordDisplacementChange(VK_NULL_HANDLE, *pass, buffers, *planned, everything);
        evaluateGridOnCpu(*planned, buffers);
        full.push_back(msSince(fullStart));
    }
    result.fullUploadMs = median(full);

    // A brush a few faces wide (4% of the bounding-box diagonal) with every brush, and big ones
    // (12% and 20%, about 9 and 25 times the samples): raising, and the two brushes whose
    // new values read more than the sample itself.
    const float diagonal = computeBounds(cage).diagonal();
    const std::pair<BrushKind, float> brushes[] = {
        {BrushKind::Raise, 0.04f}, {BrushKind::Smooth, 0.04f}, {BrushKind::Flatten, 0.04f},
        {BrushKind::Erase, 0.04f}, {BrushKind::Raise, 0.12f},  {BrushKind::Raise, 0.20f},
        {BrushKind::Smooth, 0.20f}, {BrushKind::Flatten, 0.20f}};
    std::vector<uint32_t> sited;
    for (uint32_t i = 0; i < samples.sampleCount(); ++i)
        if (samples.hasSite(i)) sited.push_back(i);
    std::mt19937 rng(seed);

    Sculptor sculptor(displacement, samples);
    for (auto [kind, fraction] : brushes) {
        const Brush brush{kind, fraction * diagonal, kind == BrushKind::Raise ? 0.05f : 0.5f, Falloff::Smooth};
        std::vector<double> update, upload, total, bytes, reached, subfaces, slots;
        sculptor.beginStroke();
        for (uint32_t r = 0; r < repeats; ++r) {
            const glm::vec3 centre = samples.position(sited[rng() % sited.size()]);
            auto dabStart = Clock::now();
            sculptor.dab(brush, MirrorAxis::None, centre);
            const double updateMs = msSince(dabStart);

            // The CPU grid path records no device work: the command buffer is not used.
            auto uploadStart = Clock::now();
            const DisplacementUpdate gpu =
                recordDisplacementChange(VK_NULL_HANDLE, *pass, buffers, *planned, sculptor.lastDabSamples());
            const double uploadMs = msSince(uploadStart);
            update.push_back(updateMs);
            upload.push_back(uploadMs);
            total.push_back(updateMs + uploadMs);
            bytes.push_back(double(gpu.uploadedSamples) * sizeof(float));
            reached.push_back(double(sculptor.lastDabSamples().size()));
            subfaces.push_back(double(gpu.evaluatedSubfaces));
            slots.push_back(double(gpu.displacedSlots));
        }
        sculptor.endStroke();
        if (std::memcmp(buffers.displacementSamples.data, displacement.samples.data(), displacement.samples.size() * sizeof(float)))
            result.error = "the Vulkan sample buffer differs from the samples (upload ranges miss a change)";
        result.dabs.push_back({kind, brush.radius, repeats, median(update), median(upload), median(total),
                               median(bytes), median(subfaces), median(slots), median(reached)});
    }
    destroyPlanBuffers(ctx, buffers);
    destroyPlanPass(ctx, *pass);
    return result;
}

// ---- the suite: one row per brush and radius -------------------------------------------

constexpr uint32_t kDisplacementResolution = 16;  // per sub-face
constexpr uint32_t kDabsPerRepeat = 20;           // dabs are cheap: many per repeat

void benchDisplacement(const BenchCage& bench, const BenchArgs& args, Report& report) {
    std::fprintf(stderr, "bench displacement: %s (%u faces)\n", bench.name.c_str(), bench.cage.faceCount());
    Result<VulkanContext> context = createBenchContext();
    if (!context) {
        report.notes.push_back(bench.name + ": no Vulkan context: " + context.error().message);
        return;
    }
    const uint32_t dabs = args.repeats * kDabsPerRepeat;
    DisplacementBenchResult result = measureDisplacementDabs(*context, bench.cage, kDisplacementResolution, dabs, args.seed);
    const std::string device = context->deviceName;
    destroyContext(*context);
    if (!result.error.empty()) report.notes.push_back(bench.name + ": " + result.error);
    if (result.dabs.empty()) return;
    report.notes.push_back(bench.name + ": resolution " + std::to_string(result.resolution) + " on every sub-face, " +
                           std::to_string(result.samples) + " samples (" + number(result.samples * 4.0 / 1048576.0) +
                           " MiB); smooth falloff, dabs at random sample positions; the samples cache is built once per "
                           "layout; GPU buffers: the plans renderer's sample buffer and its CPU-path grid at factor " +
                           std::to_string(result.gridFactor) + " (" + std::to_string(result.gridSubfaces) +
                           " sub-faces), both mapped Vulkan buffers on " + device);
    for (const DabMeasurement& m : result.dabs) {
        Row r;
        r.cage = bench.name;
        r.faces = bench.cage.faceCount();
        r.benchmark = std::string(brushKindName(m.brush)) + " dab, radius " + number(m.radius) + ": CPU update " +
                      number(m.updateMs) + " ms + GPU buffers " + number(m.uploadMs) + " ms (" + number(m.bytes / 1024.0) +
                      " KiB of samples, " + number(m.gridSlots) + " grid slots of " + number(m.gridSubfaces) +
                      " sub-faces; " + number(m.samplesReached) +
                      " samples in reach) vs uploading every sample and re-evaluating the whole grid; 2nd: building "
                      "the samples cache";
        r.repeats = m.repeats;
        r.unit = "ms";
        r.ours = m.totalMs;
        r.baseline = result.fullUploadMs;
        r.baseline2 = result.cacheBuildMs;
        r.target = Target::OursAtMost;
        r.targetValue = 5.0;
        report.rows.push_back(r);
    }
}

}  // namespace qp::cli
