// Lighting of the plans' fragment shaders (after plan_draw.glsl): "studio", a key light from
// the front-right-above and a fill from the upper left, both two-sided (open cages show their
// inside), or "matcap" (matcap.glsl) when bit 8 of draw.colorMode is set (plan_pass.cpp
// drawPush). Linear colour.
#include "matcap.glsl"

const vec3 kPlanAlbedo = vec3(0.72, 0.74, 0.78);
const vec3 kWireColor = vec3(0.08, 0.1, 0.14);  // tessellation wireframe
const uint kMatcapBit = 0x100u;

vec3 lightPlan(vec3 albedo, vec3 normal, bool frontFacing) {
    vec3 n = normalize(normal);
    if (!frontFacing) n = -n;
    if ((draw.colorMode & kMatcapBit) != 0u) {
        vec3 highlight;
        vec3 light = matcapLight(viewNormalFrom(draw.viewProjection, n), highlight);
        return albedo * light + highlight;
    }
    vec3 key = normalize(draw.keyLight.xyz), fill = normalize(draw.fillLight.xyz);
    float diffuse = 0.75 * abs(dot(n, key)) + 0.25 * max(dot(n, fill), 0.0);
    return albedo * (0.18 + 0.82 * diffuse);
}
