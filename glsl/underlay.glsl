// The anatomical underlay's colour at a voxel coordinate: the volume sampled trilinearly
// (8 reads of the value buffer, in float32, exactly as UnderlayVolume::sample does in
// float64), windowed to [0, 1] and turned into the linear colour that an sRGB target
// stores as round(255 g): a window maps linearly onto the PNG's 8-bit values. Shared by
// underlay.frag and the underlay's shadow receiver (raycast_exact.frag), which binds
// the underlay's blocks as set UNDERLAY_SET.
#ifndef UNDERLAY_SET
#define UNDERLAY_SET 0
#endif
// A storage buffer, as the frame block (frame.glsl says why).
layout(std430, set = UNDERLAY_SET, binding = 0) readonly buffer UnderlayParams {
    mat4 world_to_voxel;
    ivec4 dims;
    vec4 window;
} underlay;

layout(std430, set = UNDERLAY_SET, binding = 1) readonly buffer UnderlayValues {
    float values[];  // channels interleaved, i fastest, then j, then k
};

float underlay_value_at(ivec3 p, int c) {
    ivec4 d = underlay.dims;
    return values[((p.z * d.y + p.y) * d.x + p.x) * d.w + c];
}

float underlay_srgb_to_linear(float c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

// The linear colour at `voxel`; false outside the volume (beyond half a voxel from the
// outer voxel centres) and where a neighbouring voxel is NaN: nothing is drawn there.
bool underlay_rgb(vec3 voxel, out vec3 linear_rgb) {
    linear_rgb = vec3(0.0);
    vec3 size = vec3(underlay.dims.xyz);
    if (any(lessThan(voxel, vec3(-0.5))) || any(greaterThan(voxel, size - 0.5))) {
        return false;
    }
    ivec3 last = underlay.dims.xyz - 1;
    vec3 p = clamp(voxel, vec3(0.0), vec3(last));
    ivec3 lo = min(ivec3(floor(p)), last);
    ivec3 hi = min(lo + 1, last);
    vec3 f = p - vec3(lo);
    vec3 rgb = vec3(0.0);
    for (int c = 0; c < underlay.dims.w; ++c) {
        float c000 = underlay_value_at(ivec3(lo.x, lo.y, lo.z), c);
        float c100 = underlay_value_at(ivec3(hi.x, lo.y, lo.z), c);
        float c010 = underlay_value_at(ivec3(lo.x, hi.y, lo.z), c);
        float c110 = underlay_value_at(ivec3(hi.x, hi.y, lo.z), c);
        float c001 = underlay_value_at(ivec3(lo.x, lo.y, hi.z), c);
        float c101 = underlay_value_at(ivec3(hi.x, lo.y, hi.z), c);
        float c011 = underlay_value_at(ivec3(lo.x, hi.y, hi.z), c);
        float c111 = underlay_value_at(ivec3(hi.x, hi.y, hi.z), c);
        float x00 = mix(c000, c100, f.x);
        float x10 = mix(c010, c110, f.x);
        float x01 = mix(c001, c101, f.x);
        float x11 = mix(c011, c111, f.x);
        float v = mix(mix(x00, x10, f.y), mix(x01, x11, f.y), f.z);
        if (isnan(c000) || isnan(c100) || isnan(c010) || isnan(c110) ||
            isnan(c001) || isnan(c101) || isnan(c011) || isnan(c111)) {
            return false;
        }
        rgb[c] = clamp((v - underlay.window.x) * underlay.window.y, 0.0, 1.0);
    }
    if (underlay.dims.w == 1) {
        rgb = vec3(rgb.x);
    }
    linear_rgb = vec3(underlay_srgb_to_linear(rgb.r), underlay_srgb_to_linear(rgb.g),
                      underlay_srgb_to_linear(rgb.b));
    return true;
}
