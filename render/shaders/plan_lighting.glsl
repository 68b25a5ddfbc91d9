// Lighting of the plans' fragment shaders: a key light from the front-right-above and a fill
// from the upper left, both two-sided (open cages show their inside). Linear colour.
const vec3 kPlanAlbedo = vec3(0.72, 0.74, 0.78);
const vec3 kWireColor = vec3(0.08, 0.1, 0.14);  // tessellation wireframe

vec3 lightPlan(vec3 albedo, vec3 normal, bool frontFacing) {
    vec3 n = normalize(normal);
    if (!frontFacing) n = -n;
    vec3 key = normalize(vec3(0.3, 0.5, 1.0)), fill = normalize(vec3(-0.6, 0.8, -0.2));
    float diffuse = 0.75 * abs(dot(n, key)) + 0.25 * max(dot(n, fill), 0.0);
    return albedo * (0.18 + 0.82 * diffuse);
}
