// A pixel's ray in one glyph's normalised local frame, the radial sign function, and the
// shading of a hit: what the ray-casting fragment shaders (raycast_common.glsl, which
// feeds it the flat inputs of the proxy box) and the compute ray caster
// (raycast_exact.comp, which reads the glyph's instance and box from storage buffers)
// share. Include after frame.glsl, the glyph function and shading.glsl.

float shape(float f) {
    return glyph_set.hide_negative == NEGATIVE_HIDE ? max(f, 0.0) : abs(f);
}

// g > 0 inside the glyph. Coordinates are normalised so the bound is 1 + offset.
#if defined(GLYPHCAST_PLANE)
// The plane glyph (exact method only, no offset): g = T(q^) |q| − 1 − D(q^) |q|², which
// is −|q|² (λ² − T λ + D) at λ = 1/|q|, positive between its two surfaces, as the exact
// method's F is (the centre zone samples it; both surfaces lie far outside the zone).
float inside(vec3 q) {
    float len = length(q);
    if (len < 1e-20) {
        return -1.0;
    }
    vec3 u = q / len;
    return plane_t(u) * len - 1.0 - glyph_f(u) * len * len;
}
#elif defined(GLYPHCAST_RATIO)
// The sign σ of λ/Q at a point of a ratio glyph's surface, r = |q| along q^, where
// a = r² Q(q^)² + D(q^) and c = r Q(q^) T(q^): the branch whose factor a − σ c vanishes
// there (the nearer to 0 of the two).
float ratio_sign(float a, float c) {
    return abs(a - c) <= abs(a + c) ? 1.0 : -1.0;
}

// The ratio glyph (exact method only, no offset): with r = |q|, a = r² Q(q^)² + D(q^)
// and c = r Q(q^) T(q^), g = c² − a², which is F / |q|^14 (exact_root.glsl), negative
// outside both surfaces and at the centre.
float inside(vec3 q) {
    float len = length(q);
    if (len < 1e-20) {
        return -1.0;
    }
    vec3 u = q / len;
    float qu = ratio_q(u);
    float a = len * len * qu * qu + glyph_f(u);
    float c = len * qu * plane_t(u);
    return c * c - a * a;
}
#elif defined(GLYPHCAST_RECIPROCAL)
// The reciprocal glyph r = 1/|f| (exact method only, no offset): g = 1 - |q| |f(q^)|,
// 1 at the centre, which it holds.
float inside(vec3 q) {
    float len = length(q);
    if (len < 1e-20) {
        return 1.0;
    }
    return 1.0 - len * abs(glyph_f(q / len));
}
#else
float inside(vec3 q) {
    float len = length(q);
    if (len < 1e-20) {
        return frame.march.w;
    }
    return shape(glyph_f(q / len)) + frame.march.w - len;
}
#endif

// The pixel's ray clipped to the glyph's bounding sphere and to its oriented box, in the
// local frame q = (p - c) / rho, where rho maps normalised glyph units to world units.
// Points are q(s) = mid + s * dir, with s measured from the point `mid` of the ray closest
// to the centre, so that q stays well conditioned however far the camera is.
struct GlyphRay {
    vec3 origin;      // world
    vec3 dir;         // world and local (unit)
    vec3 mid;         // local
    float t_mid;      // local distance from the origin to mid
    float rho;
    float half_chord; // of the sphere: the chord is [-half_chord, half_chord] before clipping
    float s_start;    // chord entry, never behind the ray origin
    float s_end;      // chord exit
};

// v rotated by the inverse of the unit quaternion q.
vec3 rotate_inverse(vec4 q, vec3 v) {
    return v - 2.0 * cross(q.xyz, q.w * v - cross(q.xyz, v));
}

