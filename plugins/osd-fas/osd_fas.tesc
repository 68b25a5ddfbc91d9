#version 450
// osd-fas: the tessellation levels of one Far patch, OpenSubdiv's rule (osd_fas_gpu.h). Edge e
// below is Far's (0: v=0, 1: u=1, 2: v=1, 3: u=0), Vulkan's outer level (e + 1) % 4.
#include "tess_patch.glsl"
#include "osd_fas_data.glsl"

layout(vertices = 1) out;
layout(location = 0) flat in uint inPatch[];
layout(location = 0) patch out uint patchIndex;
// Per Far edge: the segments of its first half when it is a transition edge, else 0.
layout(location = 1) patch out vec4 firstHalf;

float uniformLevel(uint depth) { return max(1.0, ceil(pc.uniformFactor / float(1u << depth))); }

// The plans' edge-sphere rule, at most 32: a transition edge is two such halves.
float adaptiveLevel(vec3 a, vec3 b) {
    vec3 centre = 0.5 * (a + b);
    float radius = 0.5 * length(b - a);
    float w = max((pc.viewProj * vec4(centre, 1.0)).w, 1e-4);
    return clamp(ceil(2.0 * radius * pc.pixelsPerUnit / w / pc.pixelsPerSegment), 1.0, 32.0);
}

void main() {
    uint p = inPatch[0];
    patchIndex = p;
    uint depth = patchDepth(p), transitions = patchTransitions(p);
    float outer[4];
    for (uint e = 0u; e < 4u; ++e) {
        bool split = ((transitions >> e) & 1u) != 0u;
        float first, second = 0.0;
        if (pc.uniformFactor > 0.0) {
            first = uniformLevel(split ? depth + 1u : depth);
            if (split) second = first;
        } else {
            uint edge = PATCH_EDGE_POINTS + 3u * e;
            vec3 a = fasPoint(patchWord(p, edge)), b = fasPoint(patchWord(p, edge + 2u));
            if (split) {
                vec3 m = fasPoint(patchWord(p, edge + 1u));
                first = adaptiveLevel(a, m);
                second = adaptiveLevel(m, b);
            } else {
                first = adaptiveLevel(a, b);
            }
        }
        firstHalf[e] = split ? first : 0.0;
        outer[(e + 1u) % 4u] = first + second;
    }
    for (uint i = 0u; i < 4u; ++i) gl_TessLevelOuter[i] = outer[i];
    // OpenSubdiv's inner levels: the means of the opposite outer levels.
    gl_TessLevelInner[0] = 0.5 * (outer[1] + outer[3]);
    gl_TessLevelInner[1] = 0.5 * (outer[0] + outer[2]);
}
