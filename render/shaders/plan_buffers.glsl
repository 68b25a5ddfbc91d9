// Where the plan pass's buffers are when they are reached by address (QP_BY_ADDRESS: the pass
// switches to these shader variants when a buffer is larger than the device's storage buffer
// range, as a million-face cage's control points and grid are; render/plan_pass.h). Then one
// uniform block at set 0, binding 0 holds every buffer's device address (PlanAddresses in
// render/plan_pipelines.h, the same order), and each file that reads a buffer declares its
// reference type and a macro that names the array as the descriptor variant does. Otherwise the
// buffers are bound as storage buffers, which lavapipe reads faster (its compute grid took 1.6x
// as long by address).
#ifndef PLAN_BUFFERS_GLSL
#define PLAN_BUFFERS_GLSL
#ifdef QP_BY_ADDRESS
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

layout(std140, set = 0, binding = 0) uniform PlanAddresses {
    uint64_t planHeadersAddress, nodesAddress, pointsAddress, weightsAddress, subfacesAddress, ringsAddress,
        positionsAddress, controlPointsAddress, gridAddress, boundariesAddress, segmentsAddress,
        boundaryPointsAddress, subfaceGridAddress, pointPositionsAddress, captureAddress, updateListAddress,
        gridSourceAddress, slotSubfaceAddress, dispTilesAddress, dispPaddedAddress, dispSamplesAddress;
    uint controlPointCount;  // vec4s in controlPoints
    uint dispPaddedCount;    // uints in dispPadded (a placeholder when there is no displacement)
} planBuffers;
#define PLAN_CONTROL_POINT_COUNT planBuffers.controlPointCount
#define PLAN_DISP_PADDED_COUNT planBuffers.dispPaddedCount
#else
#define PLAN_CONTROL_POINT_COUNT uint(controlPoints.length())
#define PLAN_DISP_PADDED_COUNT uint(dispPadded.length())
#endif
#endif
