#version 450
// The ground plane of examples/embed.rs: an engine's own geometry, drawn into the same
// depth buffer as the glyphs. A square in the plane z = square.z, centred at square.xy
// with half-size square.w, as two triangles made from gl_VertexIndex (no vertex buffer).
layout(push_constant) uniform Plane {
    mat4 view_proj;   // the same matrix as the glyph pass's FrameParams.view_proj
    vec4 square;
} plane;

layout(location = 0) out vec2 v_xy;

const vec2 CORNERS[6] = vec2[6](
    vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
    vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0)
);

void main() {
    vec2 xy = plane.square.xy + plane.square.w * CORNERS[gl_VertexIndex];
    v_xy = xy;
    gl_Position = plane.view_proj * vec4(xy, plane.square.z, 1.0);
}
