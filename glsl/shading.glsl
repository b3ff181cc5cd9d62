// Blinn-Phong shading and the glyph colour modes shared by every ray-casting method.

// Perceptual colormap for magnitudes: a polynomial fit of viridis (t in [0, 1]), linear RGB.
vec3 viridis(float t) {
    t = clamp(t, 0.0, 1.0);
    const vec3 c0 = vec3(0.2777273272234177, 0.005407344544966578, 0.3340998053353061);
    const vec3 c1 = vec3(0.1050930431085774, 1.404613529898575, 1.384590162594685);
    const vec3 c2 = vec3(-0.3308618287255563, 0.214847559468213, 0.09509516302823659);
    const vec3 c3 = vec3(-4.634230498983486, -5.799100973351585, -19.33244095627987);
    const vec3 c4 = vec3(6.228269936347081, 14.17993336680509, 56.69055260068105);
    const vec3 c5 = vec3(4.776384997670288, -13.74514537774601, -65.35303263337234);
    const vec3 c6 = vec3(-5.435455855934631, 4.645852612178535, 26.3124352495832);
    vec3 srgb = c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * c6)))));
    return pow(clamp(srgb, 0.0, 1.0), vec3(2.2));
}

// Colour of a surface point: `dir` is the unit direction from the glyph centre,
// `radius` the world distance from the centre, `f` the glyph function there (its sign
// picks the sign colouring's colour; passes that do not know it give 1).
vec3 glyph_color(vec3 dir, float radius, float f) {
    int mode = frame.modes.z;
    if (mode == COLOR_DIRECTION) {
        // The paper's |p^|: red x, green y, blue z, read as sRGB values.
        return pow(abs(dir), vec3(2.2));
    } else if (mode == COLOR_MAGNITUDE) {
        return viridis((radius - frame.magnitude_range.x) * frame.magnitude_range.y);
    } else if (mode == COLOR_SIGN) {
        return f < 0.0 ? frame.negative_color.rgb : frame.uniform_color.rgb;
    }
    return frame.uniform_color.rgb;
}

// The normal turned towards the viewer, as the lighting takes it.
vec3 facing_normal(vec3 normal, vec3 view_dir) {
    return dot(normal, view_dir) < 0.0 ? -normal : normal;
}

// Blinn-Phong with the terms of --ambient, --specular and --shininess
// (src/render/settings.rs, Lighting), the light's diffuse and specular terms scaled by
// `visibility`, the share of the light that reaches the point (--shadows; 1 unshadowed):
// the normal is turned towards the viewer.
#ifdef GLYPHCAST_SHADOWS
// The share of the ambient light that reaches the point (--ambient-occlusion, set by
// the shadow-casting shader from its occlusion rays; 1 unoccluded).
float shadow_ambient_share = 1.0;
#endif
vec3 blinn_phong_visible(vec3 base, vec3 normal, vec3 view_dir, float visibility) {
    vec3 n = facing_normal(normal, view_dir);
    vec3 l = frame.light.xyz;
    vec3 h = normalize(l + view_dir);
    float ambient = frame.shading.x;
    float diffuse = max(dot(n, l), 0.0) * visibility;
    float specular = frame.shading.y * pow(max(dot(n, h), 0.0), frame.shading.z) * visibility;
#ifdef GLYPHCAST_SHADOWS
    return base * (ambient * shadow_ambient_share + (1.0 - ambient) * diffuse) + vec3(specular);
#else
    return base * (ambient + (1.0 - ambient) * diffuse) + vec3(specular);
#endif
}

// Blinn-Phong of a point the whole light reaches.
vec3 blinn_phong(vec3 base, vec3 normal, vec3 view_dir) {
    return blinn_phong_visible(base, normal, view_dir, 1.0);
}
