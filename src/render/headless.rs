//! Offscreen rendering: colour (RGBA8 sRGB), ray distance (R32F) and D32 depth targets,
//! the glyph pass of the settings' method recorded between them (the ray-cast pass for
//! the ray caster and the sphere impostor, the mesh pass for tessellated glyphs), and a
//! readback of colour and distance. With `--path compute` the exact method runs as the
//! compute ray caster instead, whose colour and distance buffers are read back the same
//! way.
//!
//! The ray-cast glyphs are drawn through the engine component
//! ([`GlyphRenderer`], one frame in flight): each prepared frame holds its glyphs as
//! [`UploadedGlyphs`] and records them with [`GlyphRenderer::record_glyphs`], the call an
//! engine's `record` makes, so there is one way to draw.
use crate::camera::Camera;
use crate::error::{Error, Result, Setting};
use crate::render::component::{GlyphRenderer, RendererDesc, UploadedGlyphs};
use crate::render::compute::{
    ComposePipeline, ComputeGlyphsGpu, ComputeRayCastPass, ComputeSceneGpu,
};
use crate::render::frame::{FrameParams, SceneExtent};
use crate::render::glyph_data::GlyphSetData;
use crate::render::glyph_shadows::{GlyphShadowPass, HITS_HEADER, HitsBuffer};
use crate::render::mesh::{GlyphMeshes, MeshPass, MeshSceneGpu, MeshStats};
use crate::render::peaks::{PeakSet, PeaksGpu, PeaksPass};
use crate::render::raycast::{FrameTarget, PassOptions, RayCastPass, TargetFormats};
use crate::render::settings::RenderSettings;
use crate::render::underlay::{
    Underlay, UnderlayGpu, UnderlayPass, UnderlayPlane, extent_with_planes,
};
use crate::render::underlay_shadows::UnderlayShadowPass;
use crate::render::visibility::{KNOWN_DEPTH_HEADER, VisibilityBuffers, WorkCounts};
use crate::render::{Method, RenderPath};
use crate::vk::recording::{
    COLOR_OUTPUT, COPY_READ, COPY_WRITE, DEPTH_TESTS, FRAGMENT_STORAGE, NOTHING, TRANSFER_READS,
    TRANSFER_WRITES, cleared_color_attachment, color_image_copy, copies_to_host, layout_transition,
    memory_barrier,
};
use crate::vk::{Buffer, Gpu, GpuTimer, Image, OneShot};
use ash::vk;
use gpu_allocator::MemoryLocation;

/// The offscreen colour target: 8-bit sRGB RGBA, as the PNG is written.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
/// The ray-distance target (the depth map's values; negative where no glyph is hit).
pub(crate) const DISTANCE_FORMAT: vk::Format = vk::Format::R32_SFLOAT;
/// The depth buffer (reversed: cleared to 0, tested with GREATER).
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The offscreen targets' formats, which every pass of the renderer draws into.
const FORMATS: TargetFormats = TargetFormats {
    color: COLOR_FORMAT,
    depth: DEPTH_FORMAT,
    distance: Some(DISTANCE_FORMAT),
};

/// The second rendering's attachments, where shadows fall on the glyphs and the underlay
/// after the frame: colour and depth (a pipeline that blends one colour attachment and
/// writes none of another needs the independentBlend feature).
const RECEIVER_FORMATS: TargetFormats = TargetFormats {
    distance: None,
    ..FORMATS
};

/// What a frame shows: the camera, the image size in pixels and, optionally, the
/// anatomical underlay and the fibre peaks drawn in the glyphs' depth buffer.
#[derive(Clone, Copy)]
pub struct FrameView<'a> {
    /// The camera.
    pub camera: &'a Camera,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The underlay's planes, if any.
    pub underlay: Option<&'a Underlay>,
    /// The fibre peaks, if any.
    pub peaks: Option<&'a PeakSet>,
}

impl<'a> FrameView<'a> {
    /// `camera` on a `width` x `height` image, without an underlay.
    pub fn new(camera: &'a Camera, width: u32, height: u32) -> Self {
        FrameView {
            camera,
            width,
            height,
            underlay: None,
            peaks: None,
        }
    }

    /// The same view with `underlay` drawn in it.
    pub fn with_underlay(self, underlay: Option<&'a Underlay>) -> Self {
        FrameView { underlay, ..self }
    }

    /// The same view with `peaks` drawn in it.
    pub fn with_peaks(self, peaks: Option<&'a PeakSet>) -> Self {
        FrameView { peaks, ..self }
    }
}

/// What a headless render produces.
#[derive(Clone, Debug)]
pub struct RenderedImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// sRGB-encoded RGBA, row-major from the top-left.
    pub rgba: Vec<u8>,
    /// Distance along each pixel's ray to the first hit, NaN for a miss.
    pub distance: Vec<f32>,
    /// Instanced draws recorded: one per glyph set, more where a set was split.
    pub draws: usize,
    /// GPU time of the glyph pass (timestamps around the rendering), if the queue has them.
    pub gpu_ms: Option<f64>,
    /// Sizes and generation time of the meshes, for tessellated glyphs.
    pub mesh: Option<MeshStats>,
    /// The ray caster that drew it (what `auto` chose).
    pub path: RenderPath,
    /// Passes its glyphs were drawn in: more than one where hidden glyphs were culled
    /// in passes (`cull`), 1 otherwise.
    pub passes: usize,
    /// How its hidden glyphs were skipped: `Passes`, `EarlyOut`, or `Off` (drawn as
    /// without culling).
    pub culling: crate::render::Culling,
}

impl RenderedImage {
    /// What culling of hidden glyphs was asked for in `settings` and what this frame did,
    /// in one short phrase for a person, as `render` prints it and `bench`'s `cull` column
    /// gives it: `occluded: 9 passes`, `occluded: early outs (1 pass)`, `occluded: none
    /// needed (1 pass)`, `off (1 pass)`, or `passes: none (...)` with the reason where
    /// the asked way could not be taken. `gpu` is the device that drew it.
    pub fn culling_report(
        &self,
        gpu: &crate::Gpu,
        settings: &crate::render::RenderSettings,
    ) -> Result<String> {
        let factor = crate::render::settings::supersampling_factor(settings.samples)?;
        let drawn = crate::render::culling_report::Drawn {
            path: self.path,
            culling: self.culling,
            passes: self.passes,
            target: (self.width * factor, self.height * factor),
        };
        Ok(crate::render::culling_report::report(
            gpu.context(),
            settings,
            drawn,
        ))
    }
}

