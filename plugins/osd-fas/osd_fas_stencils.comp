#version 450
// Far's stencil table applied to the cage's positions, one invocation per point (refined
// vertices of every level, then the Gregory-basis end caps' points), as OpenSubdiv's GLSL
// compute evaluator does. Summed relative to the stencil's first cage vertex: the weights sum
// to 1 only up to round-off, which against absolute coordinates would move nearby points apart.
#define QP_FAS_WRITE_POINTS
#include "osd_fas_data.glsl"

layout(local_size_x = 64) in;

vec3 cagePosition(uint vertex) {
    uint o = words[HEADER_CAGE_OFFSET] + 3u * vertex;
    return vec3(uintBitsToFloat(words[o]), uintBitsToFloat(words[o + 1u]), uintBitsToFloat(words[o + 2u]));
}

void main() {
    uint point = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (point >= words[HEADER_POINT_COUNT]) return;
    uint begin = words[words[HEADER_STENCIL_OFFSETS] + point], end = words[words[HEADER_STENCIL_OFFSETS] + point + 1u];
    vec3 p = vec3(0.0);
    if (end > begin) {
        uint indices = words[HEADER_STENCIL_INDICES], weights = words[HEADER_STENCIL_WEIGHTS];
        vec3 first = cagePosition(words[indices + begin]);
        for (uint k = begin; k < end; ++k)
            p += uintBitsToFloat(words[weights + k]) * (cagePosition(words[indices + k]) - first);
        p += first;
    }
    uint o = words[HEADER_POINT_OFFSET] + 4u * point;
    words[o] = floatBitsToUint(p.x);
    words[o + 1u] = floatBitsToUint(p.y);
    words[o + 2u] = floatBitsToUint(p.z);
    words[o + 3u] = floatBitsToUint(1.0);
}
