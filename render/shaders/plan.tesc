#version 450
// Tessellation factors of one sub-face. Shared edges get identical factors from both sides:
// they are computed from the same boundary points in canonical order. A cage edge next to a
// non-quad is split: the quad side uses 2k segments, each n-gon sub-face half k.
#include "plan_eval.glsl"
#include "plan_boundary.glsl"
#include "plan_draw.glsl"

layout(vertices = 1) out;
layout(location = 0) flat in uint inDrawn[];
layout(location = 0) patch out uint drawn;
layout(location = 1) patch out uvec4 edgeFactor;  // sub-face edges 0..3

uint edgeSegments(uint d, uint e, bool ngon) {
    EdgeRef r = boundaries[d].edges[e];
    uint start = boundaries[d].corners[e == 1u ? 1u : (e == 2u ? 3u : 0u)];
    uint end = boundaries[d].corners[e == 0u ? 1u : (e == 3u ? 3u : 2u)];
    if ((r.flags & 6u) != 0u) {  // split (quad side) or half (n-gon side) of a cage edge
        vec4 m = pointPositions[r.midpoint];
        uint k = uint(ceil(sphereFactor(m.xyz, m.w) * 0.5));
        return (r.flags & 2u) != 0u ? 2u * k : k;
    }
    vec3 a = pointPositions[min(start, end)].xyz, b = pointPositions[max(start, end)].xyz;
    float f = sphereFactor(0.5 * (a + b), 0.5 * length(b - a));
    return uint(ceil(ngon ? 0.5 * f : f));
}

void main() {
    uint d = inDrawn[0];
    bool ngon = (boundaries[d].edges[0].flags & 4u) != 0u;
    uvec4 f = uvec4(edgeSegments(d, 0u, ngon), edgeSegments(d, 1u, ngon), edgeSegments(d, 2u, ngon),
                    edgeSegments(d, 3u, ngon));
    drawn = d;
    edgeFactor = f;
    // Vulkan quad domain: outer[0] is u=0 (edge 3), [1] v=0 (edge 0), [2] u=1 (edge 1), [3] v=1 (edge 2).
    gl_TessLevelOuter[0] = float(f.w);
    gl_TessLevelOuter[1] = float(f.x);
    gl_TessLevelOuter[2] = float(f.y);
    gl_TessLevelOuter[3] = float(f.z);
    float inner = float(max(max(f.x, f.y), max(f.z, f.w)));
    gl_TessLevelInner[0] = inner;
    gl_TessLevelInner[1] = inner;
}