/// The offscreen targets of one image size, with their readback buffers.
struct Targets {
    color: Image,
    distance: Image,
    depth: Image,
    /// Where frames are culled in passes: the images of the later passes' first stage.
    stages: Option<StageImages>,
    color_readback: Buffer,
    distance_readback: Buffer,
    /// The work counters and the depth copied between the glyphs' passes.
    visibility: VisibilityBuffers,
}

/// The images of a later pass's first stage (render::visibility): the nearest ray
/// distance of its glyphs, and the scratch colour image it draws beside it.
struct StageImages {
    nearest: Image,
    scratch: Image,
}

impl StageImages {
    fn new(gpu: &Gpu, extent: vk::Extent2D) -> Result<StageImages> {
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        Ok(StageImages {
            nearest: Image::new(
                gpu.context(),
                "nearest distance",
                extent,
                DISTANCE_FORMAT,
                color_usage,
                vk::ImageAspectFlags::COLOR,
            )?,
            scratch: Image::new(
                gpu.context(),
                "scratch colour",
                extent,
                COLOR_FORMAT,
                vk::ImageUsageFlags::COLOR_ATTACHMENT,
                vk::ImageAspectFlags::COLOR,
            )?,
        })
    }
}

impl Targets {
    /// The targets of `extent`, with the visibility buffers of set layout `visibility`
    /// (for no culling where its known depths exceed `limit` bytes), and with `passes`
    /// the images of the later passes' stages.
    fn new(
        gpu: &Gpu,
        extent: vk::Extent2D,
        visibility: vk::DescriptorSetLayout,
        (limit, passes): (u64, bool),
    ) -> Result<Targets> {
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let pixels = extent.width as u64 * extent.height as u64;
        Ok(Targets {
            color: Image::new(
                gpu.context(),
                "colour",
                extent,
                COLOR_FORMAT,
                color_usage,
                vk::ImageAspectFlags::COLOR,
            )?,
            distance: Image::new(
                gpu.context(),
                "distance",
                extent,
                DISTANCE_FORMAT,
                color_usage,
                vk::ImageAspectFlags::COLOR,
            )?,
            depth: Image::new(
                gpu.context(),
                "depth",
                extent,
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::TRANSFER_DST,
                vk::ImageAspectFlags::DEPTH,
            )?,
            stages: passes.then(|| StageImages::new(gpu, extent)).transpose()?,
            visibility: VisibilityBuffers::new(
                gpu.context(),
                visibility,
                (extent.width, extent.height),
                (limit, passes),
            )?,
            color_readback: Buffer::new(
                gpu.context(),
                "colour readback",
                4 * pixels,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?,
            distance_readback: Buffer::new(
                gpu.context(),
                "distance readback",
                4 * pixels,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?,
        })
    }
}

/// Renders glyph sets headless. Owns its passes so pipelines are reused across renders.
pub struct HeadlessRenderer {
    /// The ray caster (and sphere impostor), one frame in flight.
    glyphs: GlyphRenderer,
    mesh: MeshPass,
    compute: ComputeRayCastPass,
    /// Made on first use: most renders have no underlay and no peaks, and each pass's
    /// pipeline costs a few milliseconds to create.
    underlay: Option<UnderlayPass>,
    /// The underlay receiving shadows, made on first use too.
    underlay_shadows: Option<UnderlayShadowPass>,
    /// The glyphs' shadows, cast after the frame from the hits its distance attachment
    /// holds (render::glyph_shadows), made on first use too.
    glyph_shadows: Option<GlyphShadowPass>,
    peaks: Option<PeaksPass>,
    commands: OneShot,
    timer: Option<GpuTimer>,
}

impl HeadlessRenderer {
    /// The passes and command buffers for offscreen frames on `gpu`.
    pub fn new(gpu: &Gpu) -> Result<HeadlessRenderer> {
        let desc = RendererDesc {
            formats: FORMATS,
            // glyphcast's own targets: one sample, reversed depth, dynamic rendering.
            options: PassOptions::default(),
            frames_in_flight: 1,
            settings: RenderSettings::default(),
        };
        let mut glyphs = GlyphRenderer::new(gpu.context(), &desc)?;
        // Only the visible hits cast shadow rays: after the frame (render::glyph_shadows).
        glyphs.pass_mut().set_deferred_shadows(true);
        // Hidden glyphs are skipped in passes (render::visibility).
        glyphs.set_draws_passes(true);
        Ok(HeadlessRenderer {
            glyphs,
            mesh: MeshPass::new(gpu.context(), FORMATS)?,
            compute: ComputeRayCastPass::new(gpu.context())?,
            underlay: None,
            underlay_shadows: None,
            glyph_shadows: None,
            peaks: None,
            commands: OneShot::new(gpu)?,
            timer: GpuTimer::new(gpu)?,
        })
    }

    /// Compiles the ray-casting pipelines of `variants` (from
    /// [`early_variants`](crate::render::promote::early_variants)) now, in
    /// parallel, rather than at the first frame's upload: a one-shot render calls it on a
    /// thread of its own while the glyphs are prepared.
    pub fn prepare_pipelines(
        &mut self,
        variants: &[crate::render::raycast::Variant],
    ) -> Result<()> {
        self.glyphs.pass_mut().prepare_pipelines(variants)
    }

    /// The ray-cast pass, for settings such as the storage buffer limit.
    pub fn pass_mut(&mut self) -> &mut RayCastPass {
        self.glyphs.pass_mut()
    }

    /// The mesh pass, for settings such as the storage buffer limit.
    pub fn mesh_pass_mut(&mut self) -> &mut MeshPass {
        &mut self.mesh
    }

    /// The compute ray caster, for settings such as the storage buffer limit.
    pub fn compute_pass_mut(&mut self) -> &mut ComputeRayCastPass {
        &mut self.compute
    }

    /// Renders `sets`, and the view's underlay planes (if any) in the same depth buffer,
    /// as `view` sees them.
    ///
    /// With `settings.samples` = s^2 > 1 (4 or 16) the colour is supersampled: drawn at s
    /// times the size and box-filtered down (`render::antialias`), so that edge pixels
    /// take the fraction of their s x s samples that glyphs (or the underlay) cover, in
    /// linear light, and alpha is that coverage over a transparent background. The
    /// distance map is drawn at the image's own size, one ray per pixel centre, so it
    /// keeps the scene format's contract whatever the sample count.
    pub fn render_view(
        &mut self,
        gpu: &Gpu,
        sets: &[GlyphSetData],
        view: &FrameView,
        settings: &RenderSettings,
    ) -> Result<RenderedImage> {
        let factor = crate::render::antialias::supersampling_factor(settings.samples)?;
        if factor == 1 {
            return self.render_once(gpu, sets, view, settings);
        }
        let (big_w, big_h) = crate::render::antialias::supersampled_size(
            view.width,
            view.height,
            factor,
            settings.samples,
        )?;
        check_image_size(gpu, big_w, big_h)?;
        let single = RenderSettings {
            samples: 1,
            ..*settings
        };
        let big_view = FrameView {
            width: big_w,
            height: big_h,
            ..*view
        };
        let big = self.render_once(gpu, sets, &big_view, &single)?;
        let rgba =
            crate::render::antialias::box_filter(&big.rgba, view.width, view.height, factor)?;
        let big_ms = big.gpu_ms;
        drop(big);
        let mut image = self.render_once(gpu, sets, view, &single)?;
        image.rgba = rgba;
        image.gpu_ms = match (image.gpu_ms, big_ms) {
            (Some(a), Some(b)) => Some(a + b),
            _ => None,
        };
        Ok(image)
    }

    /// One render at one sample per pixel.
    fn render_once(
        &mut self,
        gpu: &Gpu,
        sets: &[GlyphSetData],
        view: &FrameView,
        settings: &RenderSettings,
    ) -> Result<RenderedImage> {
        let frame = self.prepare_view(gpu, sets, view, settings)?;
        let gpu_ms = self.draw(gpu, &frame)?;
        let mut image = read_back(&frame.targets, view.width, view.height)?;
        image.draws = frame.draws();
        image.passes = frame.passes();
        image.culling = frame.culling();
        image.mesh = frame.mesh_stats().copied();
        image.gpu_ms = gpu_ms;
        image.path = frame.path();
        gpu.check_validation()?;
        Ok(image)
    }

    /// Uploads the glyph sets (tessellated first, for the mesh methods) and creates the
    /// targets: everything a frame needs, so that it can be drawn many times (benchmarks)
    /// without uploading again. The view's underlay and peaks, if any, are drawn in the
    /// glyphs' depth buffer; the depth range covers them too. Neither goes
    /// with the compute path, which has no depth buffer to share.
    pub fn prepare_view(
        &mut self,
        gpu: &Gpu,
        sets: &[GlyphSetData],
        view: &FrameView,
        settings: &RenderSettings,
    ) -> Result<PreparedFrame> {
        let FrameView {
            camera,
            width,
            height,
            underlay,
            peaks,
        } = *view;
        settings.validate()?;
        check_image_size(gpu, width, height)?;
        // `auto` is decided here, for this device and these glyphs. Culling needs the
        // target's known depths in one storage buffer: a larger target (8192 x 8192 on a
        // device of 128 MiB, such as lavapipe of Mesa 25) is drawn without it.
        let limit = self.glyphs.pass().storage_buffer_limit(gpu.context());
        let culls = crate::render::visibility::known_depths_fit(limit, width, height);
        let settings = &RenderSettings {
            path: settings.path.on_context(
                gpu.context(),
                settings.method,
                sets.iter().map(|set| set.shape),
            ),
            cull: if culls {
                settings.cull
            } else {
                crate::render::Culling::Off
            },
            ..*settings
        };
        let extent = frame_extent(camera, sets, settings, underlay, peaks);
        let params = FrameParams::new(camera, width, height, &extent, settings);
        let scene = match settings.method {
            _ if settings.path == RenderPath::Compute => {
                let (glyphs, scene) =
                    self.compute
                        .upload(gpu.context(), sets, &params, camera, (width, height))?;
                let compose = self
                    .compute
                    .compose_pipeline(FORMATS, crate::vk::RasterTarget::default())?;
                // The shadows are cast after the frame from its hits, as on the fragment
                // path: by the glyphs' boxes drawn again, so those are uploaded too.
                let shadows = if settings.shadows.enabled() || settings.ambient_occlusion.enabled()
                {
                    let boxes = RenderSettings {
                        path: RenderPath::Fragment,
                        ..*settings
                    };
                    let mut glyphs = self.glyphs.upload(sets, &boxes)?;
                    let whole = FrameTarget::whole(vk::Extent2D { width, height });
                    glyphs.set_frame(&params, &whole)?;
                    Some(glyphs)
                } else {
                    None
                };
                GlyphsOnGpu::Compute(Box::new(ComputeFrame {
                    scene,
                    _glyphs: glyphs,
                    compose,
                    shadows,
                }))
            }
            Method::Mesh(kind) => {
                let meshes = GlyphMeshes::build(sets, kind)?;
                GlyphsOnGpu::Mesh(Box::new(self.mesh.upload(
                    gpu.context(),
                    &meshes,
                    &params,
                )?))
            }
            _ => {
                let mut glyphs = self.glyphs.upload(sets, settings)?;
                let whole = FrameTarget::whole(vk::Extent2D { width, height });
                glyphs.set_frame(&params, &whole)?;
                self.glyphs.prepare_passes(&glyphs, 0, false)?;
                GlyphsOnGpu::RayCast(Box::new(glyphs))
            }
        };
        let size = vk::Extent2D { width, height };
        let underlay = underlay
            .map(|u| -> Result<_> {
                let pass = match &mut self.underlay {
                    Some(pass) => pass,
                    None => self
                        .underlay
                        .insert(UnderlayPass::new(gpu.context(), FORMATS)?),
                };
                let on_gpu = pass.upload(gpu.context(), &u.volume)?;
                Ok((on_gpu, u.planes.clone()))
            })
            .transpose()?;
        // Shadows and occlusion fall on the underlay too.
        if let (Some(_), Some(glyphs)) = (&underlay, scene.shadow_casters())
            && glyphs.gpu.shadows
        {
            let pass = match &mut self.underlay_shadows {
                Some(pass) => pass,
                None => self
                    .underlay_shadows
                    .insert(UnderlayShadowPass::new(gpu.context(), RECEIVER_FORMATS)?),
            };
            pass.prepare(glyphs)?;
        }
        // The glyphs' shadows, cast after the frame from its hits.
        let hits = match scene.shadow_casters() {
            Some(glyphs) if glyphs.gpu.deferred => {
                let pass = match &mut self.glyph_shadows {
                    Some(pass) => pass,
                    None => self
                        .glyph_shadows
                        .insert(GlyphShadowPass::new(gpu.context(), RECEIVER_FORMATS)?),
                };
                pass.prepare(glyphs)?;
                Some(pass.hits(size, limit)?)
            }
            _ => None,
        };
        let peaks_gpu = match peaks {
            Some(p) => {
                let pass = match &mut self.peaks {
                    Some(pass) => pass,
                    None => self.peaks.insert(PeaksPass::new(gpu.context(), FORMATS)?),
                };
                pass.upload(gpu.context(), p, &params)?
            }
            None => None,
        };
        let visibility = self.glyphs.pass().visibility_set_layout()?;
        // Only glyphs culled in passes draw the later passes' stages.
        let passes = matches!(&scene, GlyphsOnGpu::RayCast(glyphs)
            if glyphs.cull() == crate::render::Culling::Passes);
        Ok(PreparedFrame {
            scene,
            targets: Targets::new(gpu, size, visibility, (limit, passes))?,
            count_work: false,
            size,
            settings: *settings,
            underlay,
            peaks: peaks_gpu.map(|on_gpu| (on_gpu, peaks.cloned().unwrap_or_default())),
            view_proj: params.view_proj,
            hits,
        })
    }

    /// Draws a prepared frame and waits for it; returns the glyph pass's GPU time.
    pub fn draw(&mut self, gpu: &Gpu, frame: &PreparedFrame) -> Result<Option<f64>> {
        // A camera moved by `set_camera` may need passes the first one did not.
        if let GlyphsOnGpu::RayCast(glyphs) = &frame.scene {
            self.glyphs.prepare_passes(glyphs, 0, frame.count_work)?;
        }
        let passes = (
            &self.glyphs,
            &mut self.mesh,
            &mut self.compute,
            (self.underlay.as_ref(), self.underlay_shadows.as_ref()),
            self.peaks.as_ref(),
            self.glyph_shadows.as_ref(),
        );
        let timer = self.timer.as_ref();
        self.commands
            .run(gpu, |cmd| record_frame(passes, timer, gpu, cmd, frame))?;
        self.timer.as_ref().map(GpuTimer::elapsed_ms).transpose()
    }

    /// The image of the last `draw` of `frame`.
    pub fn read(&self, gpu: &Gpu, frame: &PreparedFrame) -> Result<RenderedImage> {
        let mut image = read_back(&frame.targets, frame.size.width, frame.size.height)?;
        image.draws = frame.draws();
        image.passes = frame.passes();
        image.culling = frame.culling();
        image.mesh = frame.mesh_stats().copied();
        image.path = frame.path();
        gpu.check_validation()?;
        Ok(image)
    }
}

/// The glyphs of a frame as the method's pass holds them (boxed: gpu-allocator's
/// allocations make both kilobytes large).
enum GlyphsOnGpu {
    RayCast(Box<UploadedGlyphs>),
    Mesh(Box<MeshSceneGpu>),
    Compute(Box<ComputeFrame>),
}

/// The glyphs of a frame on the compute path.
struct ComputeFrame {
    /// The tile lists and outputs of the compute ray caster (dropped before the glyphs
    /// its descriptor sets hold).
    scene: ComputeSceneGpu,
    /// The glyphs on the GPU.
    _glyphs: ComputeGlyphsGpu,
    /// The draw of its outputs into the frame's attachments.
    compose: ComposePipeline,
    /// The glyphs' boxes, for the shadows and occlusion cast after the frame (as on the
    /// fragment path); `None` without either.
    shadows: Option<UploadedGlyphs>,
}

impl GlyphsOnGpu {
    /// The glyphs uploaded as boxes to cast rays: drawn on the fragment path, drawn again
    /// to cast shadows after the frame on both ray casters.
    fn shadow_casters(&self) -> Option<&UploadedGlyphs> {
        match self {
            GlyphsOnGpu::RayCast(glyphs) => Some(glyphs),
            GlyphsOnGpu::Compute(frame) => frame.shadows.as_ref(),
            GlyphsOnGpu::Mesh(_) => None,
        }
    }
}

/// A frame ready to draw: the uploaded glyph sets and the offscreen targets.
pub struct PreparedFrame {
    scene: GlyphsOnGpu,
    targets: Targets,
    size: vk::Extent2D,
    settings: RenderSettings,
    /// The underlay's volume on the GPU and its planes, if any.
    underlay: Option<(UnderlayGpu, Vec<UnderlayPlane>)>,
    /// The peaks on the GPU and as given, if any.
    peaks: Option<(PeaksGpu, PeakSet)>,
    /// The frame's world-to-clip matrix, which the underlay's planes share.
    view_proj: [[f32; 4]; 4],
    /// Where the glyphs' shadows are cast after the frame: its hits.
    hits: Option<HitsBuffer>,
    /// Whether the next draws count their work ([`PreparedFrame::count_work`]).
    count_work: bool,
}

impl PreparedFrame {
    /// Whether the next draws count the fragments' work (a little slower: atomic counters
    /// in the fragment shaders); [`PreparedFrame::work`] reads the counts.
    pub fn count_work(&mut self, on: bool) {
        self.count_work = on;
    }

    /// The work of the last draw that counted (see [`WorkCounts`]); `None` for the
    /// tessellated and compute paths, which do not count.
    pub fn work(&self) -> Result<Option<WorkCounts>> {
        match &self.scene {
            GlyphsOnGpu::RayCast(glyphs) if self.count_work => Ok(Some(
                self.targets.visibility.counts(glyphs.passes(0).max(1))?,
            )),
            _ => Ok(None),
        }
    }

    /// The ray caster that draws the frame: the settings' path, with `auto` decided for
    /// the device and the glyphs ([`RenderPath::on_device`]).
    pub fn path(&self) -> RenderPath {
        self.settings.path
    }

    /// Passes the glyphs are drawn in (render::visibility); 1 for the tessellated and
    /// compute paths.
    pub fn passes(&self) -> usize {
        match &self.scene {
            GlyphsOnGpu::RayCast(glyphs) => glyphs.passes(0).max(1),
            _ => 1,
        }
    }

    /// How the frame skips hidden glyphs (render::visibility): `Passes`, `EarlyOut`, or
    /// `Off` (a flat field, culling off, the tessellated and compute paths).
    pub fn culling(&self) -> crate::render::Culling {
        match &self.scene {
            GlyphsOnGpu::RayCast(glyphs) => glyphs.culling(0),
            _ => crate::render::Culling::Off,
        }
    }

    /// Instanced draws per frame (dispatches for the compute ray caster).
    pub fn draws(&self) -> usize {
        match &self.scene {
            GlyphsOnGpu::RayCast(glyphs) => glyphs.draws(),
            GlyphsOnGpu::Mesh(scene) => scene.draws(),
            GlyphsOnGpu::Compute(frame) => frame.scene.dispatches(),
        }
    }

    /// Moves the camera, keeping the uploaded glyphs (`sets` are the ones the frame was
    /// prepared from): the next `draw` sees the glyphs from `camera`. Returns `false`,
    /// changing nothing, on the compute path, whose tile lists depend on the camera
    /// (prepare the frame again there). Not while a draw of the frame is in flight.
    pub fn set_camera(&mut self, sets: &[GlyphSetData], camera: &Camera) -> Result<bool> {
        let (width, height) = (self.size.width, self.size.height);
        let mut extent = SceneExtent::for_settings(camera, sets, &self.settings);
        if let Some((_, planes)) = &self.underlay {
            extent = extent_with_planes(camera, extent, planes);
        }
        if let Some((_, peaks)) = &self.peaks {
            extent = peaks.widen(camera, extent);
        }
        let params = FrameParams::new(camera, width, height, &extent, &self.settings);
        if let Some((on_gpu, _)) = &mut self.peaks {
            on_gpu.set_frame(&params)?;
        }
        match &mut self.scene {
            GlyphsOnGpu::RayCast(glyphs) => {
                glyphs.set_frame(&params, &FrameTarget::whole(self.size))?
            }
            GlyphsOnGpu::Mesh(scene) => scene.set_frame(&params)?,
            GlyphsOnGpu::Compute(_) => return Ok(false),
        }
        Ok(true)
    }

    /// Sizes and generation time of the meshes, for tessellated glyphs.
    pub fn mesh_stats(&self) -> Option<&MeshStats> {
        match &self.scene {
            GlyphsOnGpu::RayCast(_) | GlyphsOnGpu::Compute(_) => None,
            GlyphsOnGpu::Mesh(scene) => Some(&scene.stats),
        }
    }
}

type Passes<'a> = (
    &'a GlyphRenderer,
    &'a mut MeshPass,
    &'a mut ComputeRayCastPass,
    (Option<&'a UnderlayPass>, Option<&'a UnderlayShadowPass>),
    Option<&'a PeaksPass>,
    Option<&'a GlyphShadowPass>,
);

fn record_frame(
    (glyphs, mesh, compute, (underlay, underlay_shadows), peaks, glyph_shadows): Passes,
    timer: Option<&GpuTimer>,
    gpu: &Gpu,
    cmd: vk::CommandBuffer,
    frame: &PreparedFrame,
) -> Result<()> {
    let (d, extent) = (gpu.device(), frame.size);
    // The timed span is the glyph pass: from the cleared attachments (and, on the compute
    // path, the dispatches before them) to the last fragment.
    if let GlyphsOnGpu::Compute(on_gpu) = &frame.scene {
        if let Some(timer) = timer {
            timer.start(cmd);
        }
        compute.record(cmd, &on_gpu.scene)?;
    }
    let early_out = frame.culling() == crate::render::Culling::EarlyOut;
    clear_visibility(
        d,
        cmd,
        &frame.targets.visibility,
        (frame.count_work, early_out),
    );
    begin_targets(d, cmd, &frame.targets);
    if let (Some(timer), false) = (timer, matches!(frame.scene, GlyphsOnGpu::Compute(_))) {
        timer.start(cmd);
    }
    let targets = &frame.targets;
    let color_attachments = [
        cleared_color_attachment(targets.color.view, frame.settings.background),
        // -1: no glyph along the ray (read back as NaN).
        cleared_color_attachment(targets.distance.view, [-1.0, 0.0, 0.0, 0.0]),
    ];
    // Kept: the glyphs' later passes load it, and copy it before they begin.
    let mut depth_attachment = crate::vk::cleared_depth_attachment(targets.depth.view)
        .store_op(vk::AttachmentStoreOp::STORE);
    // The underlay receives the glyphs' shadows only where the frame has both and the
    // glyphs were uploaded to cast rays.
    let casters = frame.scene.shadow_casters();
    let receives = frame.underlay.is_some() && casters.is_some_and(|glyphs| glyphs.gpu.shadows);
    // The glyphs' shadows, cast after the frame from its hits.
    let casts = match (casters, &frame.hits, glyph_shadows) {
        (Some(on_gpu), Some(hits), Some(pass)) if on_gpu.gpu.deferred => Some((on_gpu, hits, pass)),
        _ => None,
    };
    if receives || casts.is_some() {
        // Kept for the shadows, drawn in a second rendering.
        depth_attachment = depth_attachment.store_op(vk::AttachmentStoreOp::STORE);
    }
    let rendering = vk::RenderingInfo::default()
        .render_area(extent.into())
        .layer_count(1)
        .color_attachments(&color_attachments)
        .depth_attachment(&depth_attachment);
    // SAFETY: `cmd` is recording; every handle is alive until the submission completes.
    unsafe { d.cmd_begin_rendering(cmd, &rendering) };
    // A frame with an underlay or peaks was prepared by the pass that records them.
    if let (Some((volume, planes)), Some(underlay)) = (&frame.underlay, underlay) {
        underlay.record(cmd, volume, planes, frame.view_proj, extent);
    }
    match &frame.scene {
        GlyphsOnGpu::RayCast(on_gpu) => {
            let visibility = &targets.visibility;
            let count = frame.count_work;
            let mut later_passes = 0;
            let mut restart = |cmd, stage| {
                if stage == crate::vk::DrawStage::Nearest {
                    later_passes += 1;
                }
                let first = later_passes == 1;
                restart_rendering(d, cmd, targets, extent, (stage, count, first))
            };
            glyphs.record_glyph_passes(cmd, on_gpu, (0, count), visibility, &mut restart)?
        }
        GlyphsOnGpu::Mesh(scene) => mesh.record(cmd, scene, extent)?,
        GlyphsOnGpu::Compute(on_gpu) => {
            compute.record_compose(cmd, &on_gpu.scene, on_gpu.compose, [0, 0]);
        }
    }
    if let (Some((on_gpu, _)), Some(peaks)) = (&frame.peaks, peaks) {
        peaks.record(cmd, on_gpu, extent);
    }
    // SAFETY: as above.
    unsafe { d.cmd_end_rendering(cmd) };
    if let Some((_, hits, _)) = casts {
        copy_hits(d, cmd, targets, hits, extent);
    }
    // The glyphs' boxes and the underlay's planes again, darkened by the shadows of the
    // glyphs drawn before: in a rendering of the colour and depth attachments only (a
    // pipeline that blends one attachment and not another needs the independentBlend
    // feature).
    let underlay_receives = match (receives, &frame.underlay, casters, underlay_shadows) {
        (true, Some((volume, planes)), Some(on_gpu), Some(receiver)) => {
            Some((volume, planes, on_gpu, receiver))
        }
        _ => None,
    };
    if casts.is_some() || underlay_receives.is_some() {
        let color = [loaded_attachment(
            targets.color.view,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        )];
        let depth = loaded_attachment(
            targets.depth.view,
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
        );
        let rendering = vk::RenderingInfo::default()
            .render_area(extent.into())
            .layer_count(1)
            .color_attachments(&color)
            .depth_attachment(&depth);
        let written = vk::MemoryBarrier2::default()
            .src_stage_mask(COLOR_OUTPUT.0 | DEPTH_TESTS.0)
            .src_access_mask(COLOR_OUTPUT.1 | DEPTH_TESTS.1)
            .dst_stage_mask(COLOR_OUTPUT.0 | DEPTH_TESTS.0)
            .dst_access_mask(
                COLOR_OUTPUT.1 | vk::AccessFlags2::COLOR_ATTACHMENT_READ | DEPTH_TESTS.1,
            );
        // SAFETY: as above.
        unsafe {
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&[written]),
            );
            d.cmd_begin_rendering(cmd, &rendering);
        }
        let recorded = casts
            .map(|(on_gpu, hits, pass)| pass.record(cmd, (on_gpu, 0), hits, extent))
            .transpose()
            .and_then(|_| {
                underlay_receives
                    .map(|(volume, planes, on_gpu, receiver)| {
                        let glyphs = (on_gpu, 0);
                        receiver.record(cmd, glyphs, (volume, planes), frame.view_proj, extent)
                    })
                    .transpose()
            });
        // SAFETY: as above.
        unsafe { d.cmd_end_rendering(cmd) };
        recorded?;
    }
    if let Some(timer) = timer {
        timer.stop(cmd);
    }
    copy_targets_to_host(d, cmd, targets, extent);
    Ok(())
}

