// What every ray-casting method shares (Hlawitschka et al., Sec. 4): the pixel's ray in the
// glyph's normalised local frame, the radial sign function, refinement of a bracketed
// sign change, and the shading and outputs of a hit. A method's fragment shader includes
// this file and only decides how to find the first sign change along the chord. The
// parts without fragment inputs and outputs (the ray in the glyph's frame, g, the shading
// of a hit) are in glyph_ray.glsl, which the compute ray caster shares.
//
// The sign function is the radial form g(q) = h(f(q/|q|)) + offset - |q| (h = abs, or
// max(., 0) to hide negative lobes), which has the zero set of the paper's Eq. 3 but stays
// well scaled near the centre.
#include "frame.glsl"
#include "glyph_function.glsl"
#include "pixel_ray.glsl"
#include "shading.glsl"
#include "glyph_ray.glsl"

#ifndef GLYPHCAST_RECEIVER
// (The underlay's shadow receiver, raycast_exact.frag's GLYPHCAST_RECEIVER variant,
// draws the underlay's planes: it has no glyph's inputs, and no depth of its own.)
// The glyph index is declared only where it is read: the vertex variant of exact and
// fixed does not write it (unoptimised SPIR-V keeps every declared input, and an input
// no stage writes is a validation error); that variant's location 0 carries the pieces'
// words instead.
#ifdef RAYCAST_READS_GLYPH_INDEX
layout(location = 0) flat in uint v_glyph;
#else
// The fragment's piece's words (--proxy pieces; raycast.vert); its frame comes as
// v_box_rotation.
layout(location = 0) flat in uvec4 v_piece_words;
#endif
layout(location = 1) flat in vec4 v_center_radius;
layout(location = 2) flat in vec4 v_box_rotation;  // box to world (raycast.vert)
layout(location = 3) flat in vec3 v_box_extent;    // in units of v_center_radius.w
// The glyph's monomial coefficients (glyph_c), from raycast.vert. On lavapipe a fragment
// shader reads a storage buffer at a per-fragment index as a gather per lane, and the
// coefficients' loads alone were a quarter of the exact method's time; flat inputs are
// set up once per triangle. 4 + GLYPH_COEFF_VEC4S locations (27 at order 12).
const int GLYPH_COEFF_VEC4S = (GLYPH_MONOMIALS + 3) / 4;
layout(location = 4) flat in vec4 v_coeffs[GLYPH_COEFF_VEC4S];
#endif
#include "pieces.glsl"
// true (--proxy pieces): the ray is clipped to the fragment's piece as well.
layout(constant_id = 3) const bool PIECES = false;

layout(location = 0) out vec4 out_color;
#ifndef GLYPHCAST_NO_DISTANCE  // build.rs: the variant for a colour attachment only
layout(location = 1) out float out_distance;
#endif
#ifndef GLYPHCAST_RECEIVER
#ifndef GLYPHCAST_GLYPH_RECEIVER
// (The glyphs' shadow receiver, raycast_exact.frag's GLYPHCAST_GLYPH_RECEIVER variant,
// shades hits found before: it writes colour alone.)
layout(depth_less) out float gl_FragDepth;  // reversed depth: hits lie behind the proxy
#endif

#ifndef GLYPHCAST_GLYPH_RECEIVER
// What the later passes of a frame know of visibility (src/render/visibility.rs): the
// work counters; the depth of the glyphs drawn before the pass, per pixel (a copy of the
// depth attachment, which the pass's winners update and which is copied back after it);
// and per pixel, during the first stage of a later pass the gate of its second stage,
// during the second the nearest ray distance the pass's glyphs reach (the first stage's
// result). The header holds the row length (x), the visibility word (y:
// VISIBILITY_SHADE_NEAREST, VISIBILITY_GATE, VISIBILITY_COUNT, VISIBILITY_EARLY_OUT) and
// the target's first pixel (z, w: a host's scissor offset; 0 for the headless targets).
// The word is read from a storage buffer, not pushed: lavapipe compiles a shader again
// for each value of a push constant that steers a branch.
layout(std430, set = 1, binding = 0) buffer WorkCounters {
    uint work_counters[4];  // WORK_FRAGMENTS, WORK_EVALUATIONS
};
layout(std430, set = 1, binding = 1) buffer KnownDepth {
    uvec4 known_header;
    uint known_words[];  // the known depths' bits
};
layout(std430, set = 1, binding = 2) buffer NearestDistance {
    uint nearest_words[];  // the gate's bits, then the nearest distances'
};

