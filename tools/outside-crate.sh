#!/usr/bin/env bash
# An engine's first build: a new crate outside the repository (a temporary folder) that
# depends on glyphcast and on glyphcast-wgpu by path, built with plain `cargo` and no
# environment script sourced (no SHADERC_LIB_DIR, no VULKAN_SDK), draws one glyph
# headless and checks the pixels (src/main.rs), then draws it again in a wgpu
# application's textures through glyphcast-wgpu (src/bin/wgpu.rs): the shaderc that
# glyphcast's build script links is found and completed by
# crates/glyphcast-shaderc-link alone. Runs on lavapipe where the machine has it.
#
# Cheap on top of the workspace's build: the crate builds into the workspace's target
# folder with the workspace's Cargo.lock (so the same dependency versions), the root
# Cargo.toml's dev profile (glyphcast and the helper, members there, keep their
# member's settings), and the workspace's SPIR-V cache (no shader is compiled again).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
target="${CARGO_TARGET_DIR:-$repo/target}"
if ! command -v cargo >/dev/null 2>&1 && [ -x "$HOME/.cargo/bin/cargo" ]; then
    PATH="$HOME/.cargo/bin:$PATH"
fi
crate=$(mktemp -d)
trap 'rm -rf "$crate"' EXIT
mkdir -p "$crate/src"
cat >"$crate/Cargo.toml" <<TOML
[package]
name = "glyphcast-outside-check"
version = "0.0.0"
edition = "2024"
publish = false

[dependencies]
glyphcast = { path = "$repo" }
glyphcast-wgpu = { path = "$repo/crates/glyphcast-wgpu" }
wgpu = { version = "30", default-features = false }

[profile.dev]
opt-level = 2
debug = "line-tables-only"

[profile.dev.package."*"]
opt-level = 2
debug = false

[profile.dev.package.glyphcast]
debug = "line-tables-only"

[profile.dev.package.glyphcast-shaderc-link]
debug = "line-tables-only"

[profile.dev.package.glyphcast-wgpu]
debug = "line-tables-only"
TOML
cp "$repo/Cargo.lock" "$crate/Cargo.lock"
cat >"$crate/src/main.rs" <<'RUST'
//! One glyph, drawn headless: a sphere of radius 1 (the order-2 tensor x x + y y + z z)
//! at the origin, seen from 5 units up the z axis.
use glyphcast::demo::{fibre_tensor, glyph_set, symmetric};
use glyphcast::glam::DVec3;
use glyphcast::{
    Camera, FrameView, Gpu, GpuOptions, HeadlessRenderer, ImageSize, Projection,
    RenderSettings, Scene, prepare_scene,
};

fn main() -> glyphcast::Result<()> {
    let axes = [(DVec3::X, 1.0), (DVec3::Y, 1.0), (DVec3::Z, 1.0)];
    let set = glyph_set(symmetric(2), vec![DVec3::ZERO], 1.0, vec![fibre_tensor(2, &axes)]);
    let size = 64;
    let scene = Scene {
        glyph_sets: vec![set],
        camera: Camera {
            projection: Projection::Perspective { fov_y_deg: 40.0 },
            eye: DVec3::new(0.0, 0.0, 5.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
        },
        image: ImageSize { width: size, height: size },
    };
    // GLYPHCAST_VALIDATION=1 (set below): the validation layer is on, and any message
    // it reports fails the check.
    let gpu = Gpu::headless(&GpuOptions::from_env())?;
    assert!(gpu.validation_enabled(), "the validation layer is off");
    let mut renderer = HeadlessRenderer::new(&gpu)?;
    let settings = RenderSettings::default();
    let sets = prepare_scene(&scene, settings.offset as f64)?;
    let view = FrameView::new(&scene.camera, size, size);
    let image = renderer.render_view(&gpu, &sets, &view, &settings)?;
    let at = |x: u32, y: u32| (y * image.width + x) as usize;
    let (centre, corner) = (at(size / 2, size / 2), at(0, 0));
    let rgba = |i: usize| &image.rgba[4 * i..4 * i + 4];
    println!(
        "centre: distance {}, rgba {:?}; corner: distance {}, rgba {:?}",
        image.distance[centre],
        rgba(centre),
        image.distance[corner],
        rgba(corner)
    );
    // The ray through the centre meets the sphere 5 - 1 units from the eye (to within a
    // pixel's slope); the corner's misses it, and the two pixels differ.
    assert!((image.distance[centre] - 4.0).abs() < 0.01, "centre distance");
    assert!(image.distance[corner].is_nan(), "corner hit");
    assert_ne!(rgba(centre), rgba(corner), "the glyph is not drawn");
    drop(renderer);
    gpu.check_validation()?;
    println!("one glyph drawn, no validation message");
    Ok(())
}
RUST
mkdir -p "$crate/src/bin"
cat >"$crate/src/bin/wgpu.rs" <<'RUST'
//! The same glyph in a wgpu application's textures: a device from glyphcast-wgpu's
//! `request_device` on a validated Vulkan instance, a 64 x 64 colour and depth texture
//! cleared by the application, the glyphs' command buffers submitted after.
use glyphcast::demo::{fibre_tensor, glyph_set, symmetric};
use glyphcast::glam::{DMat4, DVec3, DVec4};
use glyphcast::render::host_view::{look_at, perspective};
use glyphcast::{DepthConvention, prepare_scene};
use glyphcast_wgpu::validation::ValidatedInstance;
use glyphcast_wgpu::{GlyphPass, GlyphPassDesc, GlyphTarget, WgpuCamera};

const SIZE: u32 = 64;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let validated = ValidatedInstance::new(true)?;
    let adapter = validated.adapter()?;
    let depth_at = draw(&adapter)?;
    let (centre, corner) = (depth_at(SIZE / 2, SIZE / 2), depth_at(0, 0));
    println!("wgpu: centre depth {centre}, corner depth {corner}");
    assert!(centre < 1.0, "no glyph at the centre");
    assert_eq!(corner, 1.0, "a glyph in the corner");
    let messages = validated.messages();
    assert!(messages.is_empty(), "validation: {messages:?}");
    println!("one glyph drawn through wgpu, no validation message");
    Ok(())
}

