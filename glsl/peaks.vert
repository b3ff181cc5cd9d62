#version 450
// Fibre peaks and streamline tubes (src/render/peaks.rs): one instanced, indexed draw of
// a screen quad per capsule (QUAD_INDICES: two triangles, corners 0 to 3). The quad is
// the rectangle, aligned with the capsule's projected axis, that holds the projections
// of the eight corners of the capsule's box (the axis, half length h, widened by its
// radius r: h + r along it, r across it), so it holds the capsule's projection; it lies
// at the depth of the box's nearest corner, in front of every point of the capsule, as
// the fragment shader's depth_less promise asks. Two triangles per capsule instead of
// the box's front faces: where capsules cover a few pixels each (a whole-brain
// tractogram), lavapipe's rasteriser spends its time per triangle, not per pixel.
// A capsule that reaches the near plane (perspective) gets the whole viewport at the
// near plane instead: its fragments find their hits (or none) as anywhere else.
//
// With GLYPHCAST_LINES (streamlines drawn as lines, glsl/lines.frag) the same quad is a
// flat ribbon: at least a pixel wide, its depth that of the axis's ends (the corners
// at the low end of the axis take end a's, those at the high end end b's), interpolated
// by the rasteriser and tested before the fragment shader runs. A line that reaches
// the near plane is not drawn (its quad is empty).
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
    vec3 center = a + axis;
    uint corner = uint(gl_VertexIndex) & 3u;
    bool cut = false;
    if (frame.eye.w < 0.5) {
        float reach = abs(dot(frame.fwd.xyz, half_axes[0]))
                    + abs(dot(frame.fwd.xyz, half_axes[1]))
                    + abs(dot(frame.fwd.xyz, half_axes[2]));
        float nearest = dot(frame.fwd.xyz, center - frame.eye.xyz) - reach;
        cut = nearest <= frame.viewport.z * 1.001;
    }
    vec2 unit = vec2(corner & 1u, (corner >> 1) & 1u) * 2.0 - 1.0;
    if (cut) {
#ifdef GLYPHCAST_LINES
        gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
#else
        // Reversed depth: the near plane is 1.
        gl_Position = vec4(unit, 1.0, 1.0);
#endif
    } else {
        vec4 pa = frame.view_proj * vec4(a, 1.0);
        vec4 pb = frame.view_proj * vec4(end_b.xyz, 1.0);
        vec2 along = pb.xy / pb.w - pa.xy / pa.w;
        float length_along = length(along);
        vec2 d = length_along > 1e-12 ? along / length_along : vec2(1.0, 0.0);
        vec2 n = vec2(-d.y, d.x);
        vec2 low = vec2(1e30);
        vec2 high = vec2(-1e30);
        float depth = 0.0;
        for (uint k = 0u; k < 8u; ++k) {
            vec3 s = vec3(k & 1u, (k >> 1) & 1u, (k >> 2) & 1u) * 2.0 - 1.0;
            vec3 world = center + s.x * half_axes[0] + s.y * half_axes[1] + s.z * half_axes[2];
            vec4 clip = frame.view_proj * vec4(world, 1.0);
            vec2 ndc = clip.xy / clip.w;
            vec2 coords = vec2(dot(ndc, d), dot(ndc, n));
            low = min(low, coords);
            high = max(high, coords);
            depth = max(depth, clip.z / clip.w);
        }
#ifdef GLYPHCAST_LINES
        // At least a pixel across and along (half a pixel each side of the middle).
        float least = max(frame.viewport.x, frame.viewport.y);
        vec2 middle = 0.5 * (low + high);
        low = min(low, middle - least);
        high = max(high, middle + least);
        depth = unit.x < 0.0 ? pa.z / pa.w : pb.z / pb.w;
#endif
        vec2 picked = mix(low, high, (unit + 1.0) * 0.5);
        gl_Position = vec4(picked.x * d + picked.y * n, depth, 1.0);
    }
    v_a_radius = end_a_radius;
    v_b = end_b.xyz;
    v_color = color.rgb;
}
