// What every ray-casting method shares: the pixel-centre ray in the glyph's normalised
// frame (where the glyph's bound is 1 + offset), the radial sign function g, and the
// shading and outputs of a hit. A method's fragment shader includes this file, finds the
// first crossing along the ray and hands it to emit_hit.
#include "frame.glsl"
#include "glyph_function.glsl"
#include "shading.glsl"

layout(location = 0) flat in uint v_glyph;
layout(location = 1) flat in vec4 v_center_radius;

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_distance;
layout(depth_greater) out float gl_FragDepth;

float shape(float f) {
    return glyph_set.hide_negative != 0u ? max(f, 0.0) : abs(f);
}

// g(q) = h(f(q/|q|)) + offset - |q| (h = abs, or max(., 0) to hide negative lobes): the zero
// set of the seed's Eq. 3, but well scaled near the centre. g > 0 inside the glyph.
float inside(vec3 q) {
    float len = length(q);
    if (len < 1e-20) {
        return frame.march.w;
    }
    return shape(glyph_f(q / len)) + frame.march.w - len;
}

// The pixel-centre ray of the scene format's camera, in world space.
void pixel_ray(out vec3 origin, out vec3 dir) {
    vec2 s = vec2((2.0 * gl_FragCoord.x * frame.viewport.x - 1.0) * frame.right.w,
                  1.0 - 2.0 * gl_FragCoord.y * frame.viewport.y);
    vec3 offset = s.x * frame.right.xyz + s.y * frame.up.xyz;
    if (frame.eye.w > 0.5) {
        origin = frame.eye.xyz + offset;
        dir = frame.fwd.xyz;
    } else {
        origin = frame.eye.xyz;
        dir = normalize(frame.fwd.xyz + offset);
    }
}

// The ray in the glyph's local frame q = (p - c) / rho, parametrised by s from `mid`, the
// point closest to the centre (so mid . dir = 0 and q(s) = mid + s dir stays well
// conditioned however far the camera is).
struct GlyphRay {
    vec3 origin;      // world
    vec3 dir;         // unit, world and local
    float rho;        // world units per local unit
    float t_mid;      // local distance from the origin to mid
    vec3 mid;
    float half_chord; // of the sphere |q| = radius passed to glyph_ray
    float s_start;    // max(-half_chord, the ray origin): nothing behind the camera
};

// The ray of this fragment against the sphere |q| = radius; false if it misses the
// sphere or the sphere is behind the camera.
bool glyph_ray(float radius, out GlyphRay ray) {
    pixel_ray(ray.origin, ray.dir);
    // The box half-size is rho * (1 + offset): rho maps normalised glyph units to world units.
    ray.rho = v_center_radius.w / (1.0 + frame.march.w);
    vec3 o = (ray.origin - v_center_radius.xyz) / ray.rho;
    ray.t_mid = -dot(o, ray.dir);
    ray.mid = o + ray.t_mid * ray.dir;
    float half_chord2 = radius * radius - dot(ray.mid, ray.mid);
    ray.half_chord = sqrt(max(half_chord2, 0.0));
    ray.s_start = max(-ray.half_chord, -ray.t_mid);
    return half_chord2 > 0.0 && ray.s_start < ray.half_chord;
}

// Shades the hit at q(s_hit) and writes colour, depth and ray distance.
void emit_hit(GlyphRay ray, float s_hit) {
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
    vec4 clip = frame.view_proj * vec4(world, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w, 0.0, 1.0);

    vec3 base = glyph_color(q_dir, len * ray.rho);
    out_color = vec4(blinn_phong(base, normal, -ray.dir), 1.0);
    out_distance = distance;
}
