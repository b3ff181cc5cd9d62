#![warn(missing_docs)]
//! glyphcast: GPU ray casting of higher-order tensor and spherical-harmonic glyphs.
//!
//! The method is that of Hlawitschka, Hijazi, Knoll and Hamann, "Towards a High-quality
//! Visualization of Higher-order Reynold's Glyphs"; where the code says "the paper", it
//! means this one. `docs/architecture.md` maps the modules.
//!
//! # Crates
//!
//! This crate is the renderer core: glyph math, scenes, the Vulkan layer, the passes,
//! the engine component and the headless renderer. An engine depends on it alone; its
//! dependency tree holds none of winit, plotters, nifti, clap or indicatif. The front ends
//! are crates of their own around it: `glyphcast-dmri` (NIfTI and MRtrix images, volume
//! slices, the DWI fits, peaks and QC sets), `glyphcast-viewer` (winit windows),
//! `glyphcast-cli` (the `glyphcast` command line), `glyphcast-materials` (elastic
//! surfaces of stiffness tensors), and the Python module and the C API. The feature
//! `window` adds the surfaces and swapchains the viewer draws into.
//!
//! The Vulkan, maths and memory crates of the public API are re-exported ([`ash`],
//! [`glam`], [`gpu_allocator`]), so a host uses the versions glyphcast was built with.
//!
//! # Rendering offscreen
//!
//! The names most programs need are re-exported at the root. Rendering a scene file's
//! glyphs to pixels and the ray distance per pixel:
//!
//! ```no_run
//! use glyphcast::{FrameView, Gpu, GpuOptions, HeadlessRenderer, RenderSettings, prepare_scene};
//!
//! fn render(scene: &glyphcast::Scene) -> glyphcast::Result<glyphcast::RenderedImage> {
//!     let gpu = Gpu::headless(&GpuOptions::from_env())?;
//!     let mut renderer = HeadlessRenderer::new(&gpu)?;
//!     let settings = RenderSettings::default();
//!     let sets = prepare_scene(scene, settings.offset as f64)?;
//!     let (w, h) = (scene.image.width, scene.image.height);
//!     renderer.render_view(&gpu, &sets, &FrameView::new(&scene.camera, w, h), &settings)
//! }
//! ```
//!
//! # Embedding the ray caster in an engine
//!
//! An engine that owns its Vulkan instance, device, allocator and frame loop draws glyphs
//! into its own rendering with a [`GlyphRenderer`];
//! glyphcast then creates no instance or device and never submits, presents or waits.
//! docs/guide/embedding.md has the whole contract; in short:
//!
//! 1. Wrap the engine's device and [`gpu_allocator`] allocator in a
//!    [`vk::DeviceContext`] (`unsafe`: the engine keeps its device, instance and
//!    allocator until every glyphcast object made with the context is dropped).
//! 2. Once: [`GlyphRenderer::new`](render::component::GlyphRenderer::new) with a
//!    [`RendererDesc`]: attachment formats, samples
//!    (1, 2, 4, 8), depth convention (standard or reversed), an optional pipeline cache,
//!    frames in flight and the render settings. `prepare` makes pipelines ahead of time.
//! 3. `set_glyphs` uploads glyph data once for every frame in flight; calling it again
//!    (a slice step) never waits: the old data is released after every frame index has
//!    been begun again.
//! 4. Each frame k, after the engine waited for frame k's fence: `set_view(k, &view)`
//!    with its view and projection matrices, viewport and scissor
//!    ([`HostView`]); then, inside the engine's dynamic
//!    rendering, `record(cmd, k)` (`&self`: threads may record at once).
//!
//! ```no_run
//! use ash::vk;
//! use glam::DMat4;
//! use glyphcast::{
//!     DepthConvention, DeviceContext, GlyphRenderer, HostView, PassOptions, RenderSettings,
//!     RendererDesc, Scene, TargetFormats, prepare_scene,
//! };
//! use gpu_allocator::vulkan::Allocator;
//! use std::sync::{Arc, Mutex};
//!
//! /// Once: glyphcast on the engine's device, for its formats, 4x MSAA, standard depth
//! /// and 2 frames in flight.
//! ///
//! /// # Safety
//! /// The engine keeps `instance`, `device` and `allocator` until it has dropped the
//! /// renderer (at shutdown, after waiting for its device, before destroying its own
//! /// objects).
//! unsafe fn add_glyphs(
//!     instance: &ash::Instance,
//!     physical_device: vk::PhysicalDevice,
//!     device: &ash::Device,
//!     allocator: Arc<Mutex<Allocator>>,
//!     scene: &Scene,
//! ) -> glyphcast::Result<GlyphRenderer> {
//!     // SAFETY: `device` comes from `physical_device` of `instance`, `allocator` is its
//!     // own, and the caller keeps all three for as long as the renderer lives.
//!     let context =
//!         unsafe { DeviceContext::new(instance, physical_device, device.clone(), allocator) };
//!     let desc = RendererDesc {
//!         formats: TargetFormats {
//!             color: vk::Format::B8G8R8A8_SRGB,
//!             depth: vk::Format::D32_SFLOAT,
//!             distance: None,
//!         },
//!         options: PassOptions {
//!             samples: vk::SampleCountFlags::TYPE_4,
//!             depth: DepthConvention::Standard,
//!             pipeline_cache: vk::PipelineCache::null(),
//!             ..PassOptions::default() // dynamic rendering, not a render pass
//!         },
//!         frames_in_flight: 2,
//!         settings: RenderSettings::default(),
//!     };
//!     let mut glyphs = GlyphRenderer::new(&context, &desc)?;
//!     glyphs.set_glyphs(&prepare_scene(scene, desc.settings.offset as f64)?)?;
//!     Ok(glyphs)
//! }
//!
//! /// Each frame, after waiting for frame `k`'s fence, inside the engine's rendering.
//! fn draw_glyphs(
//!     glyphs: &mut GlyphRenderer,
//!     cmd: vk::CommandBuffer,
//!     k: usize,
//!     (view, projection): (DMat4, DMat4),
//!     extent: vk::Extent2D,
//! ) -> glyphcast::Result<()> {
//!     glyphs.set_view(k, &HostView::whole(view, projection, extent.width, extent.height))?;
//!     glyphs.record(cmd, k)
//! }
//! ```
//!
//! `examples/embed/` is a complete engine in plain ash with its own ground plane, frames
//! in flight, MSAA and either depth convention, tested under synchronization validation
//! against the headless renderer, which draws its ray-cast glyphs through the same
//! [`GlyphRenderer`], as the viewer does with 2 frames in flight. An engine that does not use gpu-allocator gives glyphcast its own
//! memory with [`DeviceContext::with_memory`] and a [`vk::MemoryAllocator`]. The
//! lower-level [`RayCastPass`] (pipelines) and
//! [`SceneGpu`] (uploaded glyphs with one frame block per
//! frame in flight) are what the component is built on.
pub mod accuracy;
pub mod bench;
pub mod camera;
pub mod catalog;
pub mod demo;
pub mod error;
pub mod glyph;
pub mod io;
pub mod parallel;
pub mod render;
pub mod rng;
pub mod scene;
pub mod vk;

pub use error::{Asked, Error, LayoutName, Result, Setting};

// The crates whose types the public API takes and returns.
pub use ash;
pub use glam;
pub use gpu_allocator;

// The names most programs need, at the root; everything else stays in its module.
pub use camera::{Camera, Projection};
pub use glyph::NegativeMode;
pub use render::component::{GlyphRenderer, RendererDesc, UploadedGlyphs};
pub use render::frame::{FrameParams, SceneExtent};
pub use render::glyph_data::{GlyphSetData, prepare_scene};
pub use render::headless::{FrameView, HeadlessRenderer, RenderedImage};
pub use render::host_view::HostView;
pub use render::raycast::{FrameTarget, PassOptions, RayCastPass, SceneGpu, TargetFormats};
pub use render::shaders::DepthConvention;
pub use render::{ColorMode, Method, RenderPath, RenderSettings};
pub use scene::{GlyphKind, GlyphSet, ImageSize, Scene, ShBasis};
pub use vk::{DeviceContext, Gpu, GpuOptions};
