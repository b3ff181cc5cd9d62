// Interval arithmetic (IA) and reduced affine arithmetic (RAA) for the generated glyph
// ranges (Knoll et al., "Fast and robust ray tracing of general implicits on the GPU").
// Mirrored in float64 and float32 by src/glyph/interval.rs; keep both in step.
//
// An interval is vec2(lo, hi). A reduced affine form is vec3(c, e, r): the set of values
// c + e * eps + [-r, r], where eps in [-1, 1] is the one noise symbol of a ray segment
// (s = centre + radius * eps) and r collects every nonlinear remainder.
//
// Float32 rounding is not controlled here (GLSL has no directed rounding): the callers
// widen the final range by a bound on the accumulated rounding (glyph_range.glsl).

vec2 ia_mul(vec2 a, vec2 b) {
    vec4 p = vec4(a.x * b.x, a.x * b.y, a.y * b.x, a.y * b.y);
    return vec2(min(min(p.x, p.y), min(p.z, p.w)), max(max(p.x, p.y), max(p.z, p.w)));
}

// x^k for even k from e = (lo^k, hi^k): never negative, and 0 when x spans 0.
// (Odd powers are monotone: e itself.)
vec2 ia_even(vec2 e, vec2 x) {
    if (x.x >= 0.0) {
        return e;
    }
    if (x.y <= 0.0) {
        return e.yx;
    }
    return vec2(0.0, max(e.x, e.y));
}

vec2 ia_scale(float c, vec2 a) {
    return c >= 0.0 ? c * a : c * a.yx;
}

// (a0 + a1 eps + ra)(b0 + b1 eps + rb). The eps^2 term is split as
// a1 b1 / 2 + (a1 b1 / 2)(2 eps^2 - 1) with |2 eps^2 - 1| <= 1, which keeps squares
// centred instead of symmetric about their centre value.
vec3 aa_mul(vec3 a, vec3 b) {
    float h = 0.5 * a.y * b.y;
    return vec3(a.x * b.x + h,
                a.x * b.y + a.y * b.x,
                abs(h) + (abs(a.x) + abs(a.y)) * b.z + a.z * (abs(b.x) + abs(b.y) + b.z));
}

vec3 aa_scale(float c, vec3 a) {
    return vec3(c * a.xy, abs(c) * a.z);
}

vec2 aa_range(vec3 a) {
    float w = abs(a.y) + a.z;
    return vec2(a.x - w, a.x + w);
}
