#version 450
// Streamlines drawn as lines (src/render/peaks.rs, `PeakSet::lines`): the flat ribbon of
// glsl/peaks.vert (GLYPHCAST_LINES), in the segment's colour, unlit, at the depth the
// rasteriser interpolates between the axis's ends. The depth test runs before this
// shader (early fragment tests), so a fragment behind a nearer glyph, tube or line costs
// nothing more: what makes a whole brain's 10^7 segments affordable on lavapipe, where
// the exact tubes (peaks.frag, which writes gl_FragDepth) shade every fragment. Not
// exact: the ribbon faces the screen, and a glyph's lobe and a line cut each other at
// the axis's depth, not at the tube's surface. The ray distance written to the depth
// map is that of the ray's point nearest the segment.
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"
#include "pixel_ray.glsl"

layout(early_fragment_tests) in;

layout(location = 0) flat in vec4 v_a_radius;
layout(location = 1) flat in vec3 v_b;
layout(location = 2) flat in vec3 v_color;

layout(location = 0) out vec4 out_color;
#ifndef GLYPHCAST_NO_DISTANCE
layout(location = 1) out float out_distance;
#endif

void main() {
    out_color = vec4(v_color, 1.0);
#ifndef GLYPHCAST_NO_DISTANCE
    vec3 origin, dir;
    pixel_ray(origin, dir);
    // The segment's point nearest the ray (its parameter clamped to the segment), and
    // the ray's point nearest that: the part of a - origin + s axis across the ray is
    // shortest at s, and the distance along the ray follows.
    vec3 w0 = v_a_radius.xyz - origin;
    vec3 axis = v_b - v_a_radius.xyz;
    vec3 w_across = w0 - dot(w0, dir) * dir;
    vec3 axis_across = axis - dot(axis, dir) * dir;
    float across = dot(axis_across, axis_across);
    float s = across > 1e-12 * dot(axis, axis)
        ? clamp(-dot(w_across, axis_across) / across, 0.0, 1.0)
        : 0.5;
    float t = dot(w0 + s * axis, dir);
    out_distance = max(t, 0.0);
#endif
}