/// Before the frame: the known depths' row length and the first pass's visibility word,
/// the work counters at zero when the frame counts, and with early outs the known depths
/// at the clear depth (no hit yet).
fn clear_visibility(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    visibility: &VisibilityBuffers,
    (count, early_out): (bool, bool),
) {
    let mut word = visibility_word(count, crate::vk::DrawStage::Normal);
    let mut clear = None;
    if early_out {
        word |= crate::catalog::codes::VISIBILITY_EARLY_OUT;
        clear = Some(PassOptions::default().depth.clear_depth());
    }
    // The targets' first pixel: (0, 0).
    visibility.record_frame_start(d, cmd, (word, [0, 0]), (clear, count));
}

/// The visibility word of a pass (glsl/raycast_common.glsl): whether it counts its work,
/// and which stage of a later pass it is.
fn visibility_word(count: bool, stage: crate::vk::DrawStage) -> u32 {
    use crate::catalog::codes::{VISIBILITY_COUNT, VISIBILITY_GATE, VISIBILITY_SHADE_NEAREST};
    use crate::vk::DrawStage;
    let count = if count { VISIBILITY_COUNT } else { 0 };
    count
        | match stage {
            DrawStage::Normal => 0,
            DrawStage::Nearest => VISIBILITY_GATE,
            DrawStage::Shade => VISIBILITY_SHADE_NEAREST,
        }
}

