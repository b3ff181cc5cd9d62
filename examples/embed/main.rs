//! Embedding glyphcast in an engine that owns its Vulkan objects and its frame loop.
//!
//! The engine (`engine.rs`, plain ash and gpu-allocator) has its own instance, device,
//! allocator, command buffers and fences, K frames in flight (each with its own
//! attachments, as swapchain images would be), its own camera matrices and depth
//! convention, and its own geometry: a ground plane (`plane.rs`) that cuts through the
//! glyphs. glyphcast's [`GlyphRenderer`] is created once with the engine's device,
//! formats, samples, depth convention and frames in flight; each frame the engine writes
//! frame k's camera (`set_view`) after waiting for frame k's fence, and the renderer
//! records into the engine's open command buffer, inside the same rendering and depth
//! buffer as the plane. glyphcast never submits, waits or presents. Halfway through, the
//! glyphs are replaced (a slice step) while frames are in flight; the old ones are
//! retired, not waited for.
//!
//! With `--path compute` the glyphs are drawn by glyphcast's compute ray caster: each
//! frame, before the engine begins its rendering, the renderer records its dispatches
//! (`record_compute`); inside the rendering, `record` draws their outputs into the
//! engine's attachments, depth-tested against the plane. The engine's images and
//! barriers are the same for both paths.
//!
//! glyphcast's buffers and images take their memory from the engine: from its
//! gpu-allocator allocator (`--allocator gpu-allocator`, the default), or from a second
//! implementation of glyphcast's `MemoryAllocator` trait (`--allocator plain`,
//! `plain_memory.rs`: one vkAllocateMemory per block).
//!
//! ```text
//! cargo run --example embed -- [--frames N] [--in-flight K] [--depth standard|reversed]
//!     [--depth-format d32|d32s8]
//!     [--samples 1|2|4|8] [--allocator gpu-allocator|plain] [--path fragment|compute]
//!     [--proxy box|hull]
//!     [--sync-validation] [--screenshot OUT.png]
//! ```
//! Any validation message (errors and warnings; synchronization validation with
//! `--sync-validation`) makes it exit with 1; an unknown option with 2.
mod engine;
mod plain_memory;
mod plane;

use ash::vk;
use engine::{Engine, Target, Validation, subresource_range};
use glam::{DMat4, DVec3};
use glyphcast::bench::workload::{BlockView, block};
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::render::host_view::{look_at, perspective};
use glyphcast::render::{Culling, Proxy};
use glyphcast::{
    Camera, DepthConvention, DeviceContext, GlyphRenderer, GlyphSetData, HostView, ImageSize,
    PassOptions, Projection, RenderPath, RenderSettings, RendererDesc, Scene, TargetFormats,
    prepare_scene,
};
// Links what completes a split system shaderc (Debian 12's) into the example (plane.rs).
use glyphcast_shaderc_link as _;
use plain_memory::PlainMemory;
use plane::{PlanePass, Square};
use std::path::PathBuf;
use std::sync::Arc;

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

/// Small, so that the tests' 60-frame runs stay quick on a software rasteriser.
const WIDTH: u32 = 128;
const HEIGHT: u32 = 96;
const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The depth-stencil format most engines draw with (`--depth-format d32s8`).
const DEPTH_STENCIL_FORMAT: vk::Format = vk::Format::D32_SFLOAT_S8_UINT;
/// The engine's near plane (its far plane: FAR for standard depth, infinite reversed).
const NEAR: f64 = 0.5;
const FAR: f64 = 40.0;
const FOV_Y_DEG: f64 = 35.0;

