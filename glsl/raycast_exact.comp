#version 450
// --path compute: the exact method (raycast_exact.frag) as a compute ray caster. One
// invocation per pixel, one workgroup per screen tile of 16 x 16 pixels. The CPU listed
// in each tile every glyph whose oriented box may cover it, sorted by the nearest depth
// the box can be hit at (src/render/tiles.rs). A pixel walks its tile's list front to
// back: it clips its ray to each glyph's sphere and box (glyph_ray_clip), runs the
// fragment shader's root isolation (exact_root.glsl) where the ray enters the box before
// its best hit, keeps the nearest hit, and stops at the first glyph whose nearest depth
// lies behind it. Only the nearest hit is shaded, once, after the walk.
//
// lavapipe ends an invocation after 65,535 loop iterations in all, so one dispatch runs
// at most WALK_PER_DISPATCH root isolations for a subgroup and walks at most
// ENTRIES_PER_DISPATCH entries of a list; a pixel whose walk is longer stores where it
// stopped, and the next dispatch (`glyph_set.slice` counts them) goes on from there and
// from the nearest hit stored. A dispatch that leaves a pixel unfinished writes the
// group counts of the next one, which is indirect: when every pixel is done, the later
// dispatches launch no workgroup.
// Glyph sets (and parts of sets that one storage buffer cannot hold) are dispatched one
// after another into the same outputs, which compose by ray distance as a depth test
// would. compose.frag then draws the outputs into the frame's attachments.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#define GLYPHCAST_COMPUTE
#include "frame.glsl"
#include "glyph_function.glsl"
#include "pixel_ray.glsl"
#include "shading.glsl"
#include "glyph_ray.glsl"
#include "exact_root.glsl"

// A tile is a workgroup: src/render/tiles.rs TILE_SIZE, 16 x 16 pixels. Its invocations
// take the tile's pixels in Morton order, so that the invocations a device runs together
// (8 lanes on lavapipe, 32 on NVIDIA) are a compact block of pixels (4 x 2, 8 x 4), which
// meet the same glyphs and finish their walks together, rather than a strip of a row.
layout(local_size_x = 256) in;

// The pixel of invocation `i` in its tile: x from the even bits of i, y from the odd.
uvec2 morton_pixel(uint i) {
    uvec2 p = uvec2(0u);
    [[unroll]] for (uint b = 0u; b < 4u; ++b) {
        p.x |= ((i >> (2u * b)) & 1u) << b;
        p.y |= ((i >> (2u * b + 1u)) & 1u) << b;
    }
    return p;
}
// src/render/tiles.rs WALK_PER_DISPATCH, set by the pipeline: root isolations a subgroup
// runs in one dispatch.
layout(constant_id = 0) const uint WALK_PER_DISPATCH = 32u;
// Entries a pixel walks in one dispatch: each is one iteration of the walk's inner loop,
// so with WALK_PER_DISPATCH root isolations of at most about 1,500 iterations each
// (src/render/tiles.rs) a dispatch stays below lavapipe's 65,535.
const uint ENTRIES_PER_DISPATCH = 8192u;

// Per glyph: centre and world radius of the bounding sphere; the box's rotation (box to
// world, x y z w) and half extents in units of that radius (GlyphSetData).
layout(std430, set = 0, binding = 2) readonly buffer Instances {
    vec4 instances[];
};
layout(std430, set = 0, binding = 3) readonly buffer Boxes {
    vec4 boxes[];
};
// Per tile (row-major): first entry of its list, length.
layout(std430, set = 0, binding = 4) readonly buffer TileRanges {
    uvec2 tile_ranges[];
};
// Per entry: glyph, bits of its nearest depth (world ray distance), sorted by the latter.
layout(std430, set = 0, binding = 5) readonly buffer TileEntries {
    uvec2 tile_entries[];
};
// Per pixel, row-major from the top-left: RGBA8 sRGB (the colour target's bytes), and
// the ray distance of the nearest hit (< 0: none yet).
layout(std430, set = 0, binding = 6) buffer Colors {
    uint colors[];
};
layout(std430, set = 0, binding = 7) buffer Distances {
    float distances[];
};
// Per pixel: the window depth of the nearest hit, as the fragment path writes
// gl_FragDepth (read by compose.frag, which draws the frame into attachments).
layout(std430, set = 0, binding = 8) writeonly buffer Depths {
    float depths[];
};

// Per pixel: the entries of its tile's list it has walked (written by every dispatch
// that walks it; the list's length once its walk is over).
layout(std430, set = 0, binding = 9) buffer Walked {
    uint walked[];
};
// Per dispatch of a part after the first: its group counts (x, y, z), zero unless the
// dispatch before left a pixel unfinished.
layout(std430, set = 0, binding = 10) buffer NextDispatch {
    uint next_dispatch[];
};

