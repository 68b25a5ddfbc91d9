// How every fragment shader writes colour. Lighting happens in linear space; an _SRGB target
// encodes on store, any other (UNORM: PNGs, most swapchains) needs the sRGB curve here. The
// pipeline sets kEncodeSrgb from the target's format (render_target.h, ColorEncoding), and
// beginRendering encodes the clear colour the same way, so background and surfaces agree.
layout(constant_id = 0) const bool kEncodeSrgb = true;

vec3 linearToSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

vec4 encodeColor(vec3 linear) {
    return vec4(kEncodeSrgb ? linearToSrgb(linear) : linear, 1.0);
}
