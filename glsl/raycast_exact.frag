#version 450
// --method exact: the first real root of the ray polynomial, isolated in float32 (after
// Peters et al., "Ray Tracing Spherical Harmonics Glyphs", VMV 2023, who make the ray
// polynomial exact and isolate its roots, and Yuksel, HPG 2022, for bracketing each root
// before a safeguarded Newton step).
//
// Along the ray, q(tau) = mid + tau d (|d| = half chord, mid . d = 0). Inside the glyph
// |f(q)| > |q|^(n+1), so the crossings are the real roots of the degree D = 2n + 2 polynomial
//     F = f(q)^2 - (q . q)^(n+1),
// and, for `negative: hide`, only the roots where f(q) > 0 count: each isolated root is
// checked, and one where f < 0 (the edge of a hidden lobe) is passed over. (For odd n,
// (q . q)^((n+1)/2) is itself a polynomial, so hide could solve f - (q . q)^((n+1)/2) of
// degree n + 1 and abs the product of that and f + (q . q)^((n+1)/2); one code path for
// every order was preferred, as even orders, the common case, have no such factoring.)
//
// 1. p(tau) = f(q(tau)) is expanded once per ray from the monomials of f, by Horner's
//    scheme on linear polynomials in tau (ray_polynomial). That is exact algebra: each
//    coefficient is rounded relative to the size of its own terms, ~|mid|^(n-k) |d|^k, so
//    F keeps its relative accuracy down to |q| ~ 1e-2. (The alternative, f at n + 1
//    Chebyshev nodes times an inverse Vandermonde matrix, rounds every coefficient
//    relative to the largest value of p: measured in float32 on the scenes of
//    tests/depth_accuracy.rs, median depth errors of 1e-5 to 3e-3 of the glyph and false
//    hits at order 12, against 2e-7 and none.)
// 2. The chord is cut at mid into halves on which |q| is monotone (one polynomial over
//    the whole chord cancels away the small values near mid: hundreds of holes per
//    scene). On each, p is re-expanded about the end nearer mid and F is formed in the
//    half's Bernstein basis (segment_polynomials).
// 3. Descartes' rule of signs in the Bernstein basis bounds the number of roots of F on
//    any piece [u0, u1] of a half by the sign changes of its Bernstein coefficients.
//    The pieces are visited in ray order as the dyadic intervals of a binary tree,
//    stacklessly, each cut by one de Casteljau pass off the part of the half not yet
//    visited (split_rest): 0 changes drop a piece, one isolates a root, more split it.
//    The sign changes of each whole half are counted before the traversal, so a half
//    without any is passed over and one with more starts at its two halves.
//    Both halves are traversed by one loop; the first isolated root that the hide filter
//    keeps is the answer, refined by Newton on F / |q|^(2n) kept in the bracket
//    (node_root). (src/glyph/bernstein.rs is the CPU port; it cuts each piece out of the
//    whole half, which gives the same pieces.)
// 4. Near the centre F ~ |q|^(2n+2) leaves float32's range: where the ray passes within
//    CENTRE_RADIUS of the centre (|q|^D >= 2^-100 outside it), that part of the chord is
//    sampled instead, with the well-conditioned radial form g of raycast_common.glsl
//    (measured by the CPU port, src/glyph/bernstein.rs: exact outside the zone; without
//    it, 77 of 200 rays passing 1e-3 from an order-12 glyph's centre lose their hit).
//
// 5. With --shadows, rays from the hit towards the light are intersected with the
//    batch's glyphs by the same root isolation (shadow.glsl), and the light's share that
//    reaches the hit scales its diffuse and specular terms; with --ambient-occlusion,
//    rays over the hemisphere of the hit, limited in reach, scale its ambient term.
//    Depth is not touched.
//
// Offset glyphs are not polynomial; the CPU rejects --offset with this method.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "raycast_common.glsl"
#include "exact_root.glsl"

