#version 450
// ACC-2: evaluates one bicubic Gregory patch (Loop, Schaefer, Ni, Castano 2009) at the
// tessellation coordinate, as evaluateAcc2Patch does on the CPU (acc2.h, core/plans/patch_basis.h):
// each interior Bezier point is the rational blend of its corner's two face points,
// (s Fp + t Fm) / (s + t) with s, t the distances to the corner's two edges (1/2 each at the
// corner itself, where the blend is 0/0), then the patch is a bicubic Bezier patch, and du, dv
// are that patch's derivatives with the blend held fixed (Acc2Settings::surfaceDerivatives =
// false, OpenSubdiv's convention).
#define TESS_EVALUATION
#include "tess_patch.glsl"

layout(quads, equal_spacing, ccw) in;
layout(location = 0) patch in uint patchIndex;

#include "tess_patch_buffers.glsl"
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PatchesRef { vec4 data[]; };
#define points PatchesRef(tessBuffers.patchDataAddress).data

void main() {
    float u = gl_TessCoord.x, v = gl_TessCoord.y;
    uint base = 20u * patchIndex;
    // Corner k owns P, Ep, Em, Fp, Fm at 5k .. 5k+4 (OpenSubdiv's GREGORY_BASIS order).
    vec3 P[4], Ep[4], Em[4], F[4];
    float s[4] = float[4](u, v, 1.0 - u, 1.0 - v);
    float t[4] = float[4](v, 1.0 - u, 1.0 - v, u);
    for (int k = 0; k < 4; ++k) {
        uint c = base + 5u * uint(k);
        P[k] = points[c].xyz;
        Ep[k] = points[c + 1u].xyz;
        Em[k] = points[c + 2u].xyz;
        float st = s[k] + t[k];
        float g = st > 0.0 ? s[k] / st : 0.5;
        F[k] = g * points[c + 3u].xyz + (1.0 - g) * points[c + 4u].xyz;
    }
    // The bicubic Bezier net q[j][i] (i along u, j along v).
    vec3 q[4][4];
    q[0][0] = P[0]; q[0][1] = Ep[0]; q[0][2] = Em[1]; q[0][3] = P[1];
    q[1][0] = Em[0]; q[1][1] = F[0]; q[1][2] = F[1]; q[1][3] = Ep[1];
    q[2][0] = Ep[3]; q[2][1] = F[3]; q[2][2] = F[2]; q[2][3] = Em[2];
    q[3][0] = P[3]; q[3][1] = Em[3]; q[3][2] = Ep[2]; q[3][3] = P[2];
    vec4 bu, du, bv, dv;
    bernstein3(u, bu, du);
    bernstein3(v, bv, dv);
    vec3 position = vec3(0.0), dpu = vec3(0.0), dpv = vec3(0.0);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            position += bu[i] * bv[j] * q[j][i];
            dpu += du[i] * bv[j] * q[j][i];
            dpv += bu[i] * dv[j] * q[j][i];
        }
    emitVertex(patchIndex, vec3(u, v, 0.0), position, unitNormal(dpu, dpv));
}
