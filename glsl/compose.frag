#version 450
// The compute ray caster's frame drawn into rendering attachments (src/render/compute.rs
// ComposePass): each pixel of the viewport reads the colour, ray distance and window depth
// the compute shader (raycast_exact.comp) stored for it, and writes them as the fragment
// path's glyph shader would have: the colour in linear light (the sRGB attachment encodes
// it again, to the same byte), the distance at location 1, the depth as gl_FragDepth, so
// that the attachment's depth test composes the glyphs with whatever else the rendering
// draws (an underlay, peaks, a host's geometry). A pixel without a hit is discarded.
layout(std430, set = 0, binding = 0) readonly buffer Colors {
    uint colors[];  // RGBA8 sRGB, row-major from the image's top-left
};
layout(std430, set = 0, binding = 1) readonly buffer Distances {
    float distances[];  // < 0: no hit
};
layout(std430, set = 0, binding = 2) readonly buffer Depths {
    float depths[];
};

layout(push_constant) uniform Region {
    uvec2 origin;     // the image's top-left pixel in the attachments
    uint row_length;  // the image's width
    uint pad;
} compose;

layout(location = 0) out vec4 out_color;
#ifndef GLYPHCAST_NO_DISTANCE  // build.rs: the variant for a colour attachment only
layout(location = 1) out float out_distance;
#endif

// The sRGB decoding, the exact inverse of the compute shader's encoding.
float srgb_to_linear(float c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy) - compose.origin;
    uint index = pixel.y * compose.row_length + pixel.x;
    float distance = distances[index];
    if (!(distance >= 0.0)) {
        discard;
    }
    vec4 c = unpackUnorm4x8(colors[index]);
    out_color = vec4(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b), c.a);
#ifndef GLYPHCAST_NO_DISTANCE
    out_distance = distance;
#endif
    gl_FragDepth = depths[index];
}
