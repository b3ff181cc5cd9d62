// Guaranteed ranges of the glyph's implicit function over a ray segment, by interval
// arithmetic (IA) or reduced affine arithmetic (RAA), for the robust ray casters and for
// the inclusion test (glyph_range.comp). Mirrored by src/glyph/interval.rs.
//
// Along q(s) = mid + s * dir, s in [s0, s1], in the normalised glyph frame, the range is
// taken of the homogeneous form of the radial sign function g:
//
//     G(q) = h(f(q)) + w |q|^n - |q|^(n+1)        (h = abs, or max(., 0) to hide)
//
// G = |q|^n g(q) since f is homogeneous of degree n, so G > 0 exactly where g > 0, but
// G is a polynomial in q (up to h and the powers of |q|), whose range IA and RAA bound.
// f's range comes from the generated glyph_f_interval / glyph_f_affine; |q|^2 along the
// ray is a quadratic in s, whose powers are bounded exactly (IA) or by secant and
// tangent lines, as |q|^k is convex in s (RAA).
//
// Float32 rounding: every returned range is widened by a bound on its rounding error,
// GLYPH_RANGE_GAMMA_F (unit roundoffs, per variant) times sum |c_k| |monomial_k| <=
// abs_sum * m^n (m: the largest coordinate magnitude on the segment), plus
// GLYPH_RANGE_GAMMA_R times the largest |q|^(n+1) + w |q|^n. The widened range contains
// G for the float32 coefficients and segment in exact arithmetic.

struct GlyphRange {
    vec2 f;  // range of f(q(s))
    vec2 g;  // range of G(q(s))
};

// Coefficients (c, b, a) of |q(s)|^2 = c + 2 b s + a s^2.
vec3 ray_quadratic(vec3 mid, vec3 dir) {
    return vec3(dot(mid, mid), dot(mid, dir), dot(dir, dir));
}

float quadratic_at(vec3 k, float s) {
    return max(k.x + s * (2.0 * k.y + s * k.z), 0.0);
}

// q2^(k/2) for q2 >= 0: powers by multiplication (pow would cost accuracy).
float half_power(float q2, uint k) {
    float p = 1.0;
    for (uint i = 0u; i < k / 2u; ++i) {
        p *= q2;
    }
    return (k & 1u) != 0u ? p * sqrt(q2) : p;
}

float order_power(float m) {
    float p = 1.0;
    for (uint i = 0u; i < GLYPH_ORDER; ++i) {
        p *= m;
    }
    return p;
}

// Exact range of |q(s)|^2 over [s0, s1]: the quadratic's vertex or an end.
vec2 radius_squared_range(vec3 k, float s0, float s1) {
    float q0 = quadratic_at(k, s0);
    float q1 = quadratic_at(k, s1);
    float vertex = k.z > 0.0 ? clamp(-k.y / k.z, s0, s1) : s0;
    return vec2(min(min(q0, q1), quadratic_at(k, vertex)), max(q0, q1));
}

vec2 shape_interval(vec2 f, bool hide) {
    if (hide) {
        return max(f, vec2(0.0));
    }
    if (f.x >= 0.0) {
        return f;
    }
    if (f.y <= 0.0) {
        return -f.yx;
    }
    return vec2(0.0, max(-f.x, f.y));
}

// Rounding bound of f's range: sum |c_k| |monomial_k| <= abs_sum * m^n.
float f_tolerance(float abs_sum, float m) {
    return GLYPH_RANGE_GAMMA_F * abs_sum * order_power(m);
}

GlyphRange glyph_range_interval(vec3 mid, vec3 dir, float s0, float s1, float offset,
                                bool hide, float abs_sum) {
    vec3 a = mid + s0 * dir;
    vec3 b = mid + s1 * dir;
    vec3 lo = min(a, b);
    vec3 hi = max(a, b);
    vec2 f = glyph_f_interval(vec2(lo.x, hi.x), vec2(lo.y, hi.y), vec2(lo.z, hi.z));
    vec2 h = shape_interval(f, hide);
    vec2 q2 = radius_squared_range(ray_quadratic(mid, dir), s0, s1);
    vec2 rn = vec2(half_power(q2.x, GLYPH_ORDER), half_power(q2.y, GLYPH_ORDER));
    vec2 rn1 = vec2(half_power(q2.x, GLYPH_ORDER + 1u), half_power(q2.y, GLYPH_ORDER + 1u));
    vec2 g = vec2(h.x + offset * rn.x - rn1.y, h.y + offset * rn.y - rn1.x);
    vec3 m3 = max(abs(lo), abs(hi));
    float m = max(max(m3.x, m3.y), m3.z);
    float tol_f = f_tolerance(abs_sum, m);
    float tol = tol_f + GLYPH_RANGE_GAMMA_R * (rn1.y + offset * rn.y);
    return GlyphRange(f + vec2(-tol_f, tol_f), g + vec2(-tol, tol));
}

