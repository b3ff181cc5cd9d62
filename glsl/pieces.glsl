// A glyph's eight pieces (--proxy pieces; src/glyph/pieces.rs): the octants of a frame
// turned to its largest lobe, each cut by guaranteed support planes along 19 directions
// (the 26-sided polytope's, less the seven that face into the octant, which its cone
// planes through the centre bound). raycast.vert draws each piece as an octagon around
// its outline; the fragment shaders clip their ray to the piece (piece_clip), so that a
// ray isolates roots only where it crosses its piece.
//
// A piece's supports travel as 19 six-bit numbers, five to a word in four words (the
// Rust side's PIECE_WORDS: the frame's quaternion, then four words per piece), each the
// support in 1/63 of the glyph's sphere radius, rounded up on the CPU. The twentieth
// number holds the piece's index (raycast.vert sets it). Four words fit the one flat
// uvec4 that the exact method's fragment shader has free (location 0, the robust
// methods' glyph index), so that the pieces take no varying a host's device might lack.

// The slot (six-bit number) of the support along the reflected integer direction r (components
// -1, 0, 1), by code (r.x + 1) + 3 (r.y + 1) + 9 (r.z + 1); -1 for a direction that
// faces into the octant (the cone planes bound it: support 0). The order is
// src/glyph/pieces.rs's PIECE_STEPS (a test there compares them).
const int PIECE_SLOT[27] = int[27](-1, -1, 16, -1, -1, 11, 17, 9, 13, -1, -1, 7, -1, -1, 0,
                                   8, 1, 3, 18, 10, 14, 12, 2, 5, 15, 4, 6);

// The pieces overlap across their cone planes by this much (units of the sphere radius),
// so that a root on a seam lies inside some piece's clipped interval whatever the
// rounding.
const float PIECE_SEAM = 1.0 / 512.0;

// The 13 directions of the 26-sided polytope, as integer steps on the frame's axes (each
// with its opposite).
const vec3 PIECE_AXES[13] = vec3[13](
    vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0),
    vec3(1.0, 1.0, 0.0), vec3(1.0, -1.0, 0.0), vec3(0.0, 1.0, 1.0), vec3(0.0, 1.0, -1.0),
    vec3(1.0, 0.0, 1.0), vec3(1.0, 0.0, -1.0),
    vec3(1.0, 1.0, 1.0), vec3(1.0, 1.0, -1.0), vec3(1.0, -1.0, 1.0), vec3(1.0, -1.0, -1.0));

// The signs of piece `piece`'s octant: bit k set is negative along axis k.
vec3 piece_signs(uint piece) {
    return vec3((piece & 1u) != 0u ? -1.0 : 1.0, (piece & 2u) != 0u ? -1.0 : 1.0,
                (piece & 4u) != 0u ? -1.0 : 1.0);
}

// The index of the piece whose words are `words`.
uint piece_index(uvec4 words) {
    return (words.w >> 24) & 7u;
}

// The code of the integer direction m (components -1, 0, 1): an index of 27.
int direction_code(vec3 m) {
    return int(m.x + 1.0) + 3 * int(m.y + 1.0) + 9 * int(m.z + 1.0);
}

// The support (units of the sphere radius) in slot `slot` of a piece's words (-1: a
// direction facing into the octant). Called with slots known when the shader is
// compiled (unrolled loops), so that no lane indexes a table of its own.
float piece_value(uvec4 words, int slot) {
    if (slot < 0) {
        return PIECE_SEAM;
    }
    return float((words[slot / 5] >> (6u * uint(slot % 5))) & 63u) * (1.0 / 63.0);
}

// [lo, hi] of the ray q(s) = mid + s dir (the glyph's local frame, in which its sphere
// has radius `radius`) narrowed to the piece of words `words` in the pieces' frame
// `frame` (unit quaternion, frame to glyph). The ray is reflected into the positive
// octant, where every slab's slots are constants.
void piece_clip(vec4 frame, uvec4 words, float radius, vec3 mid, vec3 dir,
                inout float lo, inout float hi) {
    vec3 signs = piece_signs(piece_index(words));
    vec3 m = signs * rotate_inverse(frame, mid);
    vec3 d = signs * rotate_inverse(frame, dir);
    [[unroll]] for (int k = 0; k < 13; ++k) {
        vec3 a = PIECE_AXES[k];
        float scale = inversesqrt(dot(a, a));
        float upper = piece_value(words, PIECE_SLOT[direction_code(a)]) * radius;
        float lower = -piece_value(words, PIECE_SLOT[direction_code(-a)]) * radius;
        float mk = dot(m, a) * scale;
        float dk = dot(d, a) * scale;
        dk = abs(dk) < 1e-20 ? 1e-20 : dk;
        float t0 = (lower - mk) / dk;
        float t1 = (upper - mk) / dk;
        lo = max(lo, min(t0, t1));
        hi = min(hi, max(t0, t1));
    }
}
