#version 450
// The seed's ray caster (Hlawitschka et al., Sec. 4): the pixel's ray in the glyph's local
// frame, bounding-sphere exit, fixed-step sign test with finer steps near the centre, and
// refinement of the first sign change. The sign function is the radial form
// g(q) = h(f(q/|q|)) + offset - |q| (h = abs, or max(., 0) to hide negative lobes), which has
// the zero set of the seed's Eq. 3 but stays well scaled near the centre.
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"
#include "glyph_function.glsl"
#include "pixel_ray.glsl"
#include "shading.glsl"

layout(location = 0) flat in uint v_glyph;
layout(location = 1) flat in vec4 v_center_radius;

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_distance;
layout(depth_greater) out float gl_FragDepth;

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

void main() {
    vec3 origin, dir;
    pixel_ray(origin, dir);
    // The box half-size is rho * bound: rho maps normalised glyph units to world units.
    float bound = 1.0 + frame.march.w;
    float rho = v_center_radius.w / bound;

    // Local frame: q = (p - c) / rho; march in s from the point closest to the centre.
    float t_mid;
    vec3 mid;
    ray_in_glyph_frame(origin, dir, v_center_radius.xyz, rho, t_mid, mid);
    float half_chord2 = bound * bound - dot(mid, mid);
    if (half_chord2 <= 0.0) {
        discard;
    }
    float half_chord = sqrt(half_chord2);
    float s_end = half_chord;
    float s = max(-half_chord, -t_mid);  // never behind the ray origin
    if (s >= s_end) {
        discard;
    }

    glyph_load(v_glyph);
    float step = frame.march.x;
    float centre_step = step * frame.march.y;
    float centre_zone = frame.march.z;

    float g_prev = inside(mid + s * dir);
    float s_prev = s;
    float s_hit = -1.0;
    bool found = g_prev > 0.0;
    if (found) {
        s_hit = s;
    }
    for (int i = 0; i < frame.modes.w && !found; ++i) {
        vec3 q = mid + s_prev * dir;
        s = min(s_prev + (length(q) < centre_zone ? centre_step : step), s_end);
        float g = inside(mid + s * dir);
        if (g > 0.0) {
            s_hit = refine(mid, dir, s_prev, g_prev, s, g);
            found = true;
        } else if (s >= s_end) {
            break;
        }
        s_prev = s;
        g_prev = g;
    }
    if (!found) {
        discard;
    }

    vec3 q = mid + s_hit * dir;
    float len = max(length(q), 1e-20);
    vec3 q_dir = q / len;
    vec3 grad;
    float f = glyph_f_grad(q_dir, grad);
    float sgn = (glyph_set.hide_negative != 0u || f >= 0.0) ? 1.0 : -1.0;
    // Outward normal of g = 0: (|q| + n |f|) q^ - sgn grad f(q^) (Euler's identity).
    vec3 normal = normalize((len + float(GLYPH_ORDER) * abs(f)) * q_dir - sgn * grad);

    float distance = (t_mid + s_hit) * rho;
    vec3 world = origin + distance * dir;
    gl_FragDepth = window_depth(world);

    vec3 base = glyph_color(q_dir, len * rho);
    out_color = vec4(blinn_phong(base, normal, -dir), 1.0);
    out_distance = distance;
}