// Affine form of P(s) = |q(s)|^k, k >= 1, over s = sc + sr * eps. P is convex in s, so it
// lies below its secant and above its tangents at the ends; the tangents meet at most
// 2 (sigma - d0)(d1 - sigma) / (d1 - d0) below the secant (sigma: the secant's slope,
// d0, d1: the end slopes, all per unit eps).
vec3 aa_radius_power(vec3 quad, float s0, float s1, uint k) {
    float sr = 0.5 * (s1 - s0);
    float q0 = quadratic_at(quad, s0);
    float q1 = quadratic_at(quad, s1);
    float p0 = half_power(q0, k);
    float p1 = half_power(q1, k);
    // dP/ds = k |q|^(k-1) (dir . q) / |q|; |dir . q| <= |dir| |q| bounds the quotient,
    // and at q = 0 (k = 1: a kink) 0 is a valid subgradient.
    float dir_len = sqrt(quad.z);
    float u0 = clamp((quad.y + s0 * quad.z) / max(sqrt(q0), 1e-30), -dir_len, dir_len);
    float u1 = clamp((quad.y + s1 * quad.z) / max(sqrt(q1), 1e-30), -dir_len, dir_len);
    float d0 = float(k) * half_power(q0, k - 1u) * u0 * sr;
    float d1 = float(k) * half_power(q1, k - 1u) * u1 * sr;
    float sigma = 0.5 * (p1 - p0);
    float spread = d1 - d0;
    float gap = spread > 0.0 ? 2.0 * max(sigma - d0, 0.0) * max(d1 - sigma, 0.0) / spread : 0.0;
    return vec3(0.5 * (p0 + p1) - 0.5 * gap, sigma, 0.5 * gap);
}

vec3 shape_affine(vec3 f, bool hide) {
    vec2 r = aa_range(f);
    if (r.x >= 0.0) {
        return f;
    }
    if (r.y <= 0.0) {
        return hide ? vec3(0.0) : vec3(-f.xy, f.z);
    }
    // f changes sign: h(f) is no longer affine in eps; keep its interval.
    vec2 h = shape_interval(r, hide);
    return vec3(0.5 * (h.x + h.y), 0.0, 0.5 * (h.y - h.x));
}

GlyphRange glyph_range_affine(vec3 mid, vec3 dir, float s0, float s1, float offset,
                              bool hide, float abs_sum) {
    float sc = 0.5 * (s0 + s1);
    float sr = 0.5 * (s1 - s0);
    vec3 c = mid + sc * dir;
    vec3 e = sr * dir;
    vec3 f = glyph_f_affine(vec3(c.x, e.x, 0.0), vec3(c.y, e.y, 0.0), vec3(c.z, e.z, 0.0));
    vec3 h = shape_affine(f, hide);
    vec3 quad = ray_quadratic(mid, dir);
    vec3 rn = aa_radius_power(quad, s0, s1, GLYPH_ORDER);
    vec3 rn1 = aa_radius_power(quad, s0, s1, GLYPH_ORDER + 1u);
    vec3 g = vec3(h.xy + offset * rn.xy - rn1.xy, h.z + offset * rn.z + rn1.z);
    vec3 m3 = abs(c) + abs(e);
    float m = max(max(m3.x, m3.y), m3.z);
    float tol_f = f_tolerance(abs_sum, m);
    float tol = tol_f + GLYPH_RANGE_GAMMA_R * (aa_range(rn1).y + offset * aa_range(rn).y);
    return GlyphRange(aa_range(f) + vec2(-tol_f, tol_f), aa_range(g) + vec2(-tol, tol));
}
