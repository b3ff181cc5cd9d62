#version 450
// Tessellated glyphs: the ray caster's shading, colour modes and outputs for a rasterised
// surface point, so that images and depth maps compare directly. Depth is the
// rasteriser's (exact for the planar triangle, and early depth tests stay on).
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"
#include "pixel_ray.glsl"
#include "shading.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_offset;
layout(location = 2) in vec3 v_normal;

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_distance;

void main() {
    vec3 origin, dir;
    pixel_ray(origin, dir);
    // The interpolated point lies on this pixel's ray (perspective-correct interpolation
    // of a planar triangle); its distance is measured along that ray from the ray's own
    // origin, which for an orthographic camera is not the eye.
    out_distance = dot(v_world - origin, dir);
    float radius = length(v_offset);
    vec3 from_centre = radius > 0.0 ? v_offset / radius : vec3(0.0, 0.0, 1.0);
    vec3 normal = normalize(v_normal);
    out_color = vec4(blinn_phong(glyph_color(from_centre, radius, 1.0), normal, -dir), 1.0);
}
