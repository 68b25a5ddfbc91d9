// Shared by the tessellation stages of the scheme plugins (tess_patch_pass.h): push constants,
// edge factors, the evaluation stage's outputs and the capture buffer.
#extension GL_GOOGLE_include_directive : require

// The first four members are render/shaders/mesh_push.glsl's MeshPush, which mesh.frag reads.
layout(push_constant) uniform TessPush {
    mat4 viewProj;
    vec4 eye;                // xyz: camera position
    vec4 color;              // rgb: base colour (linear)
    vec4 params;             // x: depth pull toward the eye (wireframe), y: 0 lit / 1 flat, z: 1 matcap
    float uniformFactor;     // > 0: every edge gets this many segments; 0: screen-adaptive
    float pixelsPerSegment;  // adaptive: target screen length of one segment
    float pixelsPerUnit;     // viewport height / 2 * |P[1][1]|
    uint capture;            // 1: the evaluation stage records its vertices
} pc;

// Segments for the edge from a to b: uniform, or by the screen size of the sphere around it
// (rotation-invariant, and the same from both patches of an edge, which pass the same two
// corner points: no cracks between patches).
float edgeFactor(vec3 a, vec3 b) {
    if (pc.uniformFactor > 0.0) return pc.uniformFactor;
    vec3 centre = 0.5 * (a + b);
    float radius = 0.5 * length(b - a);
    float w = max((pc.viewProj * vec4(centre, 1.0)).w, 1e-4);
    return clamp(ceil(2.0 * radius * pc.pixelsPerUnit / w / pc.pixelsPerSegment), 1.0, 64.0);
}

#ifdef TESS_EVALUATION
layout(location = 0) out vec3 outNormal;
layout(location = 1) out vec3 outWorld;
layout(location = 2) out vec3 outColor;

struct CaptureRecord {
    uint patchIndex;
    float u, v, w;
    float px, py, pz;
    float nx, ny, nz;
};
#include "tess_patch_buffers.glsl"
layout(buffer_reference, std430, buffer_reference_align = 16) restrict buffer CaptureRef {
    uint captureCount;
    uint captureCapacity;
    uint captureUnused0, captureUnused1;
    CaptureRecord records[];
};
#define captureBuffer CaptureRef(tessBuffers.captureAddress)

// Writes the vertex (what mesh.vert would for a mesh vertex) and, when capturing, records it.
void emitVertex(uint patchIndex, vec3 coord, vec3 position, vec3 normal) {
    gl_Position = pc.viewProj * vec4(position, 1.0);
    gl_Position.z -= pc.params.x * gl_Position.w;
    outNormal = normal;
    outWorld = position;
    outColor = pc.color.rgb;
    if (pc.capture != 0u) {
        uint slot = atomicAdd(captureBuffer.captureCount, 1u);
        if (slot < captureBuffer.captureCapacity)
            captureBuffer.records[slot] = CaptureRecord(patchIndex, coord.x, coord.y, coord.z, position.x, position.y, position.z,
                                          normal.x, normal.y, normal.z);
    }
}

vec3 unitNormal(vec3 du, vec3 dv) {
    vec3 n = cross(du, dv);
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0);
}

// Cubic Bernstein basis and its derivative.
void bernstein3(float t, out vec4 b, out vec4 d) {
    float s = 1.0 - t;
    b = vec4(s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t);
    d = vec4(-3.0 * s * s, 3.0 * s * s - 6.0 * t * s, 6.0 * t * s - 3.0 * t * t, 3.0 * t * t);
}
#endif