/// The command line.
#[derive(Clone, Debug)]
struct Options {
    frames: u32,
    in_flight: usize,
    depth: DepthConvention,
    /// The depth attachment's format: D32_SFLOAT, or D32_SFLOAT_S8_UINT bound as the
    /// rendering's depth and stencil attachment.
    depth_format: vk::Format,
    samples: u32,
    /// Where glyphcast's buffers and images take their memory from.
    allocator: MemorySource,
    validation: Validation,
    screenshot: Option<PathBuf>,
    /// Whether the engine draws its plane (the tests that compare glyph edges leave it
    /// out; not a command-line option).
    plane: bool,
    /// The rectangle of the target the frame is drawn in (an editor's viewport; a test's
    /// option): the whole target if none.
    viewport: Option<vk::Rect2D>,
    /// glyphcast's ray caster: fragment (drawn in the engine's rendering) or compute
    /// (dispatched before it, composed in it).
    path: RenderPath,
    /// Tests: glyphcast's context says the device is a discrete GPU (what `auto` decides
    /// by), and whether the engine records the compute path's dispatches.
    as_gpu: bool,
    dispatches: bool,
    /// Tests: a block of 8 x 8 x 12 band-8 fODFs seen head-on (glyphs hidden behind
    /// others) instead of the six glyphs, and how hidden glyphs are culled.
    block: bool,
    cull: Culling,
    /// Tests: the most bytes of one of glyphcast's storage buffers, as if the device's
    /// range were that small (`None`: the device's).
    storage_limit: Option<u64>,
    /// Whether the engine's device enables fragmentStoresAndAtomics and says so to
    /// glyphcast (`--no-fragment-stores`: a host that asks only for what glyphcast needs,
    /// whose glyphs are drawn without culling).
    fragment_stores: bool,
    /// What glyphcast draws around each glyph (`--proxy`).
    proxy: Proxy,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            frames: 60,
            in_flight: 2,
            depth: DepthConvention::Standard,
            depth_format: DEPTH_FORMAT,
            samples: 1,
            allocator: MemorySource::GpuAllocator,
            validation: Validation::Off,
            screenshot: None,
            plane: true,
            viewport: None,
            path: RenderPath::Fragment,
            as_gpu: false,
            dispatches: true,
            block: false,
            cull: Culling::Occluded,
            storage_limit: None,
            fragment_stores: true,
            proxy: Proxy::Box,
        }
    }
}

/// The engine's allocator that glyphcast's memory comes from (`--allocator`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum MemorySource {
    /// The engine's gpu-allocator `Allocator`, shared.
    GpuAllocator,
    /// [`PlainMemory`]: one vkAllocateMemory per block.
    Plain,
}

/// The options of `args`; GLYPHCAST_VALIDATION=1 turns the layer's core checks on when
/// `--sync-validation` does not ask for more.
fn parse(args: &[String]) -> std::result::Result<Options, String> {
    let mut o = Options::default();
    if std::env::var("GLYPHCAST_VALIDATION").is_ok_and(|v| v != "0") {
        o.validation = Validation::On;
    }
    let mut args = args.iter();
    while let Some(arg) = args.next() {
        let mut value = || {
            args.next()
                .cloned()
                .ok_or_else(|| format!("{arg} needs a value"))
        };
        match arg.as_str() {
            "--frames" => o.frames = number(arg, &value()?, 1)?,
            "--in-flight" => o.in_flight = number(arg, &value()?, 1)? as usize,
            "--samples" => {
                o.samples = number(arg, &value()?, 1)?;
                if ![1, 2, 4, 8].contains(&o.samples) {
                    return Err(format!("{arg}: {} is not 1, 2, 4 or 8", o.samples));
                }
            }
            "--depth" => {
                o.depth = match value()?.as_str() {
                    "standard" => DepthConvention::Standard,
                    "reversed" => DepthConvention::Reversed,
                    other => return Err(format!("{arg}: '{other}' is not standard or reversed")),
                }
            }
            "--depth-format" => {
                o.depth_format = match value()?.as_str() {
                    "d32" => DEPTH_FORMAT,
                    "d32s8" => DEPTH_STENCIL_FORMAT,
                    other => return Err(format!("{arg}: '{other}' is not d32 or d32s8")),
                }
            }
            "--allocator" => {
                o.allocator = match value()?.as_str() {
                    "gpu-allocator" => MemorySource::GpuAllocator,
                    "plain" => MemorySource::Plain,
                    other => {
                        return Err(format!("{arg}: '{other}' is not gpu-allocator or plain"));
                    }
                }
            }
            "--path" => {
                o.path = match value()?.as_str() {
                    "fragment" => RenderPath::Fragment,
                    "compute" => RenderPath::Compute,
                    other => return Err(format!("{arg}: '{other}' is not fragment or compute")),
                }
            }
            "--proxy" => {
                o.proxy = match value()?.as_str() {
                    "box" => Proxy::Box,
                    "hull" => Proxy::Hull,
                    other => return Err(format!("{arg}: '{other}' is not box or hull")),
                }
            }
            "--sync-validation" => o.validation = Validation::Sync,
            "--no-fragment-stores" => o.fragment_stores = false,
            "--screenshot" => o.screenshot = Some(PathBuf::from(value()?)),
            other => return Err(format!("unknown option '{other}'")),
        }
    }
    Ok(o)
}