// The pixel's ray in the frame of `glyph`, clipped to its chord and box.
bool clip_to_glyph(uint glyph, vec3 origin, vec3 dir, out GlyphRay ray) {
    ray.origin = origin;
    ray.dir = dir;
    // raycast.vert normalises the rotation before the fragment shader sees it.
    return glyph_ray_clip(instances[glyph], normalize(boxes[2u * glyph]),
                          boxes[2u * glyph + 1u].xyz, CHORD_RADIUS, ray);
}

// The 8-bit sRGB encoding that an R8G8B8A8_SRGB attachment applies to a written colour.
uint srgb_byte(float linear) {
    float c = clamp(linear, 0.0, 1.0);
    float encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
    return uint(encoded * 255.0 + 0.5);
}

void main() {
    uvec2 pixel = gl_WorkGroupID.xy * 16u + morton_pixel(gl_LocalInvocationIndex);
    if (pixel.x >= glyph_set.width || pixel.y >= glyph_set.height) {
        return;
    }
    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uvec2 range = tile_ranges[tile];
    uint index = pixel.y * glyph_set.width + pixel.x;
    // The part's first dispatch starts every walk (and stores where each stops: no
    // clear is needed). The lanes of a subgroup stopped at the same entry (they step
    // through the list together); its first active lane's says so to the compiler, which
    // then loads each entry and glyph once for the subgroup rather than lane by lane.
    uint start = glyph_set.slice == 0u ? 0u : subgroupBroadcastFirst(walked[index]);
    if (start >= range.y) {
        return;
    }
    uint first = range.x;
    uint count = range.y;
    uint stop = min(count, start + ENTRIES_PER_DISPATCH);
    float best = distances[index];
    vec3 origin, dir;
    pixel_ray_through(vec2(pixel) + 0.5, origin, dir);
    const uint NONE = 0xffffffffu;
    uint best_glyph = NONE;
    float best_tau = 0.0;
    // The walk skips, at the cost of the box test alone, every entry that no invocation
    // of the subgroup needs: a device runs the root isolation's long body for all the
    // lanes of a subgroup, masked, whenever one of them needs it (lavapipe runs it even
    // when none does, unless a loop's exit skips it). The glyph stays the same for every
    // lane, so its data is loaded once for all of them. Each pixel meets the same entries
    // in the same order as a walk of one pixel alone, so its hit is the same, whichever
    // invocations a vote counts (a device that lets lanes drift apart counts the active
    // ones): a lane stops at every entry it needs itself, and ends its walk only once it
    // is itself past its best hit. The lanes of a subgroup step through the list
    // together, so `runs` counts the root isolations the subgroup ran.
    uint i = start;
    uint runs = 0u;
    bool over = false;
    for (;;) {
        GlyphRay ray;
        bool needs = false;
        for (; i < stop; ++i) {
            uvec2 entry = tile_entries[first + i];
            // This glyph and every later one lie behind the best hit.
            bool behind = best >= 0.0 && uintBitsToFloat(entry.y) >= best;
            // Where the ray enters the box bounds the glyph's hits too.
            needs = !behind && clip_to_glyph(entry.x, origin, dir, ray)
                 && !(best >= 0.0 && (ray.t_mid + ray.s_start) * ray.rho >= best);
            if (subgroupAny(needs)) {
                break;
            }
            if (subgroupAll(behind)) {
                over = true;
                i = stop;
            }
        }
        if (i >= stop) {
            break;
        }
        uint glyph = tile_entries[first + i].x;
        ++i;
        ++runs;
        if (needs) {
            glyph_load(glyph);
            float h = ray.half_chord;
            ray_polynomial(ray.mid, h * ray.dir);
            float tau;
            if (first_crossing(ray.mid, h * ray.dir, ray.s_start / h, ray.s_end / h, tau)) {
                // shade_surface's distance of the hit, as the fragment shader writes it.
                float distance = (ray.t_mid + tau * h) * ray.rho;
                if (best < 0.0 || distance < best) {
                    best = distance;
                    best_glyph = glyph;
                    best_tau = tau;
                }
            }
        }
        if (runs >= WALK_PER_DISPATCH) {
            break;
        }
    }
    uint done = over ? count : i;
    walked[index] = done;
    uint next = 3u * (glyph_set.slice + 1u);
    if (done < count && next + 2u < uint(next_dispatch.length())) {
        next_dispatch[next] = gl_NumWorkGroups.x;
        next_dispatch[next + 1u] = gl_NumWorkGroups.y;
        next_dispatch[next + 2u] = 1u;
    }
    if (best_glyph == NONE) {
        return;
    }
    GlyphRay ray;
    clip_to_glyph(best_glyph, origin, dir, ray);
    glyph_load(best_glyph);
    vec4 color;
    float depth;
    float distance;
    shade_surface(ray, best_tau * ray.half_chord, color, depth, distance);
    colors[index] = srgb_byte(color.r) | (srgb_byte(color.g) << 8) | (srgb_byte(color.b) << 16)
                  | (255u << 24);
    distances[index] = distance;
    depths[index] = depth;
}
