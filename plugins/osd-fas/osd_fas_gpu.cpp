#include "osd_fas_gpu.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace qp {

using namespace OpenSubdiv;

namespace {

uint32_t append(std::vector<uint32_t>& words, size_t count) {
    const uint32_t offset = uint32_t(words.size());
    words.resize(words.size() + count, 0u);
    return offset;
}

uint32_t alignTo4(std::vector<uint32_t>& words) {
    words.resize((words.size() + 3) & ~size_t(3), 0u);
    return uint32_t(words.size());
}

float uniformLevel(uint32_t factor, uint32_t depth) {
    return std::max(1.0f, std::ceil(float(factor) / float(1u << depth)));
}

}  // namespace

FasGpuData packFasPatches(const FasPatches& patches, uint32_t cageVertices) {
    FasGpuData data;
    FasGpuHeader& h = data.header;
    std::vector<uint32_t>& words = data.words;
    append(words, (sizeof(FasGpuHeader) + 15) / 16 * 4);  // the header, rounded to whole vec4s

    h.patchCount = uint32_t(patches.layout.size());
    h.patchOffset = append(words, patches.layout.size() * (sizeof(FasGpuPatch) / 4));
    for (size_t i = 0; i < patches.layout.size(); ++i) {
        const FasPatchLayout& p = patches.layout[i];
        const Far::PatchDescriptor::Type type = patches.table->GetPatchArrayDescriptor(p.handle.arrayIndex).GetType();
        const Far::PatchParam param = patches.table->GetPatchParam(p.handle);
        FasGpuPatch gpu{};
        gpu.sharpness = patches.table->GetSingleCreasePatchSharpnessValue(p.handle);
        gpu.kind = type == Far::PatchDescriptor::GREGORY_BASIS ? FasPatchKind::GregoryBasis
                   : gpu.sharpness > 0.0f                      ? FasPatchKind::SingleCrease
                                                               : FasPatchKind::BSpline;
        gpu.param0 = param.field0;
        gpu.param1 = param.field1;
        const Far::ConstIndexArray cvs = patches.table->GetPatchVertices(p.handle);
        for (int k = 0; k < cvs.size() && k < 20; ++k) gpu.controlVertices[k] = uint32_t(cvs[k]);
        std::memcpy(gpu.edgePoints, p.edgePoints, sizeof(gpu.edgePoints));
        std::memcpy(&words[h.patchOffset + i * (sizeof(FasGpuPatch) / 4)], &gpu, sizeof(gpu));
    }

    const Far::StencilTableReal<double>& stencils = *patches.stencils;
    h.pointCount = uint32_t(stencils.GetNumStencils());
    h.pointOffset = alignTo4(words);
    append(words, size_t(h.pointCount) * 4);
    h.cageOffset = append(words, size_t(cageVertices) * 3);
    h.stencilOffsets = append(words, size_t(h.pointCount) + 1);
    for (uint32_t i = 0; i < h.pointCount; ++i) words[h.stencilOffsets + i] = uint32_t(stencils.GetOffsets()[i]);
    const std::vector<Far::Index>& indices = stencils.GetControlIndices();
    words[h.stencilOffsets + h.pointCount] = uint32_t(indices.size());
    h.stencilIndices = append(words, indices.size());
    std::copy(indices.begin(), indices.end(), words.begin() + h.stencilIndices);
    const std::vector<double>& weights = stencils.GetWeights();
    h.stencilWeights = append(words, weights.size());
    for (size_t i = 0; i < weights.size(); ++i) {  // the device applies them in float
        const float weight = float(weights[i]);
        std::memcpy(&words[h.stencilWeights + i], &weight, sizeof(float));
    }
    std::memcpy(words.data(), &h, sizeof(h));
    return data;
}

std::vector<float> fasCagePositions(std::span<const glm::vec3> positions) {
    std::vector<float> packed;
    packed.reserve(positions.size() * 3);
    for (const glm::vec3& p : positions) packed.insert(packed.end(), {p.x, p.y, p.z});
    return packed;
}

void fasUniformLevels(const Far::PatchParam& param, uint32_t factor, float outer[4]) {
    const uint32_t depth = param.GetDepth(), transitions = param.GetTransition();
    for (uint32_t e = 0; e < 4; ++e) {
        // Far's edge e (0: v=0, 1: u=1, 2: v=1, 3: u=0) is Vulkan's outer level (e + 1) % 4.
        const bool split = transitions & (1u << e);
        outer[(e + 1) % 4] = split ? 2.0f * uniformLevel(factor, depth + 1) : uniformLevel(factor, depth);
    }
}

uint64_t quadTessTriangles(const float outer[4]) {
    // Equal spacing on the quad domain (Vulkan spec, "Quad Tessellation"): inner levels are the
    // mean of the opposite outer levels (as osd_fas.tesc sets them) rounded up; a quad whose
    // levels are all 1 is two triangles, otherwise an inner level of 1 acts as 2. The inner
    // rectangle has (a-2) x (b-2) quads, and the ring around it joins each outer edge of o
    // segments to the inner side of (a-2) or (b-2): o + inner triangles.
    uint64_t o[4];
    for (int i = 0; i < 4; ++i) o[i] = uint64_t(std::ceil(outer[i]));
    const uint64_t innerU = uint64_t(std::ceil(0.5f * float(o[1] + o[3])));
    const uint64_t innerV = uint64_t(std::ceil(0.5f * float(o[0] + o[2])));
    if (innerU == 1 && innerV == 1 && o[0] == 1 && o[1] == 1 && o[2] == 1 && o[3] == 1) return 2;
    const uint64_t a = std::max<uint64_t>(innerU, 2) - 2, b = std::max<uint64_t>(innerV, 2) - 2;
    return 2 * a * b + (o[1] + a) + (o[3] + a) + (o[0] + b) + (o[2] + b);
}

uint64_t fasUniformTriangles(const FasPatches& patches, uint32_t factor) {
    uint64_t triangles = 0;
    for (const FasPatchLayout& p : patches.layout) {
        float outer[4];
        fasUniformLevels(patches.table->GetPatchParam(p.handle), factor, outer);
        triangles += quadTessTriangles(outer);
    }
    return triangles;
}

}  // namespace qp
