// Shadow rays (--shadows) of the exact method's fragment shader: from a hit, rays towards
// the light are intersected exactly (exact_root.glsl's first_crossing, the root isolation
// of the camera's rays) with every glyph of the batch whose box they enter, found by
// walking the uniform grid over the batch's boxes (src/render/shadow_grid.rs) cell by
// cell (Amanatides and Woo's traversal). The float64 reference is src/glyph/shadow.rs.
//
// A ray starts frame.shadow.w bounding radii of the hit glyph beyond the hit, so that the
// surface it leaves does not stop it; a ray that meets any glyph after that, the hit
// glyph's own lobes included, is blocked. Hard shadows cast one ray towards the light,
// soft shadows frame.shadow.y rays towards a disc of angular radius atan(frame.shadow.z)
// around it. Rays that leave the surface into the glyph (n . l <= 0) are not cast: the
// lit share is that of the rays cast, and a point that casts none keeps the light (its
// diffuse term is 0 already).
//
// The disc's 16 samples are a stratified pattern turned per pixel (shadow_disc_sample):
// a rank-1 lattice of 16 points in (r^2, angle / 2 pi), one in each sixteenth of the
// disc's area and of its turn, shifted on that torus by an offset hashed from the pixel
// (a Cranley-Patterson rotation). Every pixel's share is an unbiased stratified estimate;
// neighbouring pixels use different rays, so a penumbra shows fine noise instead of the
// bands a shared pattern leaves (16 levels at most, the same everywhere along an edge,
// several rays crossing it together where the pattern is symmetric). The offset is an
// integer hash of the pixel's index in the image (not of the hit), so the picture is
// the same at every run and the float64 reference repeats each pixel's rays
// (src/glyph/shadow.rs SamplePattern). Hard shadows' one ray is not turned.
//
// The root isolation is inlined once: the fragment shader runs it in one loop, first for
// its camera ray, then for each glyph that shadow_next_glyph hands out (a second call
// site doubles the shader, and its compile overflowed shaderc's stack). The walk's state
// is kept in globals between the calls.
//
// lavapipe ends an invocation after 65,535 loop iterations in all (src/render/tiles.rs):
// one fragment isolates the roots of at most SHADOW_ISOLATIONS glyphs and takes at most
// SHADOW_STEPS steps of the walk (glyphs listed, cells crossed); rays still unresolved
// then count as reaching the light.
//
// Ambient occlusion (--ambient-occlusion) casts AMBIENT_RAYS more rays from the hit, over
// the hemisphere around its normal: the soft light's 16 disc samples, turned by the
// pixel's offset, lifted onto the hemisphere (Malley's method), so cosine-weighted. Each
// reaches frame.shadow.x bounding radii of the hit glyph from its start: a glyph is
// tested only on the part of its chord within that reach, and the walk stops at the
// first cell boundary beyond it. The share of them that no glyph blocks scales the
// ambient term (shadow_ambient_share, read by shading.glsl). The float64 reference is
// src/glyph/shadow.rs ambient_share.
//
// Include after exact_root.glsl.

layout(std430, set = 0, binding = 2) readonly buffer ShadowInstances {
    vec4 shadow_instances[];  // centre, world bounding radius
};
layout(std430, set = 0, binding = 3) readonly buffer ShadowBoxes {
    vec4 shadow_boxes[];      // per glyph: rotation (box to world), half extents
};
layout(std430, set = 0, binding = 4) readonly buffer ShadowCells {
    vec4 lo;                  // xyz: the grid's lowest corner; w: the glyphs' mean
                              // bounding radius
    vec4 cell;                // xyz: a cell's edges
    ivec4 dims;               // xyz: cells along each axis
    uvec2 ranges[];           // per cell, x fastest: first entry, count
} shadow_grid;
layout(std430, set = 0, binding = 5) readonly buffer ShadowEntries {
    uint shadow_entries[];    // glyph indices, cell after cell
};

const int SHADOW_ISOLATIONS = 80;
const int AMBIENT_RAYS = 16;
const int SHADOW_STEPS = 2048;