// The ray (ray.origin, ray.dir set by the caller) against the sphere |q| = radius of the
// normalised frame of the glyph with bounding sphere `center_radius` (centre, world
// radius of rho (1 + offset)), and against its box (unit quaternion `box_rotation` from
// the box to the world, half extents `box_extent` in units of the sphere radius) scaled
// as the sphere is (its extents times radius / (1 + offset)); false when it misses them
// or they lie behind the origin.
bool glyph_ray_clip(vec4 center_radius, vec4 box_rotation, vec3 box_extent, float radius,
                    inout GlyphRay ray) {
    // The sphere's radius is rho * (1 + offset).
    ray.rho = center_radius.w / (1.0 + frame.march.w);
    ray_in_glyph_frame(ray.origin, ray.dir, center_radius.xyz, ray.rho, ray.t_mid, ray.mid);
    float half_chord2 = radius * radius - dot(ray.mid, ray.mid);
    if (half_chord2 <= 0.0) {
        return false;
    }
    ray.half_chord = sqrt(half_chord2);
    float lo = max(-ray.half_chord, -ray.t_mid);
    float hi = ray.half_chord;
    // Slabs of the box, in its own frame.
    vec3 extent = box_extent * radius;
    vec3 m = rotate_inverse(box_rotation, ray.mid);
    vec3 d = rotate_inverse(box_rotation, ray.dir);
    for (int i = 0; i < 3; ++i) {
        float di = abs(d[i]) < 1e-20 ? 1e-20 : d[i];
        float a = (-extent[i] - m[i]) / di;
        float b = (extent[i] - m[i]) / di;
        lo = max(lo, min(a, b));
        hi = min(hi, max(a, b));
    }
    ray.s_start = lo;
    ray.s_end = hi;
    return lo < hi;
}

// The outward unit normal of g = 0 at the surface point q of the loaded glyph, with
// |q|, q^ = q / |q| and f(q^).
vec3 surface_normal(vec3 q, out float len, out vec3 q_dir, out float f) {
    len = max(length(q), 1e-20);
    q_dir = q / len;
    vec3 grad;
    f = glyph_f_grad(q_dir, grad);
#if defined(GLYPHCAST_PLANE)
    // |q|⁴ − T(q) |q| + D(q) = 0 on both surfaces; its gradient over |q|³ is
    // 4 q^ − |q| (grad T(q^) + T(q^) q^) + |q|² grad D(q^), turned outwards (every
    // surface of a radius function faces away from the centre). Positive, for colour.
    vec3 grad_t;
    float t = plane_t_grad(q_dir, grad_t);
    vec3 normal = normalize(4.0 * q_dir - len * (grad_t + t * q_dir) + len * len * grad);
    f = 1.0;
    return dot(normal, q_dir) < 0.0 ? -normal : normal;
#elif defined(GLYPHCAST_RATIO)
    // |q| (Q(q)² + D(q)) − σ Q(q) T(q) = 0 on the branch σ; its gradient over |q|⁶ is
    // (r² Q² + D) q^ + 2 r² Q grad Q + grad D − σ r (T grad Q + Q grad T) at q^, turned
    // outwards. f becomes σ, the sign of λ/Q, for the sign colours.
    vec3 grad_t;
    vec3 grad_q;
    float t = plane_t_grad(q_dir, grad_t);
    float qu = ratio_q_grad(q_dir, grad_q);
    float a = len * len * qu * qu + f;
    float sigma = ratio_sign(a, len * qu * t);
    vec3 normal = normalize(a * q_dir + 2.0 * len * len * qu * grad_q + grad
                            - sigma * len * (t * grad_q + qu * grad_t));
    f = sigma;
    return dot(normal, q_dir) < 0.0 ? -normal : normal;
#else
    float sgn = (glyph_set.hide_negative == NEGATIVE_HIDE || f >= 0.0) ? 1.0 : -1.0;
    // Outward normal of g = 0: (|q| + n |f|) q^ - sgn grad f(q^) (Euler's identity).
#ifdef GLYPHCAST_RECIPROCAL
    // Outward normal of |f(q)| = |q|^(n-1): |q| sgn grad f(q^) - (n - 1) q^.
    return normalize(len * sgn * grad - (float(GLYPH_ORDER) - 1.0) * q_dir);
#else
    return normalize((len + float(GLYPH_ORDER) * abs(f)) * q_dir - sgn * grad);
#endif
#endif
}

// Colour (linear RGB, alpha 1), window depth and ray distance of the hit at q(s_hit),
// lit by the share `visibility` of the light (--shadows; 1 unshadowed).
void shade_surface_visible(GlyphRay ray, float s_hit, float visibility, out vec4 color,
                           out float depth, out float distance) {
    float len;
    vec3 q_dir;
    float f;
    vec3 normal = surface_normal(ray.mid + s_hit * ray.dir, len, q_dir, f);

    distance = (ray.t_mid + s_hit) * ray.rho;
    vec3 world = ray.origin + distance * ray.dir;
    depth = window_depth(world);

    vec3 base = glyph_color(q_dir, len * ray.rho, f);
    color = vec4(blinn_phong_visible(base, normal, -ray.dir, visibility), 1.0);
}

// shade_surface_visible of a hit the whole light reaches.
void shade_surface(GlyphRay ray, float s_hit, out vec4 color, out float depth,
                   out float distance) {
    shade_surface_visible(ray, s_hit, 1.0, color, depth, distance);
}
