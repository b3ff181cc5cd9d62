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
// Half extents along the box frame's ten diagonals, in units of center_radius.w
// (src/glyph/proxy.rs, diagonal_directions): the faces' (a0 + a1, a0 - a1, a1 + a2,
// a1 - a2), (a0 + a2, a0 - a2) and the corners' (a0 + a1 + a2, a0 + a1 - a2),
// (a0 - a1 + a2, a0 - a1 - a2).
layout(location = 3) in vec4 hull_a;
layout(location = 4) in vec4 hull_b;
layout(location = 5) in vec4 hull_c;

// false: the cube around the bounding sphere (the sphere impostor's proxy).
layout(constant_id = 0) const bool ORIENTED_BOX = true;
// true (--proxy hull): each glyph is drawn as an octagon around the outline of its
// 26-sided polytope (OUTLINE_INDICES of src/render/raycast.rs); false: as its box
// (CUBE_INDICES). A constant, so that the box's pipelines leave the outline's code out.
layout(constant_id = 2) const bool OUTLINE = false;
// true (--proxy pieces, with OUTLINE): each glyph is drawn as eight octagons, one around
// the outline of each of its pieces (glsl/pieces.glsl; PIECES_INDICES of
// src/render/raycast.rs), each at its piece's nearest depth.
layout(constant_id = 3) const bool PIECES = false;

// The pieces' words of every glyph of the batch (PIECE_WORDS each: the frame's
// quaternion, then four words per piece; a placeholder word where the batch draws no
// pieces).
layout(std430, set = 0, binding = 6) readonly buffer Pieces {
    uint piece_words[];
};
const uint PIECE_WORDS = 36u;

// The shared variant and the robust methods' (GLYPHCAST_GLYPH_INDEX, build.rs) pass the
// glyph's index; exact and fixed need only the coefficients.
#if !defined(GLYPH_MONOMIALS) || defined(GLYPHCAST_GLYPH_INDEX)
#define RAYCAST_GLYPH_INDEX
layout(location = 0) flat out uint v_glyph;
#else
// The exact method's pieces (PIECES): the fragment's piece's words, its index in the
// twentieth number (glsl/pieces.glsl); the piece's frame goes as the box's rotation.
layout(location = 0) flat out uvec4 v_piece_words;
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

vec3 rotate_inverse(vec4 q, vec3 v) {
    return v - 2.0 * cross(q.xyz, q.w * v - cross(q.xyz, v));
}

#include "pieces.glsl"

// The polytope's supports (units of center_radius.w) by direction_code of their
// integer direction (glsl/pieces.glsl): the glyph's 26-sided polytope's, symmetric about
// the centre, or (PIECES) the piece's in the piece's own octant (directions reflected
// by piece_signs_now).
float dop_h[27];
vec3 piece_signs_now;
// The drawn piece's words, its index set (PIECES).
uvec4 piece_words_now;

// The polytope's support along the frame direction of integer steps m (components -1,
// 0, 1; normalised).
float dop_support(vec3 m) {
    return dop_h[direction_code(PIECES ? piece_signs_now * m : m)];
}

// dop_h of the glyph's 26-sided polytope: the box's three extents, then the ten
// diagonals' (a0 + a1, a0 - a1, a1 + a2, a1 - a2, a0 + a2, a0 - a2, then a0 + a1 + a2,
// a0 + a1 - a2, a0 - a1 + a2, a0 - a1 - a2), each for both signs.
void hull_supports(vec3 extent, vec4 diagonals[3]) {
    float e[13];
    e[0] = extent.x;
    e[1] = extent.y;
    e[2] = extent.z;
    for (int i = 0; i < 10; ++i) {
        e[3 + i] = diagonals[i / 4][i % 4];
    }
    const vec3 axes[13] = vec3[13](
        vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0),
        vec3(1.0, 1.0, 0.0), vec3(1.0, -1.0, 0.0), vec3(0.0, 1.0, 1.0), vec3(0.0, 1.0, -1.0),
        vec3(1.0, 0.0, 1.0), vec3(1.0, 0.0, -1.0),
        vec3(1.0, 1.0, 1.0), vec3(1.0, 1.0, -1.0), vec3(1.0, -1.0, 1.0),
        vec3(1.0, -1.0, -1.0));
    dop_h[13] = 0.0;
    for (int k = 0; k < 13; ++k) {
        dop_h[direction_code(axes[k])] = e[k];
        dop_h[direction_code(-axes[k])] = e[k];
    }
}