/// The bytes of the gate of a later pass's second stage, which fills the nearest
/// distances' buffer during its first stage.
fn gate_bytes(visibility: &VisibilityBuffers) -> u64 {
    4 * u64::from(visibility.pixels)
}

/// The whole depth image as a buffer copy region, its values after the buffer's
/// `offset` bytes.
fn depth_copy(extent: vk::Extent2D, offset: u64) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .buffer_offset(offset)
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::DEPTH,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        })
}

/// Between the stages of the glyphs' later passes (render::visibility): ends the
/// rendering and begins the next one.
///
/// - `Nearest`: before the first later pass (`first`), the depth copied into the known
///   depths (before the others they hold it already); the gate shut; then a scratch
///   colour image that is never read and the nearest-distance image, cleared to
///   infinity, with the depth attachment tested before the fragments run and not written.
/// - `Shade`: the gate copied into the depth attachment, and the nearest distances into
///   its buffer in its place (the word of the second stage written), then the colour
///   and distance attachments with that depth attachment.
/// - `Normal`: the known depths, which the second stage's hits updated, copied into the
///   depth attachment; then the frame's usual rendering.
fn restart_rendering(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    t: &Targets,
    extent: vk::Extent2D,
    (stage, count, first): (crate::vk::DrawStage, bool, bool),
) -> Result<()> {
    use crate::vk::DrawStage;
    let stages = t.stages.as_ref().ok_or(Error::Call {
        call: "restart_rendering",
        expected: "the targets of a frame culled in passes",
    })?;
    let attachment = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    let depth_layout = vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL;
    let color_load = (
        COLOR_OUTPUT.0,
        vk::AccessFlags2::COLOR_ATTACHMENT_READ | COLOR_OUTPUT.1,
    );
    // Each rendering loads what the one before wrote.
    let attachments = [
        memory_barrier(COLOR_OUTPUT, color_load),
        memory_barrier(DEPTH_TESTS, DEPTH_TESTS),
    ];
    let known = t.visibility.known.handle;
    let loaded = |view| loaded_attachment(view, attachment);
    let depth = loaded_attachment(t.depth.view, depth_layout);
    let infinity = [f32::INFINITY, 0.0, 0.0, 0.0];
    let color_attachments = match stage {
        DrawStage::Nearest => [
            // Never read (the stage's colour output, blended as the distance is, since
            // a device without independentBlend takes no other): neither cleared nor
            // stored.
            vk::RenderingAttachmentInfo::default()
                .image_view(stages.scratch.view)
                .image_layout(attachment)
                .load_op(vk::AttachmentLoadOp::DONT_CARE)
                .store_op(vk::AttachmentStoreOp::DONT_CARE),
            cleared_color_attachment(stages.nearest.view, infinity),
        ],
        _ => [loaded(t.color.view), loaded(t.distance.view)],
    };
    let rendering = vk::RenderingInfo::default()
        .render_area(extent.into())
        .layer_count(1)
        .color_attachments(&color_attachments)
        .depth_attachment(&depth);
    // SAFETY: `cmd` is recording inside a rendering of the glyphs' passes; the images
    // and buffers are alive until the submission completes.
    unsafe {
        d.cmd_end_rendering(cmd);
        match stage {
            DrawStage::Nearest => {
                // Before the first later pass, the depth drawn so far (by the first pass
                // and anything before it) into the known depths, which the first stage
                // compares its hits with (the later passes find it there: the known
                // depths were copied into the depth attachment after the pass before);
                // then the gate shut at every pixel.
                let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                let depth_range = t.depth.subresource_range();
                let depth_image = t.depth.handle;
                let to_copy = [layout_transition(
                    depth_image,
                    depth_range,
                    (depth_layout, src),
                    DEPTH_TESTS,
                    COPY_READ,
                )];
                let back = [layout_transition(
                    depth_image,
                    depth_range,
                    (src, depth_layout),
                    COPY_READ,
                    DEPTH_TESTS,
                )];
                let copies = usize::from(first);
                let before = [
                    memory_barrier(FRAGMENT_STORAGE, TRANSFER_WRITES),
                    memory_barrier(FRAGMENT_STORAGE, TRANSFER_READS),
                    memory_barrier(TRANSFER_READS, TRANSFER_WRITES),
                    attachments[0],
                ];
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default()
                        .memory_barriers(&before)
                        .image_memory_barriers(&to_copy[..copies]),
                );
                if first {
                    let copy = [depth_copy(extent, KNOWN_DEPTH_HEADER)];
                    d.cmd_copy_image_to_buffer(cmd, depth_image, src, known, &copy);
                }
                let shut = PassOptions::default().depth.near_depth().to_bits();
                let gate = t.visibility.nearest.handle;
                d.cmd_fill_buffer(cmd, gate, 0, gate_bytes(&t.visibility), shut);
                d.cmd_fill_buffer(cmd, known, 4, 4, visibility_word(count, stage));
                let after = [
                    memory_barrier(TRANSFER_WRITES, FRAGMENT_STORAGE),
                    attachments[1],
                ];
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default()
                        .memory_barriers(&after)
                        .image_memory_barriers(&back[..copies]),
                );
            }
            DrawStage::Shade => {
                // The first stage's gate into the depth attachment, which the second
                // stage's boxes are tested against (the depth drawn so far is in the
                // known depths), and its nearest distances into their buffer.
                let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
                let (depth_range, nearest_range) = (
                    t.depth.subresource_range(),
                    stages.nearest.subresource_range(),
                );
                let nearest_image = stages.nearest.handle;
                let depth_image = t.depth.handle;
                let to_copy = [
                    layout_transition(
                        depth_image,
                        depth_range,
                        (depth_layout, dst),
                        DEPTH_TESTS,
                        COPY_WRITE,
                    ),
                    layout_transition(
                        nearest_image,
                        nearest_range,
                        (attachment, src),
                        COLOR_OUTPUT,
                        COPY_READ,
                    ),
                ];
                let back = [
                    layout_transition(
                        depth_image,
                        depth_range,
                        (dst, depth_layout),
                        COPY_WRITE,
                        DEPTH_TESTS,
                    ),
                    layout_transition(
                        nearest_image,
                        nearest_range,
                        (src, attachment),
                        COPY_READ,
                        COLOR_OUTPUT,
                    ),
                ];
                let before = [
                    memory_barrier(FRAGMENT_STORAGE, TRANSFER_WRITES),
                    memory_barrier(FRAGMENT_STORAGE, TRANSFER_READS),
                    attachments[0],
                ];
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default()
                        .memory_barriers(&before)
                        .image_memory_barriers(&to_copy),
                );
                // The gate first, then the nearest distances in its place.
                let nearest_buffer = t.visibility.nearest.handle;
                let copy = [depth_copy(extent, 0)];
                d.cmd_copy_buffer_to_image(cmd, nearest_buffer, depth_image, dst, &copy);
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default()
                        .memory_barriers(&[memory_barrier(TRANSFER_READS, TRANSFER_WRITES)]),
                );
                d.cmd_copy_image_to_buffer(
                    cmd,
                    nearest_image,
                    src,
                    nearest_buffer,
                    &[color_image_copy(extent)],
                );
                d.cmd_fill_buffer(cmd, known, 4, 4, visibility_word(count, stage));
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default()
                        .memory_barriers(&[memory_barrier(TRANSFER_WRITES, FRAGMENT_STORAGE)])
                        .image_memory_barriers(&back),
                );
            }
            DrawStage::Normal => {
                let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
                let range = t.depth.subresource_range();
                let to_copy = layout_transition(
                    t.depth.handle,
                    range,
                    (depth_layout, dst),
                    DEPTH_TESTS,
                    COPY_WRITE,
                );
                let back = layout_transition(
                    t.depth.handle,
                    range,
                    (dst, depth_layout),
                    COPY_WRITE,
                    DEPTH_TESTS,
                );
                let before = [
                    memory_barrier(FRAGMENT_STORAGE, TRANSFER_READS),
                    memory_barrier(FRAGMENT_STORAGE, TRANSFER_WRITES),
                    attachments[0],
                ];
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default()
                        .memory_barriers(&before)
                        .image_memory_barriers(&[to_copy]),
                );
                let copy = [depth_copy(extent, KNOWN_DEPTH_HEADER)];
                d.cmd_copy_buffer_to_image(cmd, known, t.depth.handle, dst, &copy);
                d.cmd_fill_buffer(cmd, known, 4, 4, visibility_word(count, DrawStage::Normal));
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default()
                        .memory_barriers(&[memory_barrier(TRANSFER_WRITES, FRAGMENT_STORAGE)])
                        .image_memory_barriers(&[back]),
                );
            }
        }
        d.cmd_begin_rendering(cmd, &rendering);
    }
    Ok(())
}