// The hit and the rays cast from it (shadow_begin).
vec3 shadow_hit;
vec3 shadow_normal;       // turned towards the viewer
float shadow_offset;      // the rays' start beyond the hit, world units
vec3 shadow_u;            // with shadow_v, the soft light's disc around frame.light
vec3 shadow_v;
vec3 shadow_normal_u;     // with shadow_normal_v, the occlusion rays' disc around the
vec3 shadow_normal_v;     // normal
uvec2 shadow_shift;       // the pixel's offset of the disc pattern, 24-bit fixed point
int shadow_rays;          // rays towards the light per hit
int shadow_casts;         // of them, those leaving the surface outwards (n . l > 0)
int shadow_blocked;       // of those, the rays found blocked
int shadow_ambient_rays;  // occlusion rays per hit (after the light's), 0 or AMBIENT_RAYS
float shadow_reach;       // how far an occlusion ray reaches, world units
int shadow_ambient_blocked;  // of them, the rays found blocked
float shadow_ray_reach;   // how far the ray being walked reaches, world units
// The ray being walked.
int shadow_sample;        // its index; -1 before the first
bool shadow_active;       // whether a ray is being walked
vec3 shadow_origin;
vec3 shadow_dir;
ivec3 shadow_at;          // its cell
ivec3 shadow_step;        // the cell steps along the ray, per axis
vec3 shadow_t_next;       // ray distance to the next cell boundary, per axis
vec3 shadow_delta;        // ray distance across one cell, per axis
uint shadow_entry;        // the next of the cell's entries to test
uint shadow_entry_end;
uvec4 shadow_recent;      // the last four glyphs tested on this ray
int shadow_steps_left;

// A unit vector perpendicular to the unit vector v.
vec3 shadow_perpendicular(vec3 v) {
    vec3 other = abs(v.x) < 0.6 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    return normalize(cross(v, other));
}

// One round of the PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering",
// JCGT 2020; src/glyph/shadow.rs pcg_hash).
uint shadow_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The disc pattern's offset for the image pixel `pixel` (src/glyph/shadow.rs
// SamplePattern::for_pixel): two hashes, 24 bits each.
uvec2 shadow_pixel_shift(uvec2 pixel) {
    uint a = shadow_hash(pixel.x + shadow_hash(pixel.y));
    uint b = shadow_hash(a);
    return uvec2(a >> 8u, b >> 8u);
}

// Sample k (0 to 15) of the unit disc (src/glyph/shadow.rs soft_sample): point k of the
// lattice (k / 16, 7 k / 16) shifted by the pixel's offset modulo 1, in 24-bit fixed
// point (so that float32 holds both coordinates exactly), then r = sqrt(x) and angle
// 2 pi y: equal areas.
vec2 shadow_disc_sample(int k) {
    uint x = ((uint(k) << 20u) + shadow_shift.x) & 0xffffffu;
    uint y = ((uint(7 * k & 15) << 20u) + shadow_shift.y) & 0xffffffu;
    float radius = sqrt(float(x) * (1.0 / 16777216.0));
    float angle = 6.28318530718 * (float(y) * (1.0 / 16777216.0));
    return radius * vec2(cos(angle), sin(angle));
}

// The image pixel of this fragment (its window position relative to the viewport's
// origin), which picks its turn of the disc pattern.
uvec2 shadow_fragment_pixel() {
    return uvec2(max(gl_FragCoord.xy - frame.window.xy, vec2(0.0)));
}

// Ray k from the hit: towards the light (its direction, or sample k of a soft light's
// disc), then, from k = shadow_rays on, the occlusion rays (src/glyph/shadow.rs
// ambient_direction).
vec3 shadow_ray_dir(int k) {
    if (k >= shadow_rays) {
        vec2 s = shadow_disc_sample(k - shadow_rays);
        return normalize(s.x * shadow_normal_u + s.y * shadow_normal_v
                         + sqrt(max(1.0 - dot(s, s), 0.0)) * shadow_normal);
    }
    vec3 light = frame.light.xyz;
    if (shadow_rays <= 1) {
        return light;
    }
    vec2 s = shadow_disc_sample(k) * frame.shadow.z;
    return normalize(light + s.x * shadow_u + s.y * shadow_v);
}

