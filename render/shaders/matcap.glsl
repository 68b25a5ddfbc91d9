// The "matcap" shading (core/scene/shading.h): a procedural clay material looked up by the view-space
// normal (x right, y up, z toward the viewer), so its light turns with the camera and every
// side of the model reads the same. No texture: a key light from the upper left, a sky/ground
// wrap, a rim at the silhouette and a soft highlight.

// The view-space normal of a world-space normal, from a Vulkan view-projection matrix: its
// first two rows are the camera's right and up axes scaled by the projection (y flipped).
vec3 viewNormalFrom(mat4 viewProjection, vec3 worldNormal) {
    vec3 right = normalize(vec3(viewProjection[0][0], viewProjection[1][0], viewProjection[2][0]));
    vec3 up = -normalize(vec3(viewProjection[0][1], viewProjection[1][1], viewProjection[2][1]));
    vec3 back = cross(right, up);
    return vec3(dot(worldNormal, right), dot(worldNormal, up), dot(worldNormal, back));
}

// The light a matcap gives a surface of this view-space normal (multiplies the albedo), and
// its highlight (added).
vec3 matcapLight(vec3 viewNormal, out vec3 highlight) {
    vec3 n = normalize(viewNormal);
    if (n.z < 0.0) n = -n;  // two-sided, like the studio lights
    const vec3 key = normalize(vec3(-0.45, 0.6, 0.66));
    float diffuse = max(dot(n, key), 0.0);
    float wrap = 0.5 + 0.5 * n.y;           // brighter from above, a darker ground below
    float rim = pow(1.0 - n.z, 3.0);        // lit silhouettes separate the form from the background
    float spec = pow(max(reflect(-key, n).z, 0.0), 24.0);
    highlight = vec3(0.22 * spec + 0.18 * rim);
    return vec3(1.0, 0.92, 0.84) * (0.1 + 0.3 * wrap + 0.7 * diffuse);
}