fn number(flag: &str, text: &str, min: u32) -> std::result::Result<u32, String> {
    match text.parse::<u32>() {
        Ok(n) if n >= min => Ok(n),
        _ => Err(format!("{flag}: '{text}' is not a whole number >= {min}")),
    }
}

/// Six glyphs of order 6 on a 3 x 2 grid at z = 0; `step` turns their fibres (the next
/// slice of a volume, as a viewer's slice step would bring).
fn scene(step: u32) -> Scene {
    let mut centers = Vec::new();
    let mut coeffs = Vec::new();
    for (k, (x, y)) in [(-1.1, -0.55), (0.0, -0.55), (1.1, -0.55)]
        .into_iter()
        .chain([(-1.1, 0.55), (0.0, 0.55), (1.1, 0.55)])
        .enumerate()
    {
        centers.push(DVec3::new(x, y, 0.0));
        let turn = 30.0 * k as f64 + 50.0 * step as f64;
        coeffs.push(fibre_tensor(
            6,
            &[
                (direction(turn, 40.0), 1.0),
                (direction(turn + 90.0, -20.0), 0.7),
            ],
        ));
    }
    Scene {
        glyph_sets: vec![glyph_set(symmetric(6), centers, 0.5, coeffs)],
        camera: camera(0),
        image: ImageSize {
            width: WIDTH,
            height: HEIGHT,
        },
    }
}

/// The plane just above the glyphs' centres, cutting all of them.
const SQUARE: Square = Square {
    center: [0.0, 0.0],
    height: 0.08,
    half: 2.2,
};

/// The camera of frame `frame`: it moves every frame, a slow orbit looking down.
fn camera(frame: u32) -> Camera {
    let angle = (-75.0 + 0.8 * frame as f64).to_radians();
    Camera {
        projection: Projection::Perspective {
            fov_y_deg: FOV_Y_DEG,
        },
        eye: DVec3::new(4.4 * angle.cos(), 4.4 * angle.sin(), 3.0),
        target: DVec3::ZERO,
        up: DVec3::Z,
    }
}

/// The engine's matrices for `camera`: a right-handed view, and a Vulkan projection (y
/// down) in the engine's depth convention: finite far plane for standard depth, infinite
/// for reversed (the two that engines commonly use).
fn host_matrices(camera: &Camera, depth: DepthConvention, rect: vk::Rect2D) -> (DMat4, DMat4) {
    let view = look_at(camera.eye, camera.target, camera.up);
    let aspect = rect.extent.width as f64 / rect.extent.height as f64;
    let fov = FOV_Y_DEG.to_radians();
    let far = match depth {
        DepthConvention::Standard => Some(FAR),
        DepthConvention::Reversed => None,
    };
    (view, perspective(fov, aspect, NEAR, far, depth))
}

/// One frame in flight's attachments, command buffer and fence.
struct Slot {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// One sample per pixel: drawn into at 1 sample, resolved into otherwise.
    color: Target,
    depth: Target,
    /// The multisampled attachments (colour, depth) when samples > 1.
    multisampled: Option<(Target, Target)>,
    /// The depth attachments' kind: with a stencil aspect or without.
    depth_kind: Attachment,
}