// The entries of the current cell.
void shadow_enter_cell() {
    ivec3 dims = shadow_grid.dims.xyz;
    uvec2 range = shadow_grid.ranges[(shadow_at.z * dims.y + shadow_at.y) * dims.x
                                     + shadow_at.x];
    shadow_entry = range.x;
    shadow_entry_end = range.x + range.y;
}

// Starts walking ray shadow_sample from its cell of the grid; false when it misses the
// grid (nothing can block it).
bool shadow_start_ray() {
    vec3 dir = shadow_dir;
    vec3 lo = shadow_grid.lo.xyz;
    vec3 size = shadow_grid.cell.xyz;
    ivec3 dims = shadow_grid.dims.xyz;
    vec3 safe = vec3(abs(dir.x) < 1e-20 ? 1e-20 : dir.x, abs(dir.y) < 1e-20 ? 1e-20 : dir.y,
                     abs(dir.z) < 1e-20 ? 1e-20 : dir.z);
    vec3 inv = 1.0 / safe;
    vec3 a = (lo - shadow_origin) * inv;
    vec3 b = (lo + vec3(dims) * size - shadow_origin) * inv;
    vec3 near = min(a, b);
    vec3 far = max(a, b);
    float t0 = max(max(max(near.x, near.y), near.z), 0.0);
    float t1 = min(min(far.x, far.y), far.z);
    if (t0 > t1) {
        return false;
    }
    vec3 start = (shadow_origin + t0 * dir - lo) / size;
    shadow_at = clamp(ivec3(floor(start)), ivec3(0), dims - 1);
    shadow_step = ivec3(sign(safe));
    shadow_delta = abs(size * inv);
    vec3 next_edge = lo + (vec3(shadow_at) + max(vec3(shadow_step), vec3(0.0))) * size;
    shadow_t_next = (next_edge - shadow_origin) * inv;
    shadow_recent = uvec4(0xffffffffu);
    shadow_enter_cell();
    return true;
}

// Sets up the rays cast from the point `hit` whose unit normal, turned towards the
// viewer, is `normal`; `radius` (world units) scales where they start and how far the
// occlusion rays reach: the hit glyph's bounding radius, or for the underlay the batch's
// mean one. `pixel` (the image pixel that shows the hit) turns the disc pattern.
void shadow_begin_at(vec3 hit, vec3 normal, float radius, uvec2 pixel) {
    shadow_shift = shadow_pixel_shift(pixel);
    shadow_normal = normal;
    shadow_hit = hit;
    shadow_offset = frame.shadow.w * radius;
    shadow_rays = int(frame.shadow.y);
    shadow_u = shadow_perpendicular(frame.light.xyz);
    shadow_v = cross(frame.light.xyz, shadow_u);
    shadow_normal_u = shadow_perpendicular(shadow_normal);
    shadow_normal_v = cross(shadow_normal, shadow_normal_u);
    shadow_casts = 0;
    for (int k = 0; k < shadow_rays; ++k) {
        shadow_casts += dot(shadow_normal, shadow_ray_dir(k)) > 0.0 ? 1 : 0;
    }
    shadow_blocked = 0;
    shadow_ambient_rays = frame.shadow.x > 0.0 ? AMBIENT_RAYS : 0;
    shadow_reach = frame.shadow.x * radius;
    shadow_ambient_blocked = 0;
    shadow_sample = -1;
    shadow_active = false;
    shadow_steps_left = SHADOW_STEPS;
}