// false: the pipeline of the frames whose visibility word is 0 (no culling, no counting:
// most frames), in which the visibility code below is compiled out. A device that runs
// skipped code masked (lavapipe of Mesa 22.3) paid for it in every fragment: 12 % of a
// flat field's frame (src/render/raycast.rs, VISIBILITY_CONSTANT).
layout(constant_id = 1) const bool VISIBILITY = true;

// This fragment's pixel among the known depths.
uint known_index() {
    uvec2 pixel = uvec2(gl_FragCoord.xy) - known_header.zw;
    return pixel.y * known_header.x + pixel.x;
}

// Adds one to work counter `counter` when the pass counts its work.
void count_work(int counter) {
    if (VISIBILITY && (known_header.y & uint(VISIBILITY_COUNT)) != 0u) {
        atomicAdd(work_counters[counter], 1u);
    }
}

// How much farther than a hit its gate lies, relative to its depth (and at least 8 units
// in the last place): the rasterised depth of the glyph's box face, which is at least as
// near as the hit, may round a little farther than the shader's depth of the hit.
const float GATE_MARGIN = 1.0e-5;

// In the first stage of a later pass (VISIBILITY_GATE): a hit nearer than the known
// depth opens the gate of the second stage at its pixel (the depth that stage's boxes
// are tested against before their fragments run, copied into the depth attachment
// between the stages) a little beyond itself. The gate of a pixel ends as that of the
// pass's nearest such hit; a pixel without one keeps its gate shut (the near plane), so
// that the second stage launches no fragment there.
void open_gate(uint index, float depth, bool reversed) {
    uint bits = floatBitsToUint(max(depth, 0.0));
    // Kept inside the depth range and off the shut value (a copy into the depth
    // attachment takes depths in [0, 1]), should a hit lie in front of the near plane.
    if (reversed) {
        float gate = min(depth * (1.0 - GATE_MARGIN), uintBitsToFloat(max(bits, 8u) - 8u));
        uint shut = floatBitsToUint(1.0);
        gate = clamp(gate, 0.0, uintBitsToFloat(shut - 1u));
        uint was = atomicCompSwap(nearest_words[index], shut, floatBitsToUint(gate));
        if (was != shut) {
            atomicMax(nearest_words[index], floatBitsToUint(gate));
        }
    } else {
        float gate = max(depth * (1.0 + GATE_MARGIN), uintBitsToFloat(bits + 8u));
        gate = clamp(gate, uintBitsToFloat(0x00800000u), 1.0);  // the least normal float
        uint was = atomicCompSwap(nearest_words[index], 0u, floatBitsToUint(gate));
        if (was != 0u) {
            atomicMin(nearest_words[index], floatBitsToUint(gate));
        }
    }
}

// In a pass drawn front to back with early outs (VISIBILITY_EARLY_OUT): whether this
// fragment's box face lies behind the known depth of its pixel (the nearest hit that the
// pass's fragments have found there so far, which each hit raises: shows_hit) by more
// than the rounding of the face's rasterised depth (GATE_MARGIN, at least 8 units in the
// last place). Its hit, which lies at or behind the face, would then fail the depth
// test, so the fragment may skip the root isolation. A device that jumps over code no
// lane of a batch runs (a GPU, lavapipe of Mesa 25) saves it where a whole batch of
// pixels is hidden; in the other fragments the test changes nothing.
bool hidden_by_known() {
    if (!VISIBILITY || (known_header.y & uint(VISIBILITY_EARLY_OUT)) == 0u) {
        return false;
    }
    float known = uintBitsToFloat(known_words[known_index()]);
    uint bits = floatBitsToUint(known);
    if (frame.window.z > 0.5) {
        float edge = min(known * (1.0 - GATE_MARGIN), uintBitsToFloat(max(bits, 8u) - 8u));
        return gl_FragCoord.z < edge;
    }
    float edge = max(known * (1.0 + GATE_MARGIN), uintBitsToFloat(bits + 8u));
    return gl_FragCoord.z > edge;
}