// dop_h of a piece of words `words`, in its octant's reflected directions. (Loops, not
// unrolled: the box's pipelines compile this shader too, and its size is what they pay
// for code they never run.)
void piece_supports(uvec4 words) {
    for (int c = 0; c < 27; ++c) {
        dop_h[c] = piece_value(words, PIECE_SLOT[c]);
    }
}

// For a direction w of the polytope's frame (any length), a point V of that frame with
// w . V an upper bound of the polytope's support along w: w is a non-negative
// combination of an axis, a face diagonal and a corner diagonal of its own octant (the
// cone of the three that holds it), and V lies on the three planes x . n = support(n)
// of those three directions. The polytope lies in the convex hull of all such points,
// and its outline on the screen in the hull's.
vec3 hull_point(vec3 w) {
    vec3 a = abs(w);
    vec3 sg = vec3(w.x < 0.0 ? -1.0 : 1.0, w.y < 0.0 ? -1.0 : 1.0, w.z < 0.0 ? -1.0 : 1.0);
    int i0 = 0;
    int i1 = 1;
    int i2 = 2;
    if (a[i1] > a[i0]) { int t = i0; i0 = i1; i1 = t; }
    if (a[i2] > a[i1]) { int t = i1; i1 = i2; i2 = t; }
    if (a[i1] > a[i0]) { int t = i0; i0 = i1; i1 = t; }
    vec3 axis = vec3(0.0);
    axis[i0] = sg[i0];
    vec3 face = axis;
    face[i1] = sg[i1];
    float x = dop_support(axis);
    float y = 1.4142135 * dop_support(face) - x;
    float z = 1.7320508 * dop_support(sg) - x - y;
    vec3 v;
    v[i0] = sg[i0] * x;
    v[i1] = sg[i1] * y;
    v[i2] = sg[i2] * z;
    return v;
}

// Row i of the view-projection matrix.
vec4 view_proj_row(int i) {
    return vec4(frame.view_proj[0][i], frame.view_proj[1][i], frame.view_proj[2][i],
                frame.view_proj[3][i]);
}

// The coordinate along `ds` (a direction of the window scaled by its pixel size) of the
// window position of world point p, in front of the eye.
float window_along(vec2 ds, vec3 p) {
    vec4 clip = frame.view_proj * vec4(p, 1.0);
    return dot(ds, clip.xy) / clip.w;
}

// The least s such that every point of the box in front of the near plane lies where
// (window position along ds) <= s: the largest position of the box's corners in front of
// it and of the points where its edges cross it (for a glyph that the near plane cuts).
float clipped_box_line(vec2 ds, vec3 centre, vec3 half_axes[3]) {
    float near = frame.viewport.z;
    float s = -3.4e38;
    [[dont_unroll]] for (uint corner = 0u; corner < 8u; ++corner) {
        vec3 unit = vec3(corner & 1u, (corner >> 1) & 1u, (corner >> 2) & 1u) * 2.0 - 1.0;
        vec3 p = centre + unit.x * half_axes[0] + unit.y * half_axes[1] + unit.z * half_axes[2];
        float depth = dot(frame.fwd.xyz, p - frame.eye.xyz);
        if (depth >= near) {
            s = max(s, window_along(ds, p));
        }
        // The edges from this corner towards the corners of higher index.
        [[dont_unroll]] for (int axis = 0; axis < 3; ++axis) {
            if (unit[axis] < 0.0) {
                vec3 q = p + 2.0 * half_axes[axis];
                float depth_q = dot(frame.fwd.xyz, q - frame.eye.xyz);
                if ((depth - near) * (depth_q - near) < 0.0) {
                    vec3 crossing = mix(p, q, (near - depth) / (depth_q - depth));
                    s = max(s, window_along(ds, crossing));
                }
            }
        }
    }
    return s;
}

