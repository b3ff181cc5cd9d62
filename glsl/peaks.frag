#version 450
// Fibre peaks (src/render/peaks.rs): the pixel's ray against one capsule, in closed form,
// step for step as the float64 reference (src/glyph/capsule.rs, which explains them):
// from the ray's point closest to the capsule's midpoint, the entry into the infinite
// cylinder about the axis, else the entry into the hemisphere at the end beyond which
// that lies. Shaded as the glyphs are (Blinn-Phong of the frame's lighting) in the
// capsule's own colour; the ray distance goes to the depth map as a glyph's does.
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"
#include "pixel_ray.glsl"
#include "shading.glsl"

layout(location = 0) flat in vec4 v_a_radius;
layout(location = 1) flat in vec3 v_b;
layout(location = 2) flat in vec3 v_color;

layout(location = 0) out vec4 out_color;
#ifndef GLYPHCAST_NO_DISTANCE
layout(location = 1) out float out_distance;
#endif
layout(depth_less) out float gl_FragDepth;  // reversed depth: hits lie behind the box

// capsule.rs PARALLEL, for float32.
const float PARALLEL = 1e-10;

void main() {
    vec3 origin, dir;
    pixel_ray(origin, dir);
    vec3 a = v_a_radius.xyz;
    float r = v_a_radius.w;
    vec3 axis = 0.5 * (v_b - a);
    vec3 m = a + axis;
    float h = length(axis);
    vec3 u = h > 0.0 ? axis / h : vec3(0.0, 0.0, 1.0);
    float t_mid = dot(m - origin, dir);
    vec3 q0 = origin + t_mid * dir - m;
    vec3 q_across = q0 - dot(q0, u) * u;
    vec3 d_across = dir - dot(dir, u) * u;
    float qa = dot(d_across, d_across);
    float qb = dot(q_across, d_across);
    float qc = dot(q_across, q_across) - r * r;
    float end;
    float s;
    vec3 normal;
    bool side = false;
    if (qa < PARALLEL) {
        if (qc > 0.0) {
            discard;
        }
        end = dot(dir, u) > 0.0 ? -h : h;
    } else {
        float disc = qb * qb - qa * qc;
        if (disc < 0.0) {
            discard;
        }
        s = (-qb - sqrt(disc)) / qa;
        vec3 p = q0 + s * dir;
        float y = dot(p, u);
        side = abs(y) <= h;
        normal = p - y * u;
        end = y < 0.0 ? -h : h;
    }
    if (!side) {
        vec3 qe = q0 - end * u;
        float be = dot(qe, dir);
        float disc = be * be - (dot(qe, qe) - r * r);
        if (disc < 0.0) {
            discard;
        }
        s = -be - sqrt(disc);
        normal = qe + s * dir;
    }
    float distance = t_mid + s;
    if (distance < 0.0) {
        discard;
    }
    gl_FragDepth = window_depth(origin + distance * dir);
    out_color = vec4(blinn_phong(v_color, normalize(normal), -dir), 1.0);
#ifndef GLYPHCAST_NO_DISTANCE
    out_distance = distance;
#endif
}
