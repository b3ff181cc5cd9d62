#version 450
// The anatomical underlay's colour: the volume sampled trilinearly at the fragment's
// voxel coordinate (8 reads of the value buffer, in float32, exactly as
// UnderlayVolume::sample does in float64), windowed to [0, 1] and written so that the
// sRGB target stores round(255 g): a window maps linearly onto the PNG's 8-bit values.
// Outside the volume (beyond half a voxel from the outer voxel centres) and where a
// neighbouring voxel is NaN, nothing is drawn: the background (or a glyph) shows.
// Where the plane is drawn, the ray distance is "no glyph": the depth map keeps glyph
// hits only, and a glyph behind the plane is not seen.
// A storage buffer, as the frame block (frame.glsl says why).
layout(std430, set = 0, binding = 0) readonly buffer UnderlayParams {
    mat4 world_to_voxel;
    ivec4 dims;
    vec4 window;
} underlay;

layout(std430, set = 0, binding = 1) readonly buffer UnderlayValues {
    float values[];  // channels interleaved, i fastest, then j, then k
};

layout(location = 0) in vec3 v_voxel;
layout(location = 0) out vec4 out_color;
// The distance attachment, where the target has one: -1, no glyph (NaN in the depth map).
layout(location = 1) out float out_distance;

float value_at(ivec3 p, int c) {
    ivec4 d = underlay.dims;
    return values[((p.z * d.y + p.y) * d.x + p.x) * d.w + c];
}

float srgb_to_linear(float c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

void main() {
    vec3 size = vec3(underlay.dims.xyz);
    if (any(lessThan(v_voxel, vec3(-0.5))) || any(greaterThan(v_voxel, size - 0.5))) {
        discard;
    }
    ivec3 last = underlay.dims.xyz - 1;
    vec3 p = clamp(v_voxel, vec3(0.0), vec3(last));
    ivec3 lo = min(ivec3(floor(p)), last);
    ivec3 hi = min(lo + 1, last);
    vec3 f = p - vec3(lo);
    vec3 rgb = vec3(0.0);
    for (int c = 0; c < underlay.dims.w; ++c) {
        float c000 = value_at(ivec3(lo.x, lo.y, lo.z), c);
        float c100 = value_at(ivec3(hi.x, lo.y, lo.z), c);
        float c010 = value_at(ivec3(lo.x, hi.y, lo.z), c);
        float c110 = value_at(ivec3(hi.x, hi.y, lo.z), c);
        float c001 = value_at(ivec3(lo.x, lo.y, hi.z), c);
        float c101 = value_at(ivec3(hi.x, lo.y, hi.z), c);
        float c011 = value_at(ivec3(lo.x, hi.y, hi.z), c);
        float c111 = value_at(ivec3(hi.x, hi.y, hi.z), c);
        float x00 = mix(c000, c100, f.x);
        float x10 = mix(c010, c110, f.x);
        float x01 = mix(c001, c101, f.x);
        float x11 = mix(c011, c111, f.x);
        float v = mix(mix(x00, x10, f.y), mix(x01, x11, f.y), f.z);
        if (isnan(c000) || isnan(c100) || isnan(c010) || isnan(c110) ||
            isnan(c001) || isnan(c101) || isnan(c011) || isnan(c111)) {
            discard;
        }
        rgb[c] = clamp((v - underlay.window.x) * underlay.window.y, 0.0, 1.0);
    }
    if (underlay.dims.w == 1) {
        rgb = vec3(rgb.x);
    }
    out_distance = -1.0;
    out_color = vec4(srgb_to_linear(rgb.r), srgb_to_linear(rgb.g), srgb_to_linear(rgb.b), 1.0);
}
