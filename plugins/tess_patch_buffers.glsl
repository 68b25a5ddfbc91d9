// Where a TessPatchPass's buffers are (tess_patch_pass.cpp, TessPatchAddresses): a uniform block
// of device addresses at set 0, binding 0, so that no buffer is held to the device's storage
// buffer range (a million patches of 40 points pass it). A shader declares the reference type of
// what it reads and names the array with a macro, e.g.
//   layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PatchesRef { vec4 points[]; };
//   #define points PatchesRef(tessBuffers.patchDataAddress).points
#ifndef TESS_PATCH_BUFFERS_GLSL
#define TESS_PATCH_BUFFERS_GLSL
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

layout(std140, set = 0, binding = 0) uniform TessPatchAddresses {
    uint64_t patchDataAddress, captureAddress, patchListAddress;
} tessBuffers;
#endif
