#version 450
// Fibre peaks (src/render/peaks.rs): one instanced, indexed draw of a box per capsule,
// the box of the capsule's axis (half length h) widened by its radius r: half extents
// h + r along the axis and r across it, in a right-handed frame, so that the faces of
// CUBE_INDICES wind counter-clockwise seen from outside and only front faces are drawn.
// A box that the near plane cuts is drawn inside out on the near plane, as raycast.vert
// does with glyph boxes (it explains why).
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"

layout(location = 0) in vec4 end_a_radius;  // xyz: one end of the axis; w: the radius
layout(location = 1) in vec4 end_b;         // xyz: the other end
layout(location = 2) in vec4 color;         // rgb: linear colour

layout(location = 0) flat out vec4 v_a_radius;
layout(location = 1) flat out vec3 v_b;
layout(location = 2) flat out vec3 v_color;

void main() {
    vec3 a = end_a_radius.xyz;
    float r = end_a_radius.w;
    vec3 axis = 0.5 * (end_b.xyz - a);
    float h = length(axis);
    vec3 u = h > 0.0 ? axis / h : vec3(0.0, 0.0, 1.0);
    vec3 helper = abs(u.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 e1 = normalize(cross(u, helper));
    vec3 e2 = cross(u, e1);
    // A margin of a hundredth of the radius: the box must hold the rounded surface.
    float across = 1.01 * r;
    vec3 half_axes[3] = vec3[3]((h + across) * u, across * e1, across * e2);
    uint corner = uint(gl_VertexIndex);
    vec3 unit = vec3(corner & 1u, (corner >> 1) & 1u, (corner >> 2) & 1u) * 2.0 - 1.0;
    vec3 center = a + axis;
    bool cut = false;
    if (frame.eye.w < 0.5) {
        float reach = abs(dot(frame.fwd.xyz, half_axes[0]))
                    + abs(dot(frame.fwd.xyz, half_axes[1]))
                    + abs(dot(frame.fwd.xyz, half_axes[2]));
        float nearest = dot(frame.fwd.xyz, center - frame.eye.xyz) - reach;
        cut = nearest <= frame.viewport.z * 1.001;
    }
    if (cut) {
        unit = -unit;
    }
    vec3 world = center + unit.x * half_axes[0] + unit.y * half_axes[1] + unit.z * half_axes[2];
    gl_Position = frame.view_proj * vec4(world, 1.0);
    if (cut) {
        gl_Position.z = gl_Position.w;
    }
    v_a_radius = end_a_radius;
    v_b = end_b.xyz;
    v_color = color.rgb;
}