impl Slot {
    fn new(
        engine: &Engine,
        cmd: vk::CommandBuffer,
        (samples, depth_format): (vk::SampleCountFlags, vk::Format),
    ) -> Result<Slot> {
        let size = extent();
        let depth_kind = Attachment::Depth {
            stencil: depth_format == DEPTH_STENCIL_FORMAT,
        };
        let one = vk::SampleCountFlags::TYPE_1;
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let read = vk::ImageUsageFlags::TRANSFER_SRC;
        let (c, d) = (vk::ImageAspectFlags::COLOR, depth_kind.aspect());
        let multisampled = if samples == one {
            None
        } else {
            Some((
                engine.create_image(
                    "msaa colour",
                    size,
                    (COLOR_FORMAT, samples),
                    color_usage,
                    c,
                )?,
                engine.create_image("msaa depth", size, (depth_format, samples), depth_usage, d)?,
            ))
        };
        let info = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        Ok(Slot {
            cmd,
            // SAFETY: valid device; destroyed in `destroy`.
            fence: unsafe { engine.device.create_fence(&info, None)? },
            color: engine.create_image(
                "colour",
                size,
                (COLOR_FORMAT, one),
                color_usage | read,
                c,
            )?,
            depth: engine.create_image(
                "depth",
                size,
                (depth_format, one),
                depth_usage | read,
                d,
            )?,
            multisampled,
            depth_kind,
        })
    }

    /// (image, aspect, kind) of every attachment, for the barriers.
    fn images(&self) -> Vec<(vk::Image, Attachment)> {
        let mut images = vec![
            (self.color.image, Attachment::Color),
            (self.depth.image, self.depth_kind),
        ];
        if let Some((color, depth)) = &self.multisampled {
            images.push((color.image, Attachment::Color));
            images.push((depth.image, self.depth_kind));
        }
        images
    }

    fn destroy(self, engine: &Engine) -> Result<()> {
        // SAFETY: the engine waited for the device; the fence is not in use.
        unsafe { engine.device.destroy_fence(self.fence, None) };
        engine.destroy_image(self.color)?;
        engine.destroy_image(self.depth)?;
        if let Some((color, depth)) = self.multisampled {
            engine.destroy_image(color)?;
            engine.destroy_image(depth)?;
        }
        Ok(())
    }
}

fn extent() -> vk::Extent2D {
    vk::Extent2D {
        width: WIDTH,
        height: HEIGHT,
    }
}

/// What the run leaves: the last frame's pictures and what the engine saw (the tests
/// read all of it; the program only the picture and the messages).
#[cfg_attr(not(test), allow(dead_code))]
struct Run {
    rgba: Vec<u8>,
    /// The last frame's window depth (sample 0 when multisampled).
    depth: Vec<f32>,
    validation: Vec<String>,
    /// Retired glyph uploads the renderer still held after the last frame.
    retired_at_end: usize,
    /// With `--allocator plain`: (blocks glyphcast took from it, blocks not given back
    /// once the renderer and context were dropped).
    plain_blocks: Option<(usize, usize)>,
    /// The last frame's camera and projection, and the glyphs it showed.
    camera: Camera,
    projection: DMat4,
    sets: Vec<GlyphSetData>,
    /// The ray caster the last glyphs were drawn with (`GlyphRenderer::path`).
    path: RenderPath,
    /// How the last frame's hidden glyphs were planned to be culled
    /// (`GlyphRenderer::culling`).
    culling: Culling,
}

fn run(options: &Options) -> Result<Run> {
    let engine = Engine::new(options.validation, options.fragment_stores)?;
    let result = run_on(&engine, options);
    let mut run = result?;
    run.validation = engine.validation_messages();
    Ok(run)
}

