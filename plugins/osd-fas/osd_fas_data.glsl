// The buffer of osd-fas's tessellator path (osd_fas_gpu.h: FasGpuHeader, FasGpuPatch): one
// storage buffer of 32-bit words, the pass's patch data (tess_patch_buffers.glsl). The compute pass writes the points; the
// tessellation stages only read.
#include "tess_patch_buffers.glsl"
#ifdef QP_FAS_WRITE_POINTS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict buffer FasDataRef { uint words[]; };
#else
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer FasDataRef { uint words[]; };
#endif
#define words FasDataRef(tessBuffers.patchDataAddress).words

const uint HEADER_PATCH_COUNT = 0u;
const uint HEADER_PATCH_OFFSET = 1u;
const uint HEADER_POINT_COUNT = 2u;
const uint HEADER_POINT_OFFSET = 3u;
const uint HEADER_CAGE_OFFSET = 4u;
const uint HEADER_STENCIL_OFFSETS = 5u;
const uint HEADER_STENCIL_INDICES = 6u;
const uint HEADER_STENCIL_WEIGHTS = 7u;

const uint PATCH_WORDS = 36u;
const uint PATCH_KIND = 0u, PATCH_PARAM0 = 1u, PATCH_PARAM1 = 2u, PATCH_SHARPNESS = 3u;
const uint PATCH_CONTROL_VERTICES = 4u, PATCH_EDGE_POINTS = 24u;
const uint KIND_BSPLINE = 0u, KIND_SINGLE_CREASE = 1u, KIND_GREGORY_BASIS = 2u;
const uint NO_EDGE_MIDPOINT = 0xffffffffu;

uint patchWord(uint patchIndex, uint word) { return words[words[HEADER_PATCH_OFFSET] + PATCH_WORDS * patchIndex + word]; }

// Far::PatchParam: depth in bits 0-3 of the second word, the boundary mask in 7-11 (its crease
// edge on a single-crease patch), the transition mask in bits 28-31 of the first.
uint patchDepth(uint patchIndex) { return patchWord(patchIndex, PATCH_PARAM1) & 15u; }
uint patchBoundary(uint patchIndex) { return (patchWord(patchIndex, PATCH_PARAM1) >> 7) & 15u; }
uint patchTransitions(uint patchIndex) { return (patchWord(patchIndex, PATCH_PARAM0) >> 28) & 15u; }

vec3 fasPoint(uint point) {
    uint o = words[HEADER_POINT_OFFSET] + 4u * point;
    return vec3(uintBitsToFloat(words[o]), uintBitsToFloat(words[o + 1u]), uintBitsToFloat(words[o + 2u]));
}

vec3 patchControlVertex(uint patchIndex, uint k) { return fasPoint(patchWord(patchIndex, PATCH_CONTROL_VERTICES + k)); }
