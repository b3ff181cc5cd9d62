// A horizontal square at height `square.y`, half-size `square.z`, centred on x = y = 0,
// drawn with the application's camera in wgpu's clip space; a two-tone checkerboard.
struct Plane {
    view_proj: mat4x4<f32>,
    // (unused, height, half size, unused)
    square: vec4<f32>,
};

@group(0) @binding(0) var<uniform> plane: Plane;

struct Corner {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> Corner {
    // Two triangles: corners (-1,-1) (1,-1) (1,1), (-1,-1) (1,1) (-1,1).
    var corners = array<vec2<f32>, 6>(
        vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
        vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0),
    );
    let xy = corners[index] * plane.square.z;
    var out: Corner;
    out.clip = plane.view_proj * vec4(xy, plane.square.y, 1.0);
    out.world = xy;
    return out;
}

@fragment
fn fs_main(corner: Corner) -> @location(0) vec4<f32> {
    let cell = floor(corner.world * 2.0);
    let dark = (i32(cell.x) + i32(cell.y)) % 2 == 0;
    return select(vec4(0.85, 0.8, 0.7, 1.0), vec4(0.55, 0.5, 0.45, 1.0), dark);
}