fn run_on(engine: &Engine, options: &Options) -> Result<Run> {
    let plain = (options.allocator == MemorySource::Plain).then(|| {
        Arc::new(PlainMemory::new(
            &engine.instance,
            engine.physical_device,
            engine.device.clone(),
        ))
    });
    let mut run = draw_frames(engine, options, plain.clone())?;
    // The renderer and context were dropped with `draw_frames`: every block is back.
    run.plain_blocks = plain.map(|p| p.counts());
    Ok(run)
}

/// glyphcast's context on the engine's device, with memory from `plain` if given, else
/// from the engine's gpu-allocator allocator.
fn context(engine: &Engine, plain: Option<Arc<PlainMemory>>) -> DeviceContext {
    // SAFETY: the device was made from this physical device and instance with dynamic
    // rendering and sample-rate shading, and both allocators allocate for it. Callers
    // drop the context (and all made with it) before the engine destroys its allocator,
    // device and instance.
    unsafe {
        match plain {
            Some(plain) => DeviceContext::with_memory(
                &engine.instance,
                engine.physical_device,
                engine.device.clone(),
                plain,
            ),
            None => DeviceContext::new(
                &engine.instance,
                engine.physical_device,
                engine.device.clone(),
                engine.allocator(),
            ),
        }
    }
}

