#version 450
// Sphere impostor: the ray caster's instanced boxes, each shading the analytic sphere
// inscribed in its box (the glyph's bounding sphere). The same rasterised proxies, ray
// setup, shading and outputs as raycast_fixed.frag with no glyph function: the cost
// floor of any box-proxy ray caster. One shader serves every tensor layout.
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"
#include "pixel_ray.glsl"
#include "shading.glsl"

layout(location = 0) flat in uint v_glyph;
layout(location = 1) flat in vec4 v_center_radius;
// The box of raycast.vert, which this pass draws as the cube around the sphere.
layout(location = 2) flat in vec4 v_box_rotation;
layout(location = 3) flat in vec3 v_box_extent;

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_distance;
layout(depth_less) out float gl_FragDepth;  // reversed depth: hits lie behind the proxy

void main() {
    vec3 origin, dir;
    pixel_ray(origin, dir);
    // In units of the sphere's radius the sphere is |q| <= 1.
    float rho = v_center_radius.w;
    float t_mid;
    vec3 mid;
    ray_in_glyph_frame(origin, dir, v_center_radius.xyz, rho, t_mid, mid);
    float half_chord2 = 1.0 - dot(mid, mid);
    if (half_chord2 <= 0.0) {
        discard;
    }
    float half_chord = sqrt(half_chord2);
    // The entry point, or for a camera inside the sphere its exit (as the reference does).
    float s_hit = -half_chord >= -t_mid ? -half_chord : half_chord;
    if (t_mid + s_hit <= 0.0) {
        discard;
    }
    vec3 q = mid + s_hit * dir;

    float distance = (t_mid + s_hit) * rho;
    vec3 world = origin + distance * dir;
    gl_FragDepth = window_depth(world);

    vec3 normal = normalize(q);
    out_color = vec4(blinn_phong(glyph_color(normal, rho, 1.0), normal, -dir), 1.0);
    out_distance = distance;
}
