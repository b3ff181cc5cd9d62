// What every ray-casting method shares (Hlawitschka et al., Sec. 4): the pixel's ray in the
// glyph's normalised local frame, the radial sign function, refinement of a bracketed
// sign change, and the shading and outputs of a hit. A method's fragment shader includes
// this file and only decides how to find the first sign change along the chord.
//
// The sign function is the radial form g(q) = h(f(q/|q|)) + offset - |q| (h = abs, or
// max(., 0) to hide negative lobes), which has the zero set of the seed's Eq. 3 but stays
// well scaled near the centre.
#include "frame.glsl"
#include "glyph_function.glsl"
#include "pixel_ray.glsl"
#include "shading.glsl"

layout(location = 0) flat in uint v_glyph;
layout(location = 1) flat in vec4 v_center_radius;
layout(location = 2) flat in vec4 v_box_rotation;  // box to world (raycast.vert)
layout(location = 3) flat in vec3 v_box_extent;    // in units of v_center_radius.w
// The glyph's monomial coefficients (glyph_c), from raycast.vert. On lavapipe a fragment
// shader reads a storage buffer at a per-fragment index as a gather per lane, and the
// coefficients' loads alone were a quarter of the exact method's time; flat inputs are
// set up once per triangle. 4 + GLYPH_COEFF_VEC4S locations (27 at order 12).
const int GLYPH_COEFF_VEC4S = (GLYPH_MONOMIALS + 3) / 4;
layout(location = 4) flat in vec4 v_coeffs[GLYPH_COEFF_VEC4S];

layout(location = 0) out vec4 out_color;
#ifndef GLYPHCAST_NO_DISTANCE  // build.rs: the variant for a colour attachment only
layout(location = 1) out float out_distance;
#endif
layout(depth_less) out float gl_FragDepth;  // reversed depth: hits lie behind the proxy

// glyph_c of this fragment's glyph (glyph_load of the vertex shader, multiplicities
// folded in).
void glyph_load_inputs() {
    [[unroll]] for (int k = 0; k < GLYPH_MONOMIALS; ++k) {
        glyph_c[k] = v_coeffs[k / 4][k % 4];
    }
}

float shape(float f) {
    return glyph_set.hide_negative != 0u ? max(f, 0.0) : abs(f);
}

// g > 0 inside the glyph. Coordinates are normalised so the bound is 1 + offset.
float inside(vec3 q) {
    float len = length(q);
    if (len < 1e-20) {
        return frame.march.w;
    }
    return shape(glyph_f(q / len)) + frame.march.w - len;
}

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

// The ray against the sphere |q| = radius of the normalised frame, and against the box
// scaled as the sphere is (its extents times radius / (1 + offset)); false when it misses
// them or they lie behind the origin.
bool glyph_ray_within(float radius, out GlyphRay ray) {
    pixel_ray(ray.origin, ray.dir);
    // The sphere's radius is rho * (1 + offset).
    ray.rho = v_center_radius.w / (1.0 + frame.march.w);
    ray_in_glyph_frame(ray.origin, ray.dir, v_center_radius.xyz, ray.rho, ray.t_mid, ray.mid);
    float half_chord2 = radius * radius - dot(ray.mid, ray.mid);
    if (half_chord2 <= 0.0) {
        return false;
    }
    ray.half_chord = sqrt(half_chord2);
    float lo = max(-ray.half_chord, -ray.t_mid);
    float hi = ray.half_chord;
    // Slabs of the box, in its own frame.
    vec3 extent = v_box_extent * radius;
    vec3 m = rotate_inverse(v_box_rotation, ray.mid);
    vec3 d = rotate_inverse(v_box_rotation, ray.dir);
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

// The ray against the glyph's bounding sphere.
bool glyph_ray(out GlyphRay ray) {
    return glyph_ray_within(1.0 + frame.march.w, ray);
}

// Refines a bracket [s0, s1] with g(s0) <= 0 < g(s1) along q(s) = mid + s * dir.
float refine(vec3 mid, vec3 dir, float s0, float g0, float s1, float g1) {
    int mode = frame.modes.x;
    if (mode == 1) {
        for (int i = 0; i < frame.modes.y; ++i) {
            float sm = 0.5 * (s0 + s1);
            float gm = inside(mid + sm * dir);
            if (gm > 0.0) { s1 = sm; g1 = gm; } else { s0 = sm; g0 = gm; }
        }
        return 0.5 * (s0 + s1);
    } else if (mode == 2) {
        return s0 + (s1 - s0) * (g0 / (g0 - g1));
    } else if (mode == 3) {
        // Regula falsi, Illinois variant: halve the weight of an end that stays put.
        int stuck = 0;
        for (int i = 0; i < frame.modes.y; ++i) {
            float sm = s0 + (s1 - s0) * (g0 / (g0 - g1));
            float gm = inside(mid + sm * dir);
            if (gm > 0.0) {
                s1 = sm; g1 = gm;
                if (stuck == 1) { g0 *= 0.5; }
                stuck = 1;
            } else {
                s0 = sm; g0 = gm;
                if (stuck == -1) { g1 *= 0.5; }
                stuck = -1;
            }
        }
        return s0 + (s1 - s0) * (g0 / (g0 - g1));
    }
    return s1;
}

// Normal, colour, depth and ray distance of the hit at q(s_hit).
void shade_hit(GlyphRay ray, float s_hit) {
    vec3 q = ray.mid + s_hit * ray.dir;
    float len = max(length(q), 1e-20);
    vec3 q_dir = q / len;
    vec3 grad;
    float f = glyph_f_grad(q_dir, grad);
    float sgn = (glyph_set.hide_negative != 0u || f >= 0.0) ? 1.0 : -1.0;
    // Outward normal of g = 0: (|q| + n |f|) q^ - sgn grad f(q^) (Euler's identity).
    vec3 normal = normalize((len + float(GLYPH_ORDER) * abs(f)) * q_dir - sgn * grad);

    float distance = (ray.t_mid + s_hit) * ray.rho;
    vec3 world = ray.origin + distance * ray.dir;
    gl_FragDepth = window_depth(world);

    vec3 base = glyph_color(q_dir, len * ray.rho);
    out_color = vec4(blinn_phong(base, normal, -ray.dir), 1.0);
#ifndef GLYPHCAST_NO_DISTANCE
    out_distance = distance;
#endif
}