/// Draws the glyph and returns the depth texture's values.
fn draw(adapter: &wgpu::Adapter) -> Result<impl Fn(u32, u32) -> f32, Box<dyn std::error::Error>> {
    let (device, queue) = glyphcast_wgpu::request_device(adapter, &Default::default())?;
    // SAFETY: the device was made by `request_device`; the textures outlive the frame.
    let mut glyphs = unsafe { GlyphPass::new(adapter, &device, &GlyphPassDesc::default())? };
    let axes = [(DVec3::X, 1.0), (DVec3::Y, 1.0), (DVec3::Z, 1.0)];
    let set = glyph_set(symmetric(2), vec![DVec3::ZERO], 1.0, vec![fibre_tensor(2, &axes)]);
    let scene = glyphcast::Scene {
        glyph_sets: vec![set],
        camera: glyphcast::Camera {
            projection: glyphcast::Projection::Perspective { fov_y_deg: 40.0 },
            eye: DVec3::new(0.0, 0.0, 5.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
        },
        image: glyphcast::ImageSize { width: SIZE, height: SIZE },
    };
    glyphs.set_glyphs(&prepare_scene(&scene, 0.0)?)?;
    let texture = |format| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d { width: SIZE, height: SIZE, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    };
    let color = texture(wgpu::TextureFormat::Rgba8UnormSrgb);
    let depth = texture(wgpu::TextureFormat::Depth32Float);
    let (color_view, depth_view) = (color.create_view(&Default::default()), depth.create_view(&Default::default()));
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &color_view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &depth_view,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
            stencil_ops: None,
        }),
        ..Default::default()
    });
    let vulkan = perspective(40f64.to_radians(), 1.0, 0.5, Some(20.0), DepthConvention::Standard);
    let camera = WgpuCamera {
        view: look_at(scene.camera.eye, scene.camera.target, scene.camera.up),
        projection: DMat4::from_diagonal(DVec4::new(1.0, -1.0, 1.0, 1.0)) * vulkan,
    };
    let target = GlyphTarget { color: &color_view, depth: &depth_view, resolve: None };
    let [states, glyph_commands] = glyphs.encode(&camera, &target)?;
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 4 * (SIZE * SIZE) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut copy = device.create_command_encoder(&Default::default());
    copy.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo { texture: &depth, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::DepthOnly },
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * SIZE), rows_per_image: Some(SIZE) },
        },
        wgpu::Extent3d { width: SIZE, height: SIZE, depth_or_array_layers: 1 },
    );
    queue.submit([encoder.finish(), states, glyph_commands, copy.finish()]);
    readback.slice(..).map_async(wgpu::MapMode::Read, |r| r.expect("mapping the readback"));
    device.poll(wgpu::PollType::wait_indefinitely())?;
    let bytes = readback.slice(..).get_mapped_range()?.to_vec();
    Ok(move |x: u32, y: u32| {
        let i = 4 * (y * SIZE + x) as usize;
        f32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]])
    })
}
RUST
lvp_icd=/usr/share/vulkan/icd.d/lvp_icd.$(uname -m).json
if [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$lvp_icd" ]; then
    export VK_DRIVER_FILES="$lvp_icd"
fi
cd "$crate"
env -u SHADERC_LIB_DIR -u VULKAN_SDK \
    GLYPHCAST_VALIDATION=1 \
    GLYPHCAST_SPIRV_CACHE="${GLYPHCAST_SPIRV_CACHE:-$target/glyphcast-spirv-cache}" \
    cargo run --offline --quiet --target-dir "$target" --bin glyphcast-outside-check
env -u SHADERC_LIB_DIR -u VULKAN_SDK \
    GLYPHCAST_SPIRV_CACHE="${GLYPHCAST_SPIRV_CACHE:-$target/glyphcast-spirv-cache}" \
    cargo run --offline --quiet --target-dir "$target" --bin wgpu
