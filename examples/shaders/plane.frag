#version 450
// A grey checkerboard of half-unit cells for the plane of examples/embed.rs.
layout(location = 0) in vec2 v_xy;
layout(location = 0) out vec4 out_color;

void main() {
    ivec2 cell = ivec2(floor(v_xy * 2.0));
    float shade = ((cell.x + cell.y) & 1) == 0 ? 0.45 : 0.25;
    out_color = vec4(vec3(shade), 1.0);
}
