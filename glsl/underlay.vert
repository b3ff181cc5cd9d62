#version 450
// The anatomical underlay (src/render/underlay.rs): one plane of the underlay volume, a
// world-space parallelogram origin + s u + t v (s, t in [0, 1]) drawn as two triangles
// made from gl_VertexIndex (no vertex buffer), into the glyphs' depth buffer. The
// underlay's voxel coordinate is an affine function of the world point, so it is
// computed per corner and interpolated (perspective-correct, hence exact up to rounding).
#ifdef GLYPHCAST_RECEIVER
// The underlay's shadow receiver (raycast_exact.frag's GLYPHCAST_RECEIVER variant): the
// underlay's blocks are set 1 (set 0 is the glyph batch's), and the push range starts
// with the batch's word (frame.glsl GlyphSetParams), so the plane follows at 16. The
// position is computed as the underlay's own draw computes it (precise), so that the
// receiver's EQUAL depth test passes exactly where the plane was drawn.
#define UNDERLAY_SET 1
#define PLANE_OFFSET layout(offset = 16)
#else
#define UNDERLAY_SET 0
#define PLANE_OFFSET
#endif
// A storage buffer, as the frame block (frame.glsl says why).
layout(std430, set = UNDERLAY_SET, binding = 0) readonly buffer UnderlayParams {
    mat4 world_to_voxel;  // world point to the underlay's voxel coordinates (i, j, k)
    ivec4 dims;           // xyz: voxels along i, j, k; w: channels (1 grey, 3 RGB)
    vec4 window;          // x: the window's low end, y: 1 / (high - low)
} underlay;

layout(push_constant) uniform Plane {
    PLANE_OFFSET mat4 view_proj;  // the glyph pass's FrameParams.view_proj
    vec4 origin;          // xyz: a corner of the plane, world space
    vec4 u;               // xyz: the edge from it along s
    vec4 v;               // xyz: the edge from it along t
    // (origin.w, u.w, v.w): the sample offset: the volume is sampled at world - offset
    // (a plane moved behind the glyphs still shows its slice).
} plane;

layout(location = 0) out vec3 v_voxel;
#ifdef GLYPHCAST_RECEIVER
layout(location = 1) out vec3 v_world;
layout(location = 2) flat out vec3 v_normal;  // the plane's, not normalised
#endif

const vec2 CORNERS[6] = vec2[6](
    vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(1.0, 1.0),
    vec2(0.0, 0.0), vec2(1.0, 1.0), vec2(0.0, 1.0)
);

void main() {
    vec2 st = CORNERS[gl_VertexIndex];
    // precise: no contraction into fused operations, which a compiler may choose
    // differently in two shaders; the position is the same rounded arithmetic in both.
    // (`invariant gl_Position` says the same, but Mesa 22.3 warns about the decoration
    // glslang puts on gl_PerVertex.)
    precise vec3 world = plane.origin.xyz + st.x * plane.u.xyz + st.y * plane.v.xyz;
    vec3 offset = vec3(plane.origin.w, plane.u.w, plane.v.w);
    v_voxel = (underlay.world_to_voxel * vec4(world - offset, 1.0)).xyz;
    precise vec4 position = plane.view_proj * vec4(world, 1.0);
    gl_Position = position;
#ifdef GLYPHCAST_RECEIVER
    v_world = world;
    v_normal = cross(plane.u.xyz, plane.v.xyz);
#endif
}