fn draw_frames(engine: &Engine, options: &Options, plain: Option<Arc<PlainMemory>>) -> Result<Run> {
    // glyphcast on the engine's device and memory: no instance or device of its own. The
    // context and renderer are locals, dropped before this function returns.
    let mut context = context(engine, plain);
    if options.fragment_stores {
        // SAFETY: the engine enabled fragmentStoresAndAtomics (`Engine::new`).
        context = unsafe { context.with_fragment_stores() };
    }
    if options.as_gpu {
        context = context.with_device_type(vk::PhysicalDeviceType::DISCRETE_GPU);
    }
    let samples = vk::SampleCountFlags::from_raw(options.samples);
    let settings = RenderSettings {
        path: options.path,
        cull: options.cull,
        proxy: options.proxy,
        ..RenderSettings::default()
    };
    let blocks = options
        .block
        .then(|| block((8, 8, 12), 8, BlockView::Front, WIDTH, HEIGHT))
        .transpose()?;
    let (first, second) = match &blocks {
        // The same block twice (the glyphs are still replaced halfway).
        Some(b) => (prepare_scene(b, 0.0)?, prepare_scene(b, 0.0)?),
        None => (
            prepare_scene(&scene(0), settings.offset as f64)?,
            prepare_scene(&scene(1), settings.offset as f64)?,
        ),
    };
    let camera = |frame| blocks.as_ref().map_or_else(|| camera(frame), |b| b.camera);
    let desc = RendererDesc {
        formats: TargetFormats {
            color: COLOR_FORMAT,
            depth: options.depth_format,
            distance: None,
        },
        options: PassOptions {
            samples,
            depth: options.depth,
            pipeline_cache: vk::PipelineCache::null(),
            ..PassOptions::default()
        },
        frames_in_flight: options.in_flight,
        settings,
    };
    let mut glyphs = GlyphRenderer::new(&context, &desc)?;
    glyphs
        .pass_mut()
        .set_storage_buffer_limit(options.storage_limit);
    // Pipelines at load time, before any frame.
    let layouts: Vec<_> = first.iter().map(|s| (s.layout, s.shape)).collect();
    glyphs.prepare(&layouts)?;
    glyphs.set_glyphs(&first)?;
    let plane = PlanePass::new(
        &engine.device,
        (COLOR_FORMAT, options.depth_format),
        samples,
        options.depth.compare_op(),
    )?;
    let cmds = engine.command_buffers(options.in_flight as u32)?;
    let slots = cmds
        .into_iter()
        .map(|cmd| Slot::new(engine, cmd, (samples, options.depth_format)))
        .collect::<Result<Vec<_>>>()?;
    let bytes = 4 * WIDTH as u64 * HEIGHT as u64;
    let color_readback = engine.create_readback("colour readback", bytes)?;
    let depth_readback = engine.create_readback("depth readback", bytes)?;
    let last = options.frames - 1;
    let rect = options.viewport.unwrap_or(extent().into());
    let mut sets = &first;
    let d = &engine.device;
    for frame in 0..options.frames {
        let slot = &slots[frame as usize % options.in_flight];
        // SAFETY: the fence belongs to this device; waiting for it ends the slot's last
        // frame, so its command buffer and frame block may be reused.
        unsafe {
            d.wait_for_fences(&[slot.fence], true, u64::MAX)?;
            d.reset_fences(&[slot.fence])?;
        }
        if frame == options.frames / 2 {
            // The slice step: new glyphs while other frames are in flight; no wait.
            glyphs.set_glyphs(&second)?;
            sets = &second;
        }
        let camera = camera(frame);
        let (view, projection) = host_matrices(&camera, options.depth, rect);
        let index = frame as usize % options.in_flight;
        let host_view = HostView {
            view,
            projection,
            viewport: vk::Viewport {
                x: rect.offset.x as f32,
                y: rect.offset.y as f32,
                width: rect.extent.width as f32,
                height: rect.extent.height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            },
            scissor: rect,
        };
        glyphs.set_view(index, &host_view)?;
        let view_proj = (projection * view).as_mat4().to_cols_array_2d();
        // SAFETY: the slot's previous submission completed (its fence).
        unsafe {
            d.reset_command_buffer(slot.cmd, vk::CommandBufferResetFlags::empty())?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            d.begin_command_buffer(slot.cmd, &begin)?;
        }
        // Outside the rendering: the compute path's dispatches into glyphcast's own
        // buffers (on the fragment path, the clearing of its early outs' known depths
        // where the frame takes them; with `auto` on a GPU, this is what lets it take
        // the compute path).
        if options.dispatches {
            glyphs.record_compute(slot.cmd, index)?;
        }
        record_frame(engine, slot, options.depth, |cmd| {
            if options.plane {
                plane.record(cmd, rect, view_proj, &SQUARE);
            }
            glyphs.record(cmd, index)?;
            Ok(())
        })?;
        if frame == last {
            record_readback(engine, slot, &color_readback, &depth_readback);
        }
        let cmds = [slot.cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        // SAFETY: recorded above; the fence was reset.
        unsafe {
            d.end_command_buffer(slot.cmd)?;
            d.queue_submit(engine.queue, &submit, slot.fence)?;
        }
    }
    // SAFETY: waits for the engine's own submissions before reading and destroying.
    unsafe { d.device_wait_idle()? };
    let run = Run {
        rgba: engine.read(&color_readback)?.to_vec(),
        depth: bytemuck::pod_collect_to_vec::<u8, f32>(engine.read(&depth_readback)?),
        validation: Vec::new(),
        retired_at_end: glyphs.retired_count(),
        plain_blocks: None,
        camera: camera(last),
        projection: host_matrices(&camera(last), options.depth, rect).1,
        sets: sets.clone(),
        path: glyphs.path(),
        culling: glyphs.culling(last as usize % options.in_flight),
    };
    engine.destroy_readback(color_readback)?;
    engine.destroy_readback(depth_readback)?;
    for slot in slots {
        slot.destroy(engine)?;
    }
    Ok(run)
}

/// The frame's rendering: attachments cleared (depth to the convention's far end), the
/// engine's draws by `draw`, multisampled attachments resolved into the slot's
/// one-sample images (colour averaged, depth of sample 0).
fn record_frame(
    engine: &Engine,
    slot: &Slot,
    depth: DepthConvention,
    draw: impl FnOnce(vk::CommandBuffer) -> Result<()>,
) -> Result<()> {
    let d = &engine.device;
    let cmd = slot.cmd;
    let to_attachment: Vec<_> = slot
        .images()
        .into_iter()
        .map(|(image, kind)| kind.to_attachment(image))
        .collect();
    let clear_color = vk::ClearValue {
        color: vk::ClearColorValue {
            float32: [0.55, 0.65, 0.8, 1.0],
        },
    };
    let clear_depth = vk::ClearValue {
        depth_stencil: vk::ClearDepthStencilValue {
            depth: depth.clear_depth(),
            stencil: 0,
        },
    };
    let attachment = |view, layout, clear| {
        vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(layout)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(clear)
    };
    let color_layout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    let depth_layout = slot.depth_kind.stage_access().2;
    let (color, depth_attachment) = match &slot.multisampled {
        None => (
            attachment(slot.color.view, color_layout, clear_color),
            attachment(slot.depth.view, depth_layout, clear_depth),
        ),
        Some((ms_color, ms_depth)) => (
            attachment(ms_color.view, color_layout, clear_color)
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(slot.color.view)
                .resolve_image_layout(color_layout),
            attachment(ms_depth.view, depth_layout, clear_depth)
                .resolve_mode(vk::ResolveModeFlags::SAMPLE_ZERO)
                .resolve_image_view(slot.depth.view)
                .resolve_image_layout(depth_layout),
        ),
    };
    let colors = [color];
    let mut rendering = vk::RenderingInfo::default()
        .render_area(extent().into())
        .layer_count(1)
        .color_attachments(&colors)
        .depth_attachment(&depth_attachment);
    if let Attachment::Depth { stencil: true } = slot.depth_kind {
        // A depth-stencil image is the rendering's stencil attachment as well: the same
        // view, cleared to 0 and resolved alike.
        rendering = rendering.stencil_attachment(&depth_attachment);
    }
    // SAFETY: `cmd` is recording; all handles live until the frame's fence signals.
    unsafe {
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_attachment),
        );
        d.cmd_begin_rendering(cmd, &rendering);
    }
    draw(cmd)?;
    // SAFETY: as above.
    unsafe { d.cmd_end_rendering(cmd) };
    Ok(())
}