/// The frame's ray distances into the bands of `hits` (each after its 16-byte header: the
/// row length, the band's first row and its rows), for the glyphs' shadows cast after
/// the frame; the distance attachment is left as it was.
fn copy_hits(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    t: &Targets,
    hits: &HitsBuffer,
    extent: vk::Extent2D,
) {
    let range = t.distance.subresource_range();
    let attachment = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
    let to_copy = layout_transition(
        t.distance.handle,
        range,
        (attachment, src),
        COLOR_OUTPUT,
        COPY_READ,
    );
    let back = layout_transition(
        t.distance.handle,
        range,
        (src, attachment),
        COPY_READ,
        COLOR_OUTPUT,
    );

    // The header's update and the copy are transfer writes; the last frame's receivers
    // read the buffer before them.
    let shader_read = (
        vk::PipelineStageFlags2::FRAGMENT_SHADER,
        vk::AccessFlags2::SHADER_STORAGE_READ,
    );
    let write = memory_barrier(shader_read, TRANSFER_WRITES);
    let read = memory_barrier(TRANSFER_WRITES, shader_read);
    // SAFETY: `cmd` is recording outside rendering; the image and buffer are alive until
    // the submission completes, and the buffer holds the header and the image's bytes.
    unsafe {
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default()
                .memory_barriers(&[write])
                .image_memory_barriers(&[to_copy]),
        );
        for band in &hits.bands {
            let header = [extent.width, band.first, band.rows, 0];
            let rows = vk::Extent2D {
                width: extent.width,
                height: band.rows,
            };
            let copy = [color_image_copy(rows)
                .image_offset(vk::Offset3D {
                    x: 0,
                    y: band.first as i32,
                    z: 0,
                })
                .buffer_offset(HITS_HEADER)];
            let buffer = band.buffer.handle;
            d.cmd_update_buffer(cmd, buffer, 0, bytemuck::cast_slice(&header));
            d.cmd_copy_image_to_buffer(cmd, t.distance.handle, src, buffer, &copy);
        }
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default()
                .memory_barriers(&[read])
                .image_memory_barriers(&[back]),
        );
    }
}

