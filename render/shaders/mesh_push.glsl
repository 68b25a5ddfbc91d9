// Push constants of mesh.vert / mesh.frag; mirrors MeshPush in render/mesh_pass.cpp.
layout(push_constant) uniform MeshPush {
    mat4 viewProj;
    vec4 eye;     // xyz: camera position, world space
    vec4 color;   // rgb: base colour, linear
    vec4 params;  // x: depth pull toward the eye (NDC units), y: 0 lit, 1 unlit, 2 colour stream over the light; z: 1 matcap, 0 studio
} pc;