#ifdef GLYPHCAST_SHADOWS
// The shadow-casting variant of the exact method (src/render/raycast.rs picks it for
// --shadows): pass 0 isolates the camera ray's first root in this fragment's glyph, each
// later pass a shadow ray's in the glyph that shadow_next_glyph loaded, so that the root
// isolation has one call site (inlined twice, the shader would be twice as large).
// Without --shadows the shader below the #else runs, untouched by shadows.
#include "shadow.glsl"

#ifdef GLYPHCAST_RECEIVER
// The underlay receiving the batch's shadows (src/render/underlay_shadows.rs): drawn over
// each underlay plane after the glyphs, where the plane is what the pixel shows (depth
// tested EQUAL). From the plane's point the same rays as from a glyph's hit are cast,
// with the batch's mean bounding radius for the hit glyph's; the plane is a matte
// surface facing the light whose colour in full light is the underlay's: it keeps
// ambient * (occlusion share) + (1 - ambient) * (lit share) of it. The pass blends by
// MIN, so that where batches overlap the darkest share holds. A pixel that loses nothing
// is discarded.
#define UNDERLAY_SET 1
#include "underlay.glsl"

layout(location = 0) in vec3 v_voxel;
layout(location = 1) in vec3 v_world;
layout(location = 2) flat in vec3 v_normal;

void main() {
    vec3 rgb;
    if (!underlay_rgb(v_voxel, rgb)) {
        discard;
    }
    vec3 origin;
    vec3 dir;
    pixel_ray(origin, dir);
    shadow_begin_at(v_world, facing_normal(normalize(v_normal), -dir), shadow_grid.lo.w,
                    shadow_fragment_pixel());
    GlyphRay ray;
    for (int pass = 0; pass < SHADOW_ISOLATIONS; ++pass) {
        if (!shadow_next_glyph(ray)) {
            break;
        }
        float h = ray.half_chord;
        ray_polynomial(ray.mid, h * ray.dir);
        shadow_ray_only = true;
        float tau;
        if (first_crossing(ray.mid, h * ray.dir, ray.s_start / h, ray.s_end / h, tau)) {
            shadow_ray_blocked();
        }
    }
    float ambient = frame.shading.x;
    float share = ambient * shadow_ambient_visibility() + (1.0 - ambient) * shadow_visibility();
    if (share >= 1.0) {
        discard;
    }
    out_color = vec4(rgb * share, 1.0);
}
#elif defined(GLYPHCAST_GLYPH_RECEIVER)
// The glyphs receiving their batch's shadows after the frame is drawn without them
// (src/render/glyph_shadows.rs): the batch's boxes drawn again, each fragment reading
// the ray distance of the hit its pixel shows (the frame's distance attachment, copied
// into the hits buffer). The fragment of the glyph that hit belongs to (the point
// just beyond it is inside that glyph, or the hit lies on its surface) casts the hit's
// rays and writes the hit's colour lit by the share of the light that reaches it; the
// pass blends by MIN. A pixel whose hit keeps the whole light is not written: in full
// light the frame keeps its colours bit for bit. Only visible hits cast rays, once each.
layout(std430, set = 1, binding = 0) readonly buffer Hits {
    uvec4 hits_band;        // x: the row length, pixels; y: the band's first row; z: its
                            // rows (the draw's scissor)
    float hit_distances[];  // per pixel of the band, row after row; -1: no glyph
};

