#![cfg_attr(not(feature = "volume"), warn(missing_docs))]
//! glyphcast: GPU ray casting of higher-order tensor and spherical-harmonic glyphs.
//!
//! The method is that of Hlawitschka, Hijazi, Knoll and Hamann, "Towards a High-quality
//! Visualization of Higher-order Reynold's Glyphs"; where the code says "the paper", it
//! means this one. `docs/architecture.md` maps the modules.
//!
//! # Features
//!
//! The core (glyph math, scenes, the Vulkan layer, the passes and the headless renderer)
//! builds alone: an engine depends on `glyphcast = { default-features = false }` and its
//! dependency tree then holds none of winit, plotters, nifti, clap or indicatif. The
//! default feature `cli` adds the command line and everything it uses: `volume` (NIfTI
//! and MRtrix images, volume slices, the DWI fits), `viewer` (winit windows) and `plots`
//! (benchmark plots).
//!
//! # Rendering offscreen
//!
//! The names most programs need are re-exported at the root. Rendering a scene file's
//! glyphs to pixels and the ray distance per pixel:
//!
//! ```no_run
//! use glyphcast::{Gpu, GpuOptions, HeadlessRenderer, RenderSettings, prepare_scene};
//!
//! fn render(scene: &glyphcast::Scene) -> glyphcast::Result<glyphcast::RenderedImage> {
//!     let gpu = Gpu::headless(&GpuOptions::from_env())?;
//!     let mut renderer = HeadlessRenderer::new(&gpu)?;
//!     let settings = RenderSettings::default();
//!     let sets = prepare_scene(scene, settings.offset as f64)?;
//!     let (w, h) = (scene.image.width, scene.image.height);
//!     renderer.render(&gpu, &sets, &scene.camera, w, h, &settings)
//! }
//! ```
//!
//! # Embedding the ray caster in an engine
//!
//! An engine that owns its Vulkan instance, device, allocator and frame can draw glyphs
//! into its own rendering; glyphcast then creates no instance or device:
//!
//! 1. Wrap the engine's device and [`gpu_allocator`] allocator in a
//!    [`vk::DeviceContext`]. This is `unsafe`: glyphcast never destroys the engine's
//!    objects, so the engine must keep its device, instance and allocator until every
//!    glyphcast object made with the context is dropped.
//! 2. Create a [`RayCastPass`](render::raycast::RayCastPass) for the engine's attachment
//!    formats ([`TargetFormats`](render::raycast::TargetFormats)): colour, depth, and
//!    optionally an R32_SFLOAT attachment for the ray distance. Without one (`distance:
//!    None`) the pass uses fragment shaders that have no distance output.
//! 3. Turn a [`Scene`](scene::Scene) into glyph data on the CPU
//!    ([`prepare_scene`](render::glyph_data::prepare_scene)) and upload it with
//!    [`RayCastPass::upload`](render::raycast::RayCastPass::upload), which gives a
//!    [`SceneGpu`](render::raycast::SceneGpu) (buffers, descriptor sets) and creates the
//!    pipelines the glyph sets need.
//! 4. Per frame, write the camera with
//!    [`SceneGpu::set_frame`](render::raycast::SceneGpu::set_frame) (the buffer is
//!    host-visible and written at once: only after the frames that read it completed),
//!    and inside the engine's dynamic rendering call
//!    [`RayCastPass::record`](render::raycast::RayCastPass::record).
//!
//! What the pass asks of the engine: a Vulkan 1.3 device with `dynamicRendering`;
//! rendering begun with attachments of the formats given at creation; a depth buffer
//! with reversed depth: cleared to 0 and tested with GREATER (1 is the near plane, and
//! perspective depth is near / e for eye depth e, with no far plane, so that float32
//! depth holds its precision at every distance). The glyph shaders write
//! `gl_FragDepth` from [`FrameParams::view_proj`](render::frame::FrameParams), so the
//! engine's own geometry must be drawn with that same matrix (build it with
//! [`FrameParams::new`](render::frame::FrameParams::new) from a
//! [`Camera`](camera::Camera) and the engine's near and far planes in a
//! [`SceneExtent`](render::frame::SceneExtent)); glyphs and geometry then occlude each
//! other per pixel through the shared depth buffer. `record` binds its own pipelines,
//! descriptor sets and vertex buffers and sets viewport and scissor to the extent.
//! `examples/embed/` is a complete engine in plain ash with its own ground plane, and a
//! test of the depth compositing against the float64 reference.
//!
//! ```no_run
//! use ash::vk;
//! use glyphcast::{
//!     Camera, DeviceContext, FrameParams, RayCastPass, RenderSettings, Scene, SceneExtent,
//!     SceneGpu, TargetFormats, prepare_scene,
//! };
//! use gpu_allocator::vulkan::Allocator;
//! use std::sync::{Arc, Mutex};
//!
//! /// Once: glyphcast on the engine's device, for its colour and depth formats.
//! ///
//! /// # Safety
//! /// The engine keeps `instance`, `device` and `allocator` until it has dropped the
//! /// pass and the glyphs (at shutdown, before destroying its own objects).
//! unsafe fn add_glyphs(
//!     instance: &ash::Instance,
//!     physical_device: vk::PhysicalDevice,
//!     device: &ash::Device,
//!     allocator: Arc<Mutex<Allocator>>,
//!     scene: &Scene,
//!     (width, height): (u32, u32),
//! ) -> glyphcast::Result<(RayCastPass, SceneGpu)> {
//!     // SAFETY: `device` comes from `physical_device` of `instance`, `allocator` is its
//!     // own, and the caller keeps all three for as long as the pass and glyphs live.
//!     let context =
//!         unsafe { DeviceContext::new(instance, physical_device, device.clone(), allocator) };
//!     let formats = TargetFormats {
//!         color: vk::Format::B8G8R8A8_SRGB,
//!         depth: vk::Format::D32_SFLOAT,
//!         distance: None,
//!     };
//!     let mut pass = RayCastPass::new(&context, formats)?;
//!     let settings = RenderSettings::default();
//!     let sets = prepare_scene(scene, settings.offset as f64)?;
//!     let frame = engine_frame(&scene.camera, (width, height), &settings);
//!     let glyphs = pass.upload(&context, &sets, &frame, settings.method)?;
//!     Ok((pass, glyphs))
//! }
//!
//! /// The glyphs' frame parameters with the engine's depth range (near 0.1, far 100).
//! fn engine_frame(camera: &Camera, (w, h): (u32, u32), settings: &RenderSettings) -> FrameParams {
//!     let extent = SceneExtent { near: 0.1, far: 100.0, max_radius: 1.0 };
//!     FrameParams::new(camera, w, h, &extent, settings)
//! }
//!
//! /// Each frame, inside the engine's dynamic rendering (after its own geometry, drawn
//! /// with `frame.view_proj` into the same depth buffer).
//! fn draw_glyphs(
//!     pass: &mut RayCastPass,
//!     glyphs: &mut SceneGpu,
//!     cmd: vk::CommandBuffer,
//!     camera: &Camera,
//!     extent: vk::Extent2D,
//! ) -> glyphcast::Result<()> {
//!     let settings = RenderSettings::default();
//!     // Only once the frame that last read the parameters has completed.
//!     glyphs.set_frame(&engine_frame(camera, (extent.width, extent.height), &settings))?;
//!     pass.record(cmd, glyphs, extent, settings.method)
//! }
//! ```
pub mod accuracy;
pub mod bench;
pub mod camera;
pub mod catalog;
pub mod demo;
pub mod error;
#[cfg(feature = "volume")]
pub mod fit;
pub mod glyph;
pub mod io;
pub mod parallel;
#[cfg(feature = "volume")]
pub mod qc;
pub mod render;
pub mod rng;
pub mod scene;
#[cfg(feature = "viewer")]
pub mod viewer;
pub mod vk;
#[cfg(feature = "volume")]
pub mod volume;

pub use error::{Error, Result, Setting};

// The names most programs need, at the root; everything else stays in its module.
pub use camera::{Camera, Projection};
pub use glyph::NegativeMode;
pub use render::frame::{FrameParams, SceneExtent};
pub use render::glyph_data::{GlyphSetData, prepare_scene};
pub use render::headless::{FrameView, HeadlessRenderer, RenderedImage};
pub use render::raycast::{RayCastPass, SceneGpu, TargetFormats};
pub use render::{ColorMode, Method, RenderPath, RenderSettings};
pub use scene::{GlyphKind, GlyphSet, ImageSize, Scene, ShBasis};
pub use vk::{DeviceContext, Gpu, GpuOptions};