// Sets up the shadow rays of the hit at q(s_hit) of the camera's ray through the loaded
// glyph, seen by this fragment's pixel.
void shadow_begin(GlyphRay camera, float s_hit) {
    float len;
    vec3 q_dir;
    float f;
    vec3 normal = surface_normal(camera.mid + s_hit * camera.dir, len, q_dir, f);
    vec3 hit = camera.origin + (camera.t_mid + s_hit) * camera.rho * camera.dir;
    // The hit glyph's bounding radius.
    shadow_begin_at(hit, facing_normal(normal, -camera.dir), camera.rho * (1.0 + frame.march.w),
                    shadow_fragment_pixel());
}

// The next glyph whose box the ray being walked enters, loaded, with that ray in its
// frame (clipped to its chord and box); false when every ray is resolved or the walk's
// steps are spent.
bool shadow_next_glyph(out GlyphRay ray) {
    for (; shadow_steps_left > 0; --shadow_steps_left) {
        if (!shadow_active) {
            shadow_sample += 1;
            if (shadow_sample >= shadow_rays + shadow_ambient_rays) {
                return false;
            }
            shadow_dir = shadow_ray_dir(shadow_sample);
            // Rays towards the light reach as far as the grid does.
            shadow_ray_reach = shadow_sample < shadow_rays ? 3.0e38 : shadow_reach;
            if (dot(shadow_normal, shadow_dir) > 0.0) {
                shadow_origin = shadow_hit + shadow_offset * shadow_dir;
                shadow_active = shadow_start_ray();
            }
        } else if (shadow_entry < shadow_entry_end) {
            uint glyph = shadow_entries[shadow_entry];
            shadow_entry += 1u;
            if (!any(equal(shadow_recent, uvec4(glyph)))) {
                shadow_recent = uvec4(glyph, shadow_recent.xyz);
                ray.origin = shadow_origin;
                ray.dir = shadow_dir;
                bool enters = glyph_ray_clip(shadow_instances[glyph],
                                             normalize(shadow_boxes[2u * glyph]),
                                             shadow_boxes[2u * glyph + 1u].xyz, CHORD_RADIUS,
                                             ray);
                // Only the part of the chord within the ray's reach.
                ray.s_end = min(ray.s_end, shadow_ray_reach / ray.rho - ray.t_mid);
                if (enters && ray.s_start < ray.s_end) {
                    glyph_load(glyph);
                    shadow_steps_left -= 1;
                    return true;
                }
            }
        } else {
            // The next cell: across the nearest boundary; past the grid or the ray's
            // reach, the ray is unblocked.
            if (min(min(shadow_t_next.x, shadow_t_next.y), shadow_t_next.z) > shadow_ray_reach) {
                shadow_active = false;
            } else if (shadow_t_next.x <= shadow_t_next.y && shadow_t_next.x <= shadow_t_next.z) {
                shadow_at.x += shadow_step.x;
                shadow_t_next.x += shadow_delta.x;
            } else if (shadow_t_next.y <= shadow_t_next.z) {
                shadow_at.y += shadow_step.y;
                shadow_t_next.y += shadow_delta.y;
            } else {
                shadow_at.z += shadow_step.z;
                shadow_t_next.z += shadow_delta.z;
            }
            if (any(lessThan(shadow_at, ivec3(0)))
                || any(greaterThanEqual(shadow_at, shadow_grid.dims.xyz))) {
                shadow_active = false;
            } else {
                shadow_enter_cell();
            }
        }
    }
    return false;
}

// The glyph last handed out blocks the ray being walked: on to the next ray.
void shadow_ray_blocked() {
    if (shadow_sample < shadow_rays) {
        shadow_blocked += 1;
    } else {
        shadow_ambient_blocked += 1;
    }
    shadow_active = false;
}

// The share of the light that reaches the hit: 1 when no ray was cast; rays left
// unresolved count as lit.
float shadow_visibility() {
    return shadow_casts == 0 ? 1.0 : 1.0 - float(shadow_blocked) / float(shadow_casts);
}

// The share of the occlusion rays that no glyph blocks (1 without ambient occlusion);
// rays left unresolved count as unblocked.
float shadow_ambient_visibility() {
    return shadow_ambient_rays == 0
        ? 1.0 : 1.0 - float(shadow_ambient_blocked) / float(shadow_ambient_rays);
}
