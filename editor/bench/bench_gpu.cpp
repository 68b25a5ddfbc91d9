// The GPU suites' harness: the benchmark device (bench_report.h) and the frames the render and
// schemes suites share (bench_frames.h).
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "bench_frames.h"
#include "bench_report.h"

namespace qp::cli {

// Lavapipe unless QUADPLAN_VK_DEVICE names a device (as the render tests). Validation stays
// off: it would dominate the timings.
Result<VulkanContext> createBenchContext() {
    ContextOptions options;
    if (const char* device = std::getenv("QUADPLAN_VK_DEVICE"); device && device[0]) {
        options.forceDevice = device;
    } else if (const char* icd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"; std::filesystem::exists(icd)) {
        setenv("VK_ICD_FILENAMES", icd, 1);  // before the loader looks for drivers
        setenv("VK_DRIVER_FILES", icd, 1);
    }
    return createContext(options);
}

Result<BenchDevice> createBenchDevice(uint32_t width, uint32_t height) {
    Result<VulkanContext> context = createBenchContext();
    if (!context) return context.error();
    BenchDevice device{std::move(context).value(), {}};
    Result<OffscreenTarget> target = createOffscreenTarget(device.ctx, width, height, VK_FORMAT_R8G8B8A8_UNORM);
    if (!target) {
        destroyContext(device.ctx);
        return target.error();
    }
    device.target = *target;
    return device;
}

void destroyBenchDevice(BenchDevice& device) {
    destroyOffscreenTarget(device.ctx, device.target);
    destroyContext(device.ctx);
}

std::string loadAverage() {
    std::string one, five, fifteen;
    std::ifstream("/proc/loadavg") >> one >> five >> fifteen;
    return one + " " + five + " " + fifteen;
}


double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

std::string cell(const FrameKind& k, bool withRatio) {
    if (k.ms.empty()) return "";
    return number(k.medianMs()) + (withRatio ? " (" + number(k.medianRatio()) + "x)" : "");
}

std::string cellWithCpu(const FrameKind& k) {
    if (k.ms.empty()) return "";
    return number(k.medianMs()) + " (" + number(k.medianRatio()) + "x; CPU " + number(k.medianCpuRatio()) + "x)";
}

Status preparePreTessellated(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, const PlannedCage& planned,
                             uint32_t factor, GpuMesh& mesh) {
    if (Status s = prepareGrid(ctx, pass, buffers, factor); !s) return s;
    evaluateGridOnCpu(planned, buffers);
    const GridLayout& layout = buffers.gridLayout;
    destroyMesh(ctx, mesh);
    Result<GpuMesh> uploaded =
        uploadMesh(ctx, {static_cast<const MeshVertex*>(buffers.grid.data), layout.slotCount()}, layout.indices);
    if (!uploaded) return uploaded.error();
    mesh = std::move(uploaded).value();
    return success();
}

Result<FrameBench> createFrameBench(const Cage& cage, const std::string& name, std::vector<std::string>& notes) {
    FrameBench bench;
    bench.database = std::make_unique<PlanDatabase>();
    Result<PlannedCage> created = PlannedCage::create(cage, *bench.database, PlanOptions{}, name);
    if (!created) return created.error();
    bench.planned = std::make_unique<PlannedCage>(std::move(created).value());
    Result<VulkanContext> context = createBenchContext();
    if (!context) return context.error();
    bench.ctx = std::move(context).value();
    notes.push_back(name + ": load average at the start (1, 5, 15 min): " + loadAverage());
    auto take = [&](auto result, auto& out) {
        if (result) out = std::move(result).value();
        else if (bench.error.empty()) bench.error = result.error().message;
        return bool(result);
    };
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    take(createOffscreenTarget(bench.ctx, kRenderSize, kRenderSize, format), bench.target) &&
        take(createPlanPass(bench.ctx, VK_NULL_HANDLE, format), bench.pass) &&
        take(uploadPlans(bench.ctx, *bench.planned), bench.buffers);
    if (bench.error.empty())
        if (Status bound = bindPlanBuffers(bench.ctx, bench.pass, bench.buffers); !bound) bench.error = bound.error().message;
    return bench;
}

void destroyFrameBench(FrameBench& bench) {
    vkDeviceWaitIdle(bench.ctx.device);
    destroyMesh(bench.ctx, bench.preMesh);
    destroyPlanBuffers(bench.ctx, bench.buffers);
    destroyPlanPass(bench.ctx, bench.pass);
    destroyOffscreenTarget(bench.ctx, bench.target);
    destroyContext(bench.ctx);
}

Result<uint32_t> coveredPixels(const VulkanContext& ctx, const OffscreenTarget& target) {
    Result<std::vector<uint8_t>> pixels = readPixels(ctx, target);
    if (!pixels) return pixels.error();
    const uint32_t* rgba = reinterpret_cast<const uint32_t*>(pixels->data());
    uint32_t covered = 0;
    for (size_t p = 0; p < pixels->size() / 4; ++p) covered += rgba[p] != rgba[0];
    return covered;
}

}  // namespace qp::cli
