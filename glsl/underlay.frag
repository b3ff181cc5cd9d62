#version 450
// The anatomical underlay's colour (underlay.glsl) at the fragment's voxel coordinate.
// Outside the volume and where a neighbouring voxel is NaN, nothing is drawn: the
// background (or a glyph) shows. Where the plane is drawn, the ray distance is "no
// glyph": the depth map keeps glyph hits only, and a glyph behind the plane is not seen.
#extension GL_GOOGLE_include_directive : require
#include "underlay.glsl"

layout(location = 0) in vec3 v_voxel;
layout(location = 0) out vec4 out_color;
// The distance attachment, where the target has one: -1, no glyph (NaN in the depth map).
layout(location = 1) out float out_distance;

void main() {
    vec3 rgb;
    if (!underlay_rgb(v_voxel, rgb)) {
        discard;
    }
    out_distance = -1.0;
    out_color = vec4(rgb, 1.0);
}