/// Copies the slot's one-sample colour and depth into the readback buffers.
fn record_readback(
    engine: &Engine,
    slot: &Slot,
    color_readback: &engine::Readback,
    depth_readback: &engine::Readback,
) {
    let d = &engine.device;
    let cmd = slot.cmd;
    let images = [
        (slot.color.image, Attachment::Color),
        (slot.depth.image, slot.depth_kind),
    ];
    let to_transfer: Vec<_> = images
        .iter()
        .map(|(image, kind)| kind.to_transfer(*image))
        .collect();
    let copy = |aspect| {
        vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: aspect,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            })
            .image_extent(extent().into())
    };
    let host_read = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::COPY)
        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)];
    let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
    // SAFETY: `cmd` is recording outside rendering; images and buffers are alive until
    // the device is idle.
    unsafe {
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_transfer),
        );
        let color_copy = [copy(vk::ImageAspectFlags::COLOR)];
        let depth_copy = [copy(vk::ImageAspectFlags::DEPTH)];
        d.cmd_copy_image_to_buffer(
            cmd,
            slot.color.image,
            src,
            color_readback.buffer,
            &color_copy,
        );
        d.cmd_copy_image_to_buffer(
            cmd,
            slot.depth.image,
            src,
            depth_readback.buffer,
            &depth_copy,
        );
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&host_read),
        );
    }
}

#[derive(Clone, Copy)]
enum Attachment {
    Color,
    /// A depth attachment, with a stencil aspect or without.
    Depth {
        stencil: bool,
    },
}

impl Attachment {
    /// Every stage and access an attachment sees in a frame: drawing, resolving (a
    /// resolve writes in the colour-output stage, also for depth) and the readback copy.
    fn stage_access(self) -> (vk::PipelineStageFlags2, vk::AccessFlags2, vk::ImageLayout) {
        let resolve = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        match self {
            Attachment::Color => (
                resolve.0,
                resolve.1 | vk::AccessFlags2::COLOR_ATTACHMENT_READ,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            ),
            Attachment::Depth { stencil } => (
                vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                    | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS
                    | resolve.0,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                    | resolve.1,
                if stencil {
                    vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL
                } else {
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL
                },
            ),
        }
    }

