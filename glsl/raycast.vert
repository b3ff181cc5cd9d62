#version 450
// Instanced proxy box: one box per glyph, oriented and sized by guaranteed bounds computed
// on the CPU (src/glyph/proxy.rs), so that far fewer fragments run than with the cube
// around the bounding sphere. Faces wind counter-clockwise seen from outside; only front
// faces are drawn.
//
// A box that the near plane cuts (the camera inside it, or just in front of it) would lose
// the fragments of its clipped front faces: such a box is drawn inside out instead. Its
// corners are mirrored through the centre, which turns the far faces towards the camera,
// and they are put on the near plane (clip z = w * frame.window.z: depth 1, the near
// plane of reversed depth, or 0 for standard depth), which keeps their screen position.
// The far faces of a convex box cover exactly the pixels whose rays meet the box in front
// of the eye, and on the near plane they stay in front of every ray-cast depth (the
// fragment shaders write depth_less, or depth_greater for standard depth:
// render::shaders::for_depth).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "frame.glsl"
// Empty for the shared variant (the sphere impostor's); a tensor layout's variant passes
// its glyph's monomial coefficients to the fragment shader (raycast_common.glsl).
#include "glyph_function.glsl"

layout(location = 0) in vec4 center_radius;  // centre, radius of the bounding sphere
layout(location = 1) in vec4 box_rotation;   // unit quaternion (x, y, z, w), box to world
layout(location = 2) in vec4 box_extent;     // half extents, in units of center_radius.w

// false: the cube around the bounding sphere (the sphere impostor's proxy).
layout(constant_id = 0) const bool ORIENTED_BOX = true;

// The shared variant and the robust methods' (GLYPHCAST_GLYPH_INDEX, build.rs) pass the
// glyph's index; exact and fixed need only the coefficients.
#if !defined(GLYPH_MONOMIALS) || defined(GLYPHCAST_GLYPH_INDEX)
#define RAYCAST_GLYPH_INDEX
layout(location = 0) flat out uint v_glyph;
#endif
layout(location = 1) flat out vec4 v_center_radius;
layout(location = 2) flat out vec4 v_box_rotation;
layout(location = 3) flat out vec3 v_box_extent;
#ifdef GLYPH_MONOMIALS
layout(location = 4) flat out vec4 v_coeffs[(GLYPH_MONOMIALS + 3) / 4];
#endif

vec3 rotate(vec4 q, vec3 v) {
    return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v);
}

void main() {
    vec4 rotation = ORIENTED_BOX ? normalize(box_rotation) : vec4(0.0, 0.0, 0.0, 1.0);
    vec3 extent = ORIENTED_BOX ? box_extent.xyz : vec3(1.0);
    vec3 half_axes[3] = vec3[3](
        rotate(rotation, vec3(center_radius.w * extent.x, 0.0, 0.0)),
        rotate(rotation, vec3(0.0, center_radius.w * extent.y, 0.0)),
        rotate(rotation, vec3(0.0, 0.0, center_radius.w * extent.z)));

    // The vertex index is the box corner (bit 0: x, bit 1: y, bit 2: z); the pass draws
    // the 12 triangles by an index buffer (CUBE_INDICES of src/render/raycast.rs) that
    // starts every triangle at corner 0 or corner 7.
    uint corner = uint(gl_VertexIndex);
    vec3 unit = vec3(corner & 1u, (corner >> 1) & 1u, (corner >> 2) & 1u) * 2.0 - 1.0;

    // The box's nearest point along the view direction, against the near plane (with a
    // margin for the rounding of the projection). Orthographic views place the near plane
    // in front of every glyph.
    bool cut = false;
    if (frame.eye.w < 0.5) {
        float reach = abs(dot(frame.fwd.xyz, half_axes[0]))
                    + abs(dot(frame.fwd.xyz, half_axes[1]))
                    + abs(dot(frame.fwd.xyz, half_axes[2]));
        float nearest = dot(frame.fwd.xyz, center_radius.xyz - frame.eye.xyz) - reach;
        cut = nearest <= frame.viewport.z * 1.001;
    }
    if (cut) {
        unit = -unit;
    }
    vec3 world = center_radius.xyz
        + unit.x * half_axes[0] + unit.y * half_axes[1] + unit.z * half_axes[2];
    gl_Position = frame.view_proj * vec4(world, 1.0);
    if (cut) {
        gl_Position.z = frame.window.z * gl_Position.w;
    }
#ifdef RAYCAST_GLYPH_INDEX
    v_glyph = gl_InstanceIndex;
#endif
    v_center_radius = center_radius;
    v_box_rotation = rotation;
    v_box_extent = extent;
#ifdef GLYPH_MONOMIALS
    // Flat outputs come from a triangle's first (provoking) vertex, corner 0 or 7; the
    // other corners' are never read. (Loading for every vertex of 36 made the vertex
    // stage of a million glyphs 7 times slower than their drawing on lavapipe.)
    bool provoking = corner == 0u || corner == 7u;
    if (provoking) {
        glyph_load(gl_InstanceIndex);
    }
    [[unroll]] for (int i = 0; i < (GLYPH_MONOMIALS + 3) / 4; ++i) {
        vec4 c = vec4(0.0);
        [[unroll]] for (int j = 0; j < 4; ++j) {
            if (provoking && 4 * i + j < GLYPH_MONOMIALS) {
                c[j] = glyph_c[4 * i + j];
            }
        }
        v_coeffs[i] = c;
    }
#endif
}
