#version 450
// Evaluates the generated interval and affine ranges of f and G over given ray segments,
// so tests can check that they contain densely sampled float64 values.
#extension GL_GOOGLE_include_directive : require
#include "codes.glsl"
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer Coefficients {
    float coeffs[];
};

struct RangeQuery {
    vec4 mid_s0;         // xyz: mid, w: s0 (normalised glyph frame)
    vec4 dir_s1;         // xyz: dir, w: s1
    uint glyph;          // index into the coefficients
    uint hide_negative;  // NEGATIVE_ABS or NEGATIVE_HIDE
    float offset;        // w, normalised units
    uint pad;
};
layout(std430, set = 0, binding = 1) readonly buffer Queries {
    RangeQuery queries[];
};

struct RangeResult {
    vec4 interval;  // f lo, f hi, G lo, G hi
    vec4 affine;    // the same by reduced affine arithmetic
};
layout(std430, set = 0, binding = 2) writeonly buffer Results {
    RangeResult results[];
};

layout(push_constant) uniform RangeParams {
    uint count;
} params;

#include "glyph_function.glsl"
#include "glyph_range.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.count) {
        return;
    }
    RangeQuery q = queries[i];
    glyph_load(q.glyph);
    float abs_sum = glyph_abs_sum(q.glyph);
    bool hide = q.hide_negative == NEGATIVE_HIDE;
    GlyphRange ia = glyph_range_interval(q.mid_s0.xyz, q.dir_s1.xyz, q.mid_s0.w, q.dir_s1.w,
                                         q.offset, hide, abs_sum);
    GlyphRange aa = glyph_range_affine(q.mid_s0.xyz, q.dir_s1.xyz, q.mid_s0.w, q.dir_s1.w,
                                       q.offset, hide, abs_sum);
    results[i] = RangeResult(vec4(ia.f, ia.g), vec4(aa.f, aa.g));
}
