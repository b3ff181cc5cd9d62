// Frame-wide parameters and the coefficient buffer of one glyph set.
// Mirrored on the CPU by src/render/frame.rs (FrameParams); src/render/interface.rs
// checks member names, offsets and bindings against the compiled SPIR-V. The mode codes
// come from src/catalog.rs (codes), which build.rs serves as codes.glsl.
#include "codes.glsl"

// A read-only storage buffer, not a uniform buffer: lavapipe (Mesa 22.3) inlines the
// values of uniform-buffer members that steer branches or loops into the shader and
// compiles it again at every command buffer, 10 to 20 ms a frame for the exact method
// and memory that grows with every frame. Storage-buffer loads are never inlined. All
// members are vec4/ivec4/mat4, so std430 lays them out as std140 would.
layout(std430, set = 0, binding = 0) readonly buffer FrameParams {
    mat4 view_proj;
    vec4 eye;             // xyz: eye; w: 1 for orthographic, 0 for perspective
    vec4 right;           // xyz: right * tan(fov/2) (or height/2); w: aspect W/H
    vec4 up;              // xyz: corrected up, scaled as right
    vec4 fwd;             // xyz: forward
    vec4 viewport;        // x: 1/width, y: 1/height, z: near plane distance (perspective; 0
                          // orthographic)
    vec4 march;           // x: step, y: centre step factor, z: centre zone radius, w: offset
    ivec4 modes;          // x: refinement (REFINE_*), y: its steps, z: colour (COLOR_*),
                          // w: max steps
    vec4 magnitude_range; // x: low end, y: 1 / (high - low)
    vec4 uniform_color;   // rgb, linear (sign colouring: the positive lobes')
    vec4 light;           // xyz: unit direction towards the light, world space (--light
                          // is given in view space; src/render/frame.rs turns it)
    vec4 robust;          // interval/affine: x: precision (pixels) * one pixel's footprint
                          // (world units at unit distance, or world units if orthographic)
    vec4 negative_color;  // sign colouring: the negative lobes' rgb, linear
    vec4 shading;         // Blinn-Phong: x ambient, y specular strength, z shininess
    vec4 window;          // xy: the viewport's origin in framebuffer pixels (a host's
                          // sub-rectangle); z: window depth of the near plane (1 reversed,
                          // 0 standard depth)
    vec4 shadow;          // --shadows (glsl/shadow.glsl): x 1 on, 0 off; y rays per hit;
                          // z tan of the light's angular radius; w the shadow ray's start
                          // beyond the hit, in units of the glyph's bounding radius
} frame;

layout(std430, set = 0, binding = 1) readonly buffer Coefficients {
    float coeffs[];
};

layout(push_constant) uniform GlyphSetParams {
    uint hide_negative;   // scene format `negative`: NEGATIVE_ABS or NEGATIVE_HIDE;
                          // a plane glyph's root: PLANE_MIN or PLANE_MAX
#ifdef GLYPHCAST_COMPUTE
    // The compute ray caster's dispatch (src/render/compute.rs, ComputeParams): which
    // slice of each tile's list it walks, and the image size.
    uint slice;
    uint width;
    uint height;
#endif
} glyph_set;