    fn aspect(self) -> vk::ImageAspectFlags {
        match self {
            Attachment::Color => vk::ImageAspectFlags::COLOR,
            Attachment::Depth { stencil: false } => vk::ImageAspectFlags::DEPTH,
            Attachment::Depth { stencil: true } => {
                vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
            }
        }
    }

    /// To the attachment layout, after whatever the image's previous frame did with it
    /// (drawn, resolved, copied from): the engine reuses a slot's images every K frames.
    fn to_attachment(self, image: vk::Image) -> vk::ImageMemoryBarrier2<'static> {
        let (stage, access, layout) = self.stage_access();
        vk::ImageMemoryBarrier2::default()
            .image(image)
            .subresource_range(subresource_range(self.aspect()))
            .src_stage_mask(stage | vk::PipelineStageFlags2::COPY)
            .src_access_mask(access | vk::AccessFlags2::TRANSFER_READ)
            .old_layout(vk::ImageLayout::UNDEFINED)
            .new_layout(layout)
            .dst_stage_mask(stage)
            .dst_access_mask(access)
    }

    fn to_transfer(self, image: vk::Image) -> vk::ImageMemoryBarrier2<'static> {
        let (stage, access, layout) = self.stage_access();
        vk::ImageMemoryBarrier2::default()
            .image(image)
            .subresource_range(subresource_range(self.aspect()))
            .old_layout(layout)
            .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
            .src_stage_mask(stage)
            .src_access_mask(access)
            .dst_stage_mask(vk::PipelineStageFlags2::COPY)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)
    }
}

/// The engine's window depth of a `width` x `height` viewport back to the distance along
/// each pixel's ray, NaN where the depth is the cleared far end. For a perspective
/// projection (w = -z), window depth z_w = -P22 + P32 / e at eye depth e.
#[cfg(test)]
fn depth_to_distance(
    depth: &[f32],
    camera: &Camera,
    projection: &DMat4,
    (width, height): (u32, u32),
) -> Vec<f64> {
    let p = projection.to_cols_array_2d();
    let fwd = camera.frame().fwd;
    depth
        .iter()
        .enumerate()
        .map(|(k, &z)| {
            let eye_depth = p[3][2] / (z as f64 + p[2][2]);
            if !(eye_depth > 0.0 && eye_depth < FAR * 0.999) {
                return f64::NAN;
            }
            let (i, j) = ((k as u32) % width, (k as u32) / width);
            eye_depth / camera.ray(i, j, width, height).dir.dot(fwd)
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let options = match parse(&args) {
        Ok(options) => options,
        Err(message) => {
            eprintln!("embed: {message}");
            eprintln!(
                "usage: embed [--frames N] [--in-flight K] [--depth standard|reversed] \
                 [--samples 1|2|4|8] [--allocator gpu-allocator|plain] [--sync-validation] \
                 [--no-fragment-stores] [--screenshot OUT.png]"
            );
            std::process::exit(2);
        }
    };
    let code = match run_and_report(&options) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("embed: {e}");
            1
        }
    };
    std::process::exit(code);
}

fn run_and_report(options: &Options) -> Result<()> {
    let run = run(options)?;
    if let Some(path) = &options.screenshot {
        glyphcast::io::png::write_png_rgba8(path, WIDTH, HEIGHT, &run.rgba)?;
        println!("wrote {}", path.display());
    }
    println!(
        "{} frames, {} in flight, {:?} depth, {} sample(s), {:?} memory: {} validation \
         message(s)",
        options.frames,
        options.in_flight,
        options.depth,
        options.samples,
        options.allocator,
        run.validation.len()
    );
    if let Some((allocated, live)) = run.plain_blocks {
        println!("plain allocator: {allocated} blocks for glyphcast, {live} not given back");
        if live > 0 {
            return Err(format!("{live} memory block(s) not given back").into());
        }
    }
    if !run.validation.is_empty() {
        return Err(format!("{} validation message(s)", run.validation.len()).into());
    }
    Ok(())
}

#[cfg(test)]
mod tests;