/// An attachment whose contents a second rendering loads and keeps.
fn loaded_attachment(
    view: vk::ImageView,
    layout: vk::ImageLayout,
) -> vk::RenderingAttachmentInfo<'static> {
    vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(layout)
        .load_op(vk::AttachmentLoadOp::LOAD)
        .store_op(vk::AttachmentStoreOp::STORE)
}

/// The depth range of a frame: the glyphs', widened to the underlay's planes and the
/// peaks' capsules.
fn frame_extent(
    camera: &Camera,
    sets: &[GlyphSetData],
    settings: &RenderSettings,
    underlay: Option<&Underlay>,
    peaks: Option<&PeakSet>,
) -> SceneExtent {
    let mut extent = SceneExtent::for_settings(camera, sets, settings);
    if let Some(underlay) = underlay {
        extent = extent_with_planes(camera, extent, &underlay.planes);
    }
    if let Some(peaks) = peaks {
        extent = peaks.widen(camera, extent);
    }
    extent
}

/// The attachments from any earlier contents to cleared attachment layouts.
fn begin_targets(d: &ash::Device, cmd: vk::CommandBuffer, t: &Targets) {
    let to_attachment = |image: &Image, layout| {
        let access = if layout == vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL {
            DEPTH_TESTS
        } else {
            COLOR_OUTPUT
        };
        let layouts = (vk::ImageLayout::UNDEFINED, layout);
        layout_transition(
            image.handle,
            image.subresource_range(),
            layouts,
            NOTHING,
            access,
        )
    };
    let mut barriers = vec![
        to_attachment(&t.color, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
        to_attachment(&t.distance, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
        to_attachment(&t.depth, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL),
    ];
    if let Some(stages) = &t.stages {
        barriers.push(to_attachment(
            &stages.nearest,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        ));
        barriers.push(to_attachment(
            &stages.scratch,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        ));
    }
    // SAFETY: `cmd` is recording outside rendering; the images are alive.
    unsafe {
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&barriers),
        );
    }
}

