#version 450
// The paper's ray caster (Hlawitschka et al., Sec. 4): fixed-step sign test of the radial
// form g along the chord, finer steps near the centre, and refinement of the first sign
// change. Ray setup, g, refinement and shading live in raycast_common.glsl.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "raycast_common.glsl"

// The first s in [s_start, s_end] where g > 0, refined; false when the march finds none.
bool fixed_march(GlyphRay ray, out float s_hit) {
    float step = frame.march.x;
    float centre_step = step * frame.march.y;
    float centre_zone = frame.march.z;

    float s = ray.s_start;
    float g_prev = inside(ray.mid + s * ray.dir);
    float s_prev = s;
    s_hit = s;
    if (g_prev > 0.0) {
        return true;
    }
    for (int i = 0; i < frame.modes.w; ++i) {
        vec3 q = ray.mid + s_prev * ray.dir;
        s = min(s_prev + (length(q) < centre_zone ? centre_step : step), ray.s_end);
        float g = inside(ray.mid + s * ray.dir);
        if (g > 0.0) {
            s_hit = refine(ray.mid, ray.dir, s_prev, g_prev, s, g);
            return true;
        } else if (s >= ray.s_end) {
            break;
        }
        s_prev = s;
        g_prev = g;
    }
    return false;
}

void main() {
    GlyphRay ray;
    if (!glyph_ray(ray)) {
        discard;
    }
    count_work(WORK_EVALUATIONS);
    glyph_load_inputs();
    float s_hit;
    if (!fixed_march(ray, s_hit)) {
        discard;
    }
    shade_hit(ray, s_hit);
}
