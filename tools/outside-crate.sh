#!/usr/bin/env bash
# An engine's first build: a new crate outside the repository (a temporary folder) that
# depends on glyphcast by path, built with plain `cargo` and no environment script
# sourced (no SHADERC_LIB_DIR, no VULKAN_SDK), draws one glyph headless and checks the
# pixels: the shaderc that glyphcast's build script links is found and completed by
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
lvp_icd=/usr/share/vulkan/icd.d/lvp_icd.$(uname -m).json
if [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$lvp_icd" ]; then
    export VK_DRIVER_FILES="$lvp_icd"
fi
cd "$crate"
env -u SHADERC_LIB_DIR -u VULKAN_SDK \
    GLYPHCAST_VALIDATION=1 \
    GLYPHCAST_SPIRV_CACHE="${GLYPHCAST_SPIRV_CACHE:-$target/glyphcast-spirv-cache}" \
    cargo run --offline --quiet --target-dir "$target"