/// The colour and distance attachments copied into their read-back buffers, and the
/// copies made visible to the host.
fn copy_targets_to_host(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    t: &Targets,
    extent: vk::Extent2D,
) {
    let to_transfer = |image: &Image| {
        let layouts = (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        );
        layout_transition(
            image.handle,
            image.subresource_range(),
            layouts,
            COLOR_OUTPUT,
            COPY_READ,
        )
    };
    let barriers = [to_transfer(&t.color), to_transfer(&t.distance)];
    let copy = [color_image_copy(extent)];
    let host_read = [copies_to_host()];
    let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
    // SAFETY: `cmd` is recording outside rendering; images and buffers are alive until the
    // submission completes, and each buffer holds its image's bytes.
    unsafe {
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&barriers),
        );
        d.cmd_copy_image_to_buffer(cmd, t.color.handle, src, t.color_readback.handle, &copy);
        d.cmd_copy_image_to_buffer(
            cmd,
            t.distance.handle,
            src,
            t.distance_readback.handle,
            &copy,
        );
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&host_read),
        );
    }
}

/// Copies the readback buffers into host memory. The buffers are allocated fallibly: a
/// large image (16384 x 16384 is 1 GiB per buffer) under a memory limit is an error,
/// not an abort.
fn read_back(t: &Targets, width: u32, height: u32) -> Result<RenderedImage> {
    let colors = t.color_readback.read()?;
    let mut rgba = host_buffer::<u8>(colors.len())?;
    rgba.extend_from_slice(colors);
    let distances = t.distance_readback.read()?;
    let mut distance = host_buffer::<f32>(distances.len() / 4)?;
    distance.extend(distances.chunks_exact(4).map(|b| {
        let d = f32::from_ne_bytes([b[0], b[1], b[2], b[3]]);
        if d < 0.0 { f32::NAN } else { d }
    }));
    Ok(RenderedImage {
        width,
        height,
        rgba,
        distance,
        draws: 0,
        gpu_ms: None,
        mesh: None,
        path: RenderPath::Fragment,
        passes: 1,
        culling: crate::render::Culling::Off,
    })
}

/// An empty vector with room for `len` values, or an out-of-memory error when
/// the host cannot provide it.
fn host_buffer<T>(len: usize) -> Result<Vec<T>> {
    let mut buffer = Vec::new();
    buffer
        .try_reserve_exact(len)
        .map_err(|_| Error::OutOfMemory {
            what: "the image's read-back",
            file: None,
            bytes: Some((len * std::mem::size_of::<T>()) as u64),
            settings: &[Setting::Width, Setting::Height],
        })?;
    Ok(buffer)
}

/// Refuses a size beyond the device's largest 2D image before anything is allocated.
fn check_image_size(gpu: &Gpu, width: u32, height: u32) -> Result<()> {
    let largest = gpu.context().max_image_dimension_2d();
    if width > largest || height > largest {
        return Err(Error::Limit {
            what: "image side in pixels (this device's largest 2D image)",
            value: u64::from(width.max(height)),
            limit: u64::from(largest),
            settings: &[Setting::Width, Setting::Height],
        });
    }
    Ok(())
}