// In the stages of a later pass: whether this hit is the one the pixel shows. In the
// first stage (VISIBILITY_GATE) every hit is kept (the blending keeps the nearest
// distance) and opens the gate where it is nearer than the known depth. In the second
// (VISIBILITY_SHADE_NEAREST) it must be the nearest hit of the pass's glyphs (the first
// stage's distance, the same arithmetic giving the same bits) and nearer than what the
// earlier passes drew (reversed depth: larger); the winner's depth replaces the known
// one, which is copied into the depth attachment after the pass.
bool shows_hit(float distance, float depth) {
    if (!VISIBILITY) {
        return true;
    }
    uint word = known_header.y;
    uint stages = uint(VISIBILITY_SHADE_NEAREST | VISIBILITY_GATE | VISIBILITY_EARLY_OUT);
    if ((word & stages) == 0u) {
        return true;
    }
    uint index = known_index();
    bool reversed = frame.window.z > 0.5;
    if ((word & uint(VISIBILITY_EARLY_OUT)) != 0u) {
        // Every hit is a surface the pixel shows or hides behind a nearer one: it
        // raises the known depth (non-negative floats order as their bits).
        uint bits = floatBitsToUint(max(depth, 0.0));
        if (reversed) {
            atomicMax(known_words[index], bits);
        } else {
            atomicMin(known_words[index], bits);
        }
        return true;
    }
    float known = uintBitsToFloat(known_words[index]);
    bool nearer = reversed ? depth > known : depth < known;
    if ((word & uint(VISIBILITY_GATE)) != 0u) {
        if (nearer) {
            open_gate(index, depth, reversed);
        }
        return true;
    }
    if (distance != uintBitsToFloat(nearest_words[index]) || !nearer) {
        return false;
    }
    known_words[index] = floatBitsToUint(depth);
    return true;
}
#endif

// glyph_c of this fragment's glyph (glyph_load of the vertex shader, multiplicities
// folded in).
void glyph_load_inputs() {
    [[unroll]] for (int k = 0; k < GLYPH_MONOMIALS; ++k) {
        glyph_c[k] = v_coeffs[k / 4][k % 4];
    }
}

// The ray through this fragment's pixel against its glyph's sphere of the given radius
// and its box (glyph_ray_clip).
bool glyph_ray_within(float radius, out GlyphRay ray) {
#ifndef GLYPHCAST_GLYPH_RECEIVER
    count_work(WORK_FRAGMENTS);
#endif
    pixel_ray(ray.origin, ray.dir);
    bool met = glyph_ray_clip(v_center_radius, v_box_rotation, v_box_extent, radius, ray);
    if (PIECES) {
#ifndef RAYCAST_READS_GLYPH_INDEX
        piece_clip(v_box_rotation, v_piece_words, radius, ray.mid, ray.dir, ray.s_start,
                   ray.s_end);
#endif
        met = met && ray.s_start < ray.s_end;
    }
    return met;
}

// The ray against the glyph's bounding sphere.
bool glyph_ray(out GlyphRay ray) {
    return glyph_ray_within(1.0 + frame.march.w, ray);
}

#endif

// Refines a bracket [s0, s1] with g(s0) <= 0 < g(s1) along q(s) = mid + s * dir.
float refine(vec3 mid, vec3 dir, float s0, float g0, float s1, float g1) {
    int mode = frame.modes.x;
    if (mode == REFINE_BISECT) {
        for (int i = 0; i < frame.modes.y; ++i) {
            float sm = 0.5 * (s0 + s1);
            float gm = inside(mid + sm * dir);
            if (gm > 0.0) { s1 = sm; g1 = gm; } else { s0 = sm; g0 = gm; }
        }
        return 0.5 * (s0 + s1);
    } else if (mode == REFINE_INTERP) {
        return s0 + (s1 - s0) * (g0 / (g0 - g1));
    } else if (mode == REFINE_SECANT) {
        // Regula falsi, Illinois variant: halve the weight of an end that stays put.
        int stuck = 0;
        for (int i = 0; i < frame.modes.y; ++i) {
            float sm = s0 + (s1 - s0) * (g0 / (g0 - g1));
            float gm = inside(mid + sm * dir);
            if (gm > 0.0) {
                s1 = sm; g1 = gm;
                if (stuck == 1) { g0 *= 0.5; }
                stuck = 1;
            } else {
                s0 = sm; g0 = gm;
                if (stuck == -1) { g1 *= 0.5; }
                stuck = -1;
            }
        }
        return s0 + (s1 - s0) * (g0 / (g0 - g1));
    }
    return s1;
}

#if !defined(GLYPHCAST_RECEIVER) && !defined(GLYPHCAST_GLYPH_RECEIVER)
// Colour, depth and ray distance of the hit at q(s_hit), lit by the share `visibility`
// of the light, to the fragment's outputs.
void shade_hit_visible(GlyphRay ray, float s_hit, float visibility) {
    vec4 color;
    float depth;
    float distance;
    shade_surface_visible(ray, s_hit, visibility, color, depth, distance);
    if (!shows_hit(distance, depth)) {
        discard;
    }
    gl_FragDepth = depth;
    out_color = color;
#ifndef GLYPHCAST_NO_DISTANCE
    out_distance = distance;
#endif
}

// shade_hit_visible of a hit the whole light reaches.
void shade_hit(GlyphRay ray, float s_hit) {
    shade_hit_visible(ray, s_hit, 1.0);
}
#endif
