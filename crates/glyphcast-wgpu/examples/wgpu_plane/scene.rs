//! The scene both the application and glyphcast's headless reference draw: six order-6
//! glyphs in a 3 x 2 grid at z = 0, a plane just above their centres that cuts them all,
//! and a camera that circles them, looking down.
use crate::plane::Square;
use glam::{DMat4, DVec3, DVec4};
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::render::host_view::{look_at, perspective};
use glyphcast::{Camera, DepthConvention, GlyphSetData, ImageSize, Projection, Scene};
use glyphcast_wgpu::{GlyphSet, WgpuCamera};

/// Small, so that a run of many frames stays quick on a software rasteriser.
pub const WIDTH: u32 = 128;
pub const HEIGHT: u32 = 96;
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The application's clear colour (linear).
pub const CLEAR_COLOR: wgpu::Color = wgpu::Color {
    r: 0.55,
    g: 0.65,
    b: 0.8,
    a: 1.0,
};
pub const NEAR: f64 = 0.5;
pub const FAR: f64 = 40.0;
pub const FOV_Y_DEG: f64 = 35.0;

/// The plane: just above the glyphs' centres.
pub const SQUARE: Square = Square {
    height: 0.08,
    half: 2.2,
};

/// The glyph scene at the camera of frame `frame`.
pub fn scene(frame: u32) -> Scene {
    let grid = [
        (-1.1, -0.55),
        (0.0, -0.55),
        (1.1, -0.55),
        (-1.1, 0.55),
        (0.0, 0.55),
        (1.1, 0.55),
    ];
    let centers = grid.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect();
    let coefficients = (0..grid.len())
        .map(|k| {
            let turn = 35.0 * k as f64;
            fibre_tensor(
                6,
                &[
                    (direction(turn, 35.0), 1.0),
                    (direction(turn + 90.0, -25.0), 0.7),
                ],
            )
        })
        .collect();
    Scene {
        glyph_sets: vec![glyph_set(symmetric(6), centers, 0.5, coefficients)],
        camera: camera(frame),
        image: ImageSize {
            width: WIDTH,
            height: HEIGHT,
        },
    }
}

/// The glyphs, prepared as glyphcast draws them.
pub fn glyph_sets() -> glyphcast::Result<Vec<GlyphSetData>> {
    let settings = glyphcast::RenderSettings::default();
    glyphcast::prepare_scene(&scene(0), settings.offset as f64)
}

/// The glyphs as an application holds them, flat arrays of centres and coefficients,
/// made a glyph set without a scene or camera: what the frame loop draws (the headless
/// reference draws `glyph_sets`, from the scene).
pub fn glyph_arrays() -> glyphcast::Result<GlyphSet> {
    let scene = scene(0);
    let set = &scene.glyph_sets[0];
    let centers: Vec<f64> = set.centers.iter().flat_map(|c| c.to_array()).collect();
    let coefficients = set.coeffs.concat();
    GlyphSet::from_arrays(
        "the example's arrays",
        symmetric(6),
        &centers,
        &[0.5],
        &coefficients,
    )
}

/// The camera of frame `frame`: a slow orbit, looking down at the origin.
pub fn camera(frame: u32) -> Camera {
    let angle = (-70.0 + 1.5 * frame as f64).to_radians();
    Camera {
        projection: Projection::Perspective {
            fov_y_deg: FOV_Y_DEG,
        },
        eye: DVec3::new(4.4 * angle.cos(), 4.4 * angle.sin(), 3.0),
        target: DVec3::ZERO,
        up: DVec3::Z,
    }
}

/// The application's matrices for frame `frame`, in wgpu's clip space (y up).
pub fn wgpu_camera(frame: u32) -> WgpuCamera {
    let c = camera(frame);
    let aspect = WIDTH as f64 / HEIGHT as f64;
    let vulkan = perspective(
        FOV_Y_DEG.to_radians(),
        aspect,
        NEAR,
        Some(FAR),
        DepthConvention::Standard,
    );
    WgpuCamera {
        view: look_at(c.eye, c.target, c.up),
        // glyphcast's helper gives Vulkan's clip space (y down); wgpu's has y up.
        projection: DMat4::from_diagonal(DVec4::new(1.0, -1.0, 1.0, 1.0)) * vulkan,
    }
}

/// The same camera from `f32` matrices, as a wgpu application holds them: what the frame
/// loop draws with.
pub fn wgpu_camera_f32(frame: u32) -> WgpuCamera {
    let c = wgpu_camera(frame);
    WgpuCamera::from_f32(c.view.as_mat4(), c.projection.as_mat4())
}