// The window position along ds (a direction of the window scaled by its pixel size) of
// the hull's point for the plane through the eye at s, and whether that point lies in
// front of the eye (the position means nothing otherwise).
float hull_reach(vec2 ds, float s, vec4 rotation, vec3 centre, float radius, out bool ahead) {
    vec4 plane = ds.x * view_proj_row(0) + ds.y * view_proj_row(1);
    vec3 normal = plane.xyz - s * view_proj_row(3).xyz;
    vec3 v = rotate(rotation, hull_point(rotate_inverse(rotation, normal)));
    vec4 clip = frame.view_proj * vec4(centre + radius * v, 1.0);
    ahead = clip.w > 0.0;
    return dot(ds, clip.xy) / clip.w;
}

// The least s found such that the glyph lies where (window position along ds) <= s, for
// a glyph wholly in front of the near plane. A plane through the eye bounds the glyph
// where the hull's point for that plane's normal lies on its inner side; from the
// centre's position, each step moves s to the position of the hull's point for the plane
// at s (the support of an orthographic view at once; a perspective view's plane turns a
// little), and a step whose point lies within s proves s. Without such a step, 3.4e38
// (the caller takes the part of the box in front of the near plane instead).
float outline_line(vec2 ds, vec4 rotation, vec3 centre, float radius) {
    float s = window_along(ds, centre);
    float proven = 3.4e38;
    bool ahead = true;
    [[dont_unroll]] for (int step = 0; step < 3; ++step) {
        bool ahead_now;
        float reached = hull_reach(ds, s, rotation, centre, radius, ahead_now);
        ahead = ahead && ahead_now;
        if (ahead && reached <= s) {
            proven = min(proven, s);
        }
        // A little beyond the point reached, so that a support met at a vertex of the
        // polytope (a piece's apex at the centre) is proven by the next step whatever
        // the rounding: a hundredth of a pixel.
        s = reached + 0.01 + 1.0e-6 * abs(reached);
    }
    return proven;
}

// s, the position along window direction d of an edge (in window units times pixels),
// kept within a margin outside the window: an edge beyond it shows the same pixels.
float window_clamped(vec2 d, vec2 pixels, float s) {
    float reach = abs(d.x * pixels.x) + abs(d.y * pixels.y);
    float margin = 0.125 * reach + 16.0;
    return clamp(s, -reach - margin, reach + margin);
}

