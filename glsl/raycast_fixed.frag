#version 450
// The seed's ray caster (Hlawitschka et al., Sec. 4): the pixel's ray in the glyph's local
// frame, bounding-sphere exit, fixed-step sign test of the radial form g (raycast_common.glsl)
// with finer steps near the centre, and refinement of the first sign change.
#extension GL_GOOGLE_include_directive : require
#include "raycast_common.glsl"

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
    GlyphRay ray;
    if (!glyph_ray(1.0 + frame.march.w, ray)) {
        discard;
    }
    vec3 mid = ray.mid;
    vec3 dir = ray.dir;
    float s = ray.s_start;
    float s_end = ray.half_chord;

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
    emit_hit(ray, s_hit);
}
