#version 450
// Instanced unit bounding box: one cube per glyph, scaled to the glyph's bounding radius
// (computed on the CPU and guaranteed to contain it). Faces wind counter-clockwise seen
// from outside; only front faces are drawn.
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"

layout(location = 0) in vec4 center_radius;

layout(location = 0) flat out uint v_glyph;
layout(location = 1) flat out vec4 v_center_radius;

// 12 triangles of the cube [-1, 1]^3, as corner indices (bit 0: x, bit 1: y, bit 2: z).
const uint CUBE[36] = uint[36](
    0, 2, 3, 0, 3, 1,   // -z
    4, 5, 7, 4, 7, 6,   // +z
    0, 1, 5, 0, 5, 4,   // -y
    2, 6, 7, 2, 7, 3,   // +y
    0, 4, 6, 0, 6, 2,   // -x
    1, 3, 7, 1, 7, 5    // +x
);

void main() {
    uint corner = CUBE[gl_VertexIndex];
    vec3 unit = vec3(corner & 1u, (corner >> 1) & 1u, (corner >> 2) & 1u) * 2.0 - 1.0;
    vec3 world = center_radius.xyz + center_radius.w * unit;
    gl_Position = frame.view_proj * vec4(world, 1.0);
    v_glyph = gl_InstanceIndex;
    v_center_radius = center_radius;
}