// The window direction (scaled to pixels) of the octagon's edge k (k = 0..7): 45
// degrees apart, clockwise in pixel coordinates, so that the octagon's vertices run the
// way the rasteriser takes as front facing, whatever the sign of the viewport's height.
vec2 outline_direction(uint k) {
    float angle = -0.78539816 * float(k);
    return vec2(cos(angle), sin(angle));
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
    // With the pieces, vertex 8 p + k is vertex k of piece p's octagon.
    uint piece = 0u;
    if (PIECES) {
        piece = corner >> 3;
        corner &= 7u;
    }
    vec4 piece_frame = vec4(0.0);
    vec3 unit = vec3(corner & 1u, (corner >> 1) & 1u, (corner >> 2) & 1u) * 2.0 - 1.0;

    // The hull's outline (OUTLINE, --proxy hull): vertex k of an octagon around the
    // outline on the screen of the glyph's 26-sided polytope, where its edges k and k + 1
    // meet, at the glyph's nearest depth along the view direction: in front of every hit
    // (the fragment shaders write depth_less, or depth_greater for standard depth). Where
    // the near plane cuts the glyph, the octagon goes around the part of its box in front
    // of the near plane, on the near plane.
    if (OUTLINE) {
        vec3 centre = center_radius.xyz;
        float radius = center_radius.w;
        vec4 diagonals[3] = ORIENTED_BOX ? vec4[3](hull_a, hull_b, hull_c)
                                         : vec4[3](vec4(1.0), vec4(1.0), vec4(1.0));
        // The polytope's frame, and the box whose part in front of the near plane bounds
        // it where the near plane cuts it: the glyph's, or its piece's (the piece's box
        // in the pieces' frame).
        vec4 outline_rotation = rotation;
        vec3 box_centre = centre;
        vec3 box_axes[3] = half_axes;
        if (!PIECES) {
            hull_supports(extent, diagonals);
        } else {
            uint base = uint(gl_InstanceIndex) * PIECE_WORDS;
            piece_frame = normalize(uintBitsToFloat(uvec4(piece_words[base],
                piece_words[base + 1u], piece_words[base + 2u], piece_words[base + 3u])));
            uint w = base + 4u + 4u * piece;
            piece_words_now = uvec4(piece_words[w], piece_words[w + 1u], piece_words[w + 2u],
                                    (piece_words[w + 3u] & 0xc0ffffffu) | (piece << 24));
            piece_signs_now = piece_signs(piece);
            piece_supports(piece_words_now);
            outline_rotation = piece_frame;
            vec3 hi = vec3(dop_support(vec3(1.0, 0.0, 0.0)), dop_support(vec3(0.0, 1.0, 0.0)),
                           dop_support(vec3(0.0, 0.0, 1.0)));
            vec3 lo = -vec3(dop_support(vec3(-1.0, 0.0, 0.0)),
                            dop_support(vec3(0.0, -1.0, 0.0)),
                            dop_support(vec3(0.0, 0.0, -1.0)));
            box_centre = centre + rotate(piece_frame, 0.5 * radius * (lo + hi));
            vec3 half_size = 0.5 * radius * (hi - lo);
            box_axes[0] = rotate(piece_frame, vec3(half_size.x, 0.0, 0.0));
            box_axes[1] = rotate(piece_frame, vec3(0.0, half_size.y, 0.0));
            box_axes[2] = rotate(piece_frame, vec3(0.0, 0.0, half_size.z));
        }
        vec3 toward = rotate(outline_rotation,
                             hull_point(rotate_inverse(outline_rotation, -frame.fwd.xyz)));
        float nearest = dot(frame.fwd.xyz, centre - frame.eye.xyz)
                      + radius * dot(frame.fwd.xyz, toward);
        bool cut = frame.eye.w < 0.5 && nearest <= frame.viewport.z * 1.001;
        vec2 pixels = 1.0 / frame.viewport.xy;
        // The two edges that meet at this vertex, by one loop each (one copy of the
        // code: the pipelines' creation on lavapipe grows with every inlined copy).
        vec2 d[2] = vec2[2](outline_direction(corner), outline_direction((corner + 1u) & 7u));
        float edge[2];
        [[dont_unroll]] for (int e = 0; e < 2; ++e) {
            vec2 ds = d[e] * pixels;
            float line = cut ? 3.4e38 : outline_line(ds, outline_rotation, centre, radius);
            edge[e] = line > 3.0e38 ? clipped_box_line(ds, box_centre, box_axes) : line;
        }
        vec2 d0 = d[0];
        vec2 d1 = d[1];
        float s0 = edge[0];
        float s1 = edge[1];
        // Edges far outside the window are brought to just outside it (what the window
        // shows of the octagon stays the same): near a tiny near plane (a camera among
        // the glyphs) positions reach 1e9 window widths, past what the rasteriser takes.
        s0 = window_clamped(d0, pixels, s0);
        s1 = window_clamped(d1, pixels, s1);
        // p = window * pixels with d0 . p = s0 and d1 . p = s1.
        float det = d0.x * d1.y - d0.y * d1.x;
        vec2 p = vec2(s0 * d1.y - s1 * d0.y, d0.x * s1 - d1.x * s0) / det;
        vec4 near_clip = frame.view_proj * vec4(frame.eye.xyz + nearest * frame.fwd.xyz, 1.0);
        float depth = cut ? frame.window.z : near_clip.z / near_clip.w;
        gl_Position = vec4(p / pixels, depth, 1.0);
        if (min(s0, s1) < -1.0e38) {
            // No part of the box in front of the near plane: nothing drawn.
            gl_Position = vec4(0.0, 0.0, -2.0, 1.0);
        }
    } else {
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
    }
#ifdef RAYCAST_GLYPH_INDEX
    v_glyph = gl_InstanceIndex;
#endif
    v_center_radius = center_radius;
    // The pieces clip the ray in their own frame; the box's clip becomes the cube
    // around the sphere in that frame, which clips nothing.
    v_box_rotation = PIECES ? piece_frame : rotation;
    v_box_extent = PIECES ? vec3(1.0) : extent;
#ifndef RAYCAST_GLYPH_INDEX
    v_piece_words = PIECES ? piece_words_now : uvec4(0u);
#endif
#ifdef GLYPH_MONOMIALS
    // Flat outputs come from a triangle's first (provoking) vertex, corner 0 or 7 (the
    // outline's triangles all start at vertex 0); the other corners' are never read.
    // (Loading for every vertex of 36 made the vertex stage of a million glyphs 7 times
    // slower than their drawing on lavapipe.)
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