// Beyond the hit (normalised glyph units, along the ray), the point that must be inside
// the glyph that owns it; and how near the surface a grazing hit lies (g, of the same
// units).
const float OWNER_STEP = 2.0e-3;
const float OWNER_GRAZE = 1.0e-4;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy) - uvec2(0u, hits_band.y);
    if (pixel.y >= hits_band.z) {
        discard;  // outside the band (the scissor keeps such fragments away)
    }
    float distance = hit_distances[pixel.y * hits_band.x + pixel.x];
    if (!(distance >= 0.0)) {
        discard;  // no glyph along the ray (-1), or the underlay's pixel
    }
    GlyphRay camera;
    if (!glyph_ray_within(CHORD_RADIUS, camera)) {
        discard;
    }
    float s_hit = distance / camera.rho - camera.t_mid;
    if (s_hit < camera.s_start - OWNER_STEP || s_hit > camera.s_end + OWNER_STEP) {
        discard;
    }
    glyph_load_inputs();
    if (!(inside(camera.mid + (s_hit + OWNER_STEP) * camera.dir) > 0.0
          || abs(inside(camera.mid + s_hit * camera.dir)) <= OWNER_GRAZE)) {
        discard;
    }
    shadow_begin(camera, s_hit);
    GlyphRay ray;
    for (int pass = 0; pass < SHADOW_ISOLATIONS; ++pass) {
        if (!shadow_next_glyph(ray)) {
            break;
        }
        float h = ray.half_chord;
        ray_polynomial(ray.mid, h * ray.dir);
        shadow_ray_only = true;
        float tau;
        if (first_crossing(ray.mid, h * ray.dir, ray.s_start / h, ray.s_end / h, tau)) {
            shadow_ray_blocked();
        }
    }
    float visibility = shadow_visibility();
    shadow_ambient_share = shadow_ambient_visibility();
    if (visibility >= 1.0 && shadow_ambient_share >= 1.0) {
        discard;
    }
    glyph_load_inputs();  // the shadow rays loaded the glyphs they met
    vec4 color;
    float depth;
    float hit_distance_again;
    shade_surface_visible(camera, s_hit, visibility, color, depth, hit_distance_again);
    out_color = color;
}
#else
void main() {
    GlyphRay camera;
    if (!glyph_ray_within(CHORD_RADIUS, camera)) {
        discard;
    }
    count_work(WORK_EVALUATIONS);
    glyph_load_inputs();
    float s_hit = 0.0;
    GlyphRay ray = camera;
    for (int pass = 0; pass <= SHADOW_ISOLATIONS; ++pass) {
        float h = ray.half_chord;
        ray_polynomial(ray.mid, h * ray.dir);
        shadow_ray_only = pass > 0;
        float tau;
        bool crossing = first_crossing(ray.mid, h * ray.dir, ray.s_start / h, ray.s_end / h,
                                       tau);
        if (pass == 0) {
            if (!crossing) {
                discard;
            }
            s_hit = tau * h;
            shadow_begin(camera, s_hit);
        } else if (crossing) {
            shadow_ray_blocked();
        }
        if (!shadow_next_glyph(ray)) {
            break;
        }
    }
    float visibility = shadow_visibility();
    shadow_ambient_share = shadow_ambient_visibility();
    glyph_load_inputs();  // the shadow rays loaded the glyphs they met
    shade_hit_visible(camera, s_hit, visibility);
}
#endif
#else
void main() {
    // The whole cast inside the branch (not after an early discard): lavapipe of Mesa 25
    // jumps over a branch that none of its batch of pixels takes, and runs the code after
    // a discard masked.
    bool hidden = hidden_by_known();
    if (hidden) {
        count_work(WORK_FRAGMENTS);  // launched all the same (the others count below)
    }
    if (!hidden) {
        GlyphRay ray;
        if (!glyph_ray_within(CHORD_RADIUS, ray)) {
            discard;
        }
        count_work(WORK_EVALUATIONS);
        glyph_load_inputs();
        float h = ray.half_chord;
        ray_polynomial(ray.mid, h * ray.dir);
        float tau;
        if (!first_crossing(ray.mid, h * ray.dir, ray.s_start / h, ray.s_end / h, tau)) {
            discard;
        }
        shade_hit(ray, tau * h);
    } else {
        discard;
    }
}
#endif
