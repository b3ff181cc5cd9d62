// Robust ray casting by range arithmetic (Knoll et al., "Fast and robust ray tracing of
// general implicits on the GPU"; the paper's Sec. 5), shared by raycast_interval.frag and
// raycast_affine.frag, which define GLYPH_SEGMENT_RANGE as glyph_range_interval or
// glyph_range_affine before including this file.
//
// The chord [s_start, s_end] is walked front to back as the leaves of an implicit binary
// tree, without a stack: a segment is named by its depth d and index i (it is
// [s_start + i L 2^-d, s_start + (i + 1) L 2^-d]). A segment whose range of G lies below 0
// holds no point of the glyph and is skipped; otherwise it is halved (d + 1, 2i) until its
// world length is below `precision` pixels' footprint at its near end. Skipping moves to
// i + 1 and then climbs while i is even, to the next right sibling of an ancestor.
//
// A leaf that the range cannot clear is searched with the point sign function g at
// ROBUST_LEAF_SAMPLES points, and the first sign change is refined as the fixed method
// does. A leaf with no sign change is passed over rather than taken as a hit: the ranges
// over-estimate (IA to first order in the segment length, RAA to second order, and both
// by the dependency between f and |q|), so a leaf next to the surface often keeps 0 in
// its range without reaching the surface, and accepting it would thicken every glyph by
// up to a few leaves. What is given up is a root pair closer together than
// precision / ROBUST_LEAF_SAMPLES pixels along the ray: a graze within a fraction of a
// pixel of the silhouette. Every segment the range rejects is certified empty, so no
// sign change wider than that is ever missed, however thin the lobe.
// The robust methods read the glyph's stored entries, so they take its index
// (raycast.vert passes it in their vertex variant, GLYPHCAST_GLYPH_INDEX).
#define RAYCAST_READS_GLYPH_INDEX
#include "raycast_common.glsl"
#include "glyph_range.glsl"

const int ROBUST_MAX_DEPTH = 22;
const int ROBUST_MAX_ITERATIONS = 16384;
const int ROBUST_LEAF_SAMPLES = 2;

// The longest segment starting at s0 (local units) that is below the precision limit.
float precision_length(GlyphRay ray, float s0) {
    if (frame.eye.w > 0.5) {
        return frame.robust.x / ray.rho;
    }
    // Perspective: the footprint grows with the distance (t_mid + s0) * rho; in local
    // units rho cancels.
    return frame.robust.x * (ray.t_mid + s0);
}

// The first point inside the glyph on a leaf [s0, s1], where g(s0) <= 0 is known up to
// rounding: g at ROBUST_LEAF_SAMPLES points, refinement of the first sign change.
bool leaf_hit(GlyphRay ray, float s0, float s1, out float s_hit) {
    float s_prev = s0;
    float g_prev = 0.0;
    for (int j = 1; j <= ROBUST_LEAF_SAMPLES; ++j) {
        float s = mix(s0, s1, float(j) / float(ROBUST_LEAF_SAMPLES));
        float g = inside(ray.mid + s * ray.dir);
        if (g > 0.0) {
            if (j == 1) {
                g_prev = inside(ray.mid + s_prev * ray.dir);
            }
            s_hit = g_prev > 0.0 ? s_prev : refine(ray.mid, ray.dir, s_prev, g_prev, s, g);
            return true;
        }
        s_prev = s;
        g_prev = g;
    }
    return false;
}

bool robust_first_hit(GlyphRay ray, out float s_hit) {
    s_hit = ray.s_start;
    if (inside(ray.mid + ray.s_start * ray.dir) > 0.0) {
        return true;
    }
    bool hide = glyph_set.hide_negative == NEGATIVE_HIDE;
    float offset = frame.march.w;
    float abs_sum = glyph_abs_sum(v_glyph);
    float chord = ray.s_end - ray.s_start;
    uint index = 0u;
    int depth = 0;
    for (int iteration = 0; iteration < ROBUST_MAX_ITERATIONS; ++iteration) {
        float len = ldexp(chord, -depth);
        float s0 = ray.s_start + float(index) * len;
        float s1 = ray.s_start + float(index + 1u) * len;
        GlyphRange range = GLYPH_SEGMENT_RANGE(ray.mid, ray.dir, s0, s1, offset, hide, abs_sum);
        if (range.g.y >= 0.0) {
            if (depth < ROBUST_MAX_DEPTH && len > precision_length(ray, s0)) {
                depth += 1;
                index *= 2u;
                continue;
            }
            if (leaf_hit(ray, s0, s1, s_hit)) {
                return true;
            }
        }
        index += 1u;
        int up = min(findLSB(index), depth);
        index >>= uint(up);
        depth -= up;
        if (depth == 0) {
            return false;  // past the end of the chord
        }
    }
    return false;
}

void main() {
    GlyphRay ray;
    if (!glyph_ray(ray)) {
        discard;
    }
    count_work(WORK_EVALUATIONS);
    glyph_load_inputs();
    float s_hit;
    if (!robust_first_hit(ray, s_hit)) {
        discard;
    }
    shade_hit(ray, s_hit);
}
