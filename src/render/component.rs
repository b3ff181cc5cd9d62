//! The engine component: glyphs drawn into a host engine's frames, the way egui-ash-renderer
//! or Dear ImGui's Vulkan backend are. The host passes its device (a [`DeviceContext`]),
//! attachment formats, samples, depth convention, pipeline cache and frames in flight
//! once; each frame it writes frame k's camera ([`GlyphRenderer::set_view`]) and records
//! into an open command buffer ([`GlyphRenderer::record`]). glyphcast never submits,
//! presents, waits or creates a device.
//!
//! Frames in flight: the glyphs are uploaded once per [`GlyphRenderer::set_glyphs`] and
//! shared; each frame index has its own frame block (camera, settings). Replacing the
//! glyphs never waits: the old ones are retired, and dropped once every frame index has
//! been begun again with `set_view`, which the host calls only after that frame's previous
//! submission completed (the fence it waits on before reusing frame k's command buffer).
//!
//! The compute ray caster (`path: compute` in the settings): each frame, outside the
//! host's rendering, [`GlyphRenderer::record_compute`] records its dispatches into
//! glyphcast's own buffers (colour, ray distance, depth per pixel of the viewport); inside
//! the rendering, [`GlyphRenderer::record`] draws them into the host's attachments with
//! one triangle over the viewport, depth-tested against what the host drew before and
//! writing the glyphs' depth for its later passes. The host's images need nothing more
//! than for the fragment path (colour and depth attachments, in attachment layouts, in
//! the rendering the glyphs are recorded in); glyphcast's barriers cover its own buffers:
//! the last read of frame k's outputs before they are written again, and the dispatches'
//! writes before the composing draw reads them. The glyphs are uploaded once; frame k's
//! tile lists are made on the CPU in `set_view` from its camera. `auto` on a GPU takes
//! the compute path in the frames whose dispatches the host records, once it has called
//! `record_compute`, and the fragment path in every other frame (the glyphs are uploaded
//! for both); a host that never calls it draws as before.
//!
//! glyphcast's own front ends draw through the same component: the headless renderer
//! (one frame in flight) keeps each prepared frame's glyphs as [`UploadedGlyphs`] made by
//! [`GlyphRenderer::upload`], writes their frame block from glyphcast's own camera
//! ([`UploadedGlyphs::set_frame`]) and records them with
//! [`GlyphRenderer::record_glyphs`], which is what [`GlyphRenderer::record`] calls for the
//! renderer's current glyphs. Glyphs held that way are retired with
//! [`GlyphRenderer::retire`] like replaced ones. The viewer does the same with 2 frames
//! in flight (`viewer::presenter`): its panels' glyphs are [`UploadedGlyphs`], each frame
//! slot writes its own frame block, and a slice step retires the old glyphs.
use crate::error::{Error, Result};
use crate::glyph::{GlyphShape, TensorLayout};
use crate::render::compute::{
    ComposePipeline, ComputeGlyphsGpu, ComputeRayCastPass, ComputeSceneGpu,
};
use crate::render::frame::FrameParams;
use crate::render::glyph_data::{GlyphSetData, largest_radius};
use crate::render::host_view::{HostView, host_frame};
use crate::render::raycast::{
    FrameTarget, PassOptions, Passes, RayCastPass, SceneGpu, TargetFormats,
};
use crate::render::settings::{Culling, RenderSettings};
use crate::render::visibility::{PassPlan, VisibilityBuffers};
use crate::render::{Method, RenderPath};
use crate::vk::DeviceContext;
use ash::vk;
use std::sync::atomic::{AtomicBool, Ordering};

/// What the host decides once.
#[derive(Clone, Debug)]
pub struct RendererDesc {
    /// Its attachments' formats (colour, depth; a distance attachment if it wants one).
    pub formats: TargetFormats,
    /// Its samples, depth convention and pipeline cache.
    pub options: PassOptions,
    /// How many frames it records ahead of the GPU (its frame-index range).
    pub frames_in_flight: usize,
    /// How the glyphs are drawn: method, march, colour, lighting.
    pub settings: RenderSettings,
}

/// Glyphs uploaded once and shared by every frame in flight, with one frame block per
/// frame index.
pub struct UploadedGlyphs {
    pub(crate) gpu: SceneGpu,
    /// The method the sets' pipelines were made for.
    method: crate::render::Method,
    /// The largest glyph radius: the top of the magnitude colour range.
    max_radius: f64,
    /// Per frame index: the viewport and scissor its frame block was written for, or
    /// `None` until `set_view` (or `set_frame`) wrote it for these glyphs.
    views: Vec<Option<(vk::Viewport, vk::Rect2D)>>,
    /// Whether hidden glyphs are skipped where the frame is drawn in passes.
    cull: Culling,
    /// The `cull` the glyphs were uploaded with (`occluded`, or a way asked for by name).
    cull_asked: Culling,
    /// Per frame index: the passes of its camera (render::visibility).
    plans: Vec<PassPlan>,
    /// On the compute path: the glyphs as the compute ray caster reads them (`gpu` then
    /// holds no glyph, only the frame blocks).
    compute: Option<ComputeUploaded>,
    /// A host's frames culled by early outs: the known depths of each frame index.
    host_early_outs: Option<HostEarlyOuts>,
}

/// The known depths of a host's frames drawn with early outs (render::visibility), which
/// `record_compute` clears before the host's rendering.
struct HostEarlyOuts {
    ctx: DeviceContext,
    /// The ray-casting pass's visibility set layout, which the known depths' sets take.
    layout: vk::DescriptorSetLayout,
    /// The host's clear depth: no hit yet.
    clear_depth: f32,
    /// The most bytes of one storage buffer: a scissor whose known depths exceed it is
    /// drawn without early outs.
    limit: u64,
    /// Per frame index: its known depths, made for the scissor of its view.
    slots: Vec<Option<EarlyOutSlot>>,
}

/// The known depths of one frame index.
struct EarlyOutSlot {
    buffers: VisibilityBuffers,
    scissor: vk::Rect2D,
    /// Whether `record_compute` cleared them since the view was set; `record` takes
    /// the early outs only then (atomic: hosts may record from several threads).
    cleared: AtomicBool,
}

impl HostEarlyOuts {
    /// Frame index `k` drawn over `scissor` with early outs (`on`) or without: its known
    /// depths made for the scissor's size where they are not, and not cleared yet.
    /// Whether the frame takes the early outs: not where `on` is false, nor where the
    /// scissor's known depths would exceed a storage buffer's `limit`.
    fn set_view(&mut self, k: usize, scissor: vk::Rect2D, on: bool) -> Result<bool> {
        let Some(slot) = self.slots.get_mut(k) else {
            return Ok(false);
        };
        let (w, h) = (scissor.extent.width, scissor.extent.height);
        if on && !crate::render::visibility::known_depths_fit(self.limit, w, h) {
            // The frame index's previous submission has completed (set_view's promise).
            *slot = None;
            return Ok(false);
        }
        if !on {
            if let Some(s) = slot {
                s.cleared.store(false, Ordering::SeqCst);
            }
            return Ok(false);
        }
        let fits = slot
            .as_ref()
            .is_some_and(|s| s.scissor.extent == scissor.extent);
        if !fits {
            // The frame index's previous submission has completed (set_view's promise).
            *slot = None;
            let buffers = VisibilityBuffers::for_early_outs(&self.ctx, self.layout, w, h)?;
            *slot = Some(EarlyOutSlot {
                buffers,
                scissor,
                cleared: AtomicBool::new(false),
            });
        }
        if let Some(s) = slot {
            s.scissor = scissor;
            s.cleared.store(false, Ordering::SeqCst);
        }
        Ok(true)
    }
}

impl UploadedGlyphs {
    /// Writes frame `frame_index`'s block as `frame` (glyphcast's own camera, made by
    /// [`FrameParams::new`]), to be drawn in `target`'s viewport and scissor. Only once
    /// the last submission that read that frame index has completed.
    pub fn set_frame(&mut self, frame: &FrameParams, target: &FrameTarget) -> Result<()> {
        let k = target.frame_index;
        if let Some(compute) = &mut self.compute {
            if let Some(dispatched) = compute.dispatched.get(k) {
                dispatched.store(false, Ordering::SeqCst);
            }
            // The previous view of this frame index is no longer read (the caller's
            // promise), so it goes before the new one is made.
            if let Some(slot) = compute.views.get_mut(k) {
                *slot = None;
            }
            let host = HostView {
                view: glam::DMat4::IDENTITY,
                projection: glam::DMat4::IDENTITY,
                viewport: target.viewport,
                scissor: target.scissor,
            };
            // With `auto`, a viewport the compute path does not draw is drawn by the
            // fragment path.
            let region = match compute_region(&host) {
                Err(_) if compute.auto => None,
                region => Some(region?),
            };
            if let (Some(glyphs), Some((origin, [width, height]))) = (&compute.glyphs, region) {
                let view = crate::render::tiles::ScreenView::of_frame(frame, width, height);
                let scene = glyphs.view(&compute.ctx, frame, view)?;
                if let Some(slot) = compute.views.get_mut(k) {
                    *slot = Some((scene, origin));
                }
            }
        }
        self.gpu.set_frame_in_flight(k, frame)?;
        if let Some(view) = self.views.get_mut(k) {
            *view = Some((target.viewport, target.scissor));
        }
        if let Some(plan) = self.plans.get_mut(k) {
            let clusters = self.gpu.sets.iter().map(|set| set.clusters.as_slice());
            *plan = crate::render::visibility::plan(clusters, frame, (self.cull, self.cull_asked));
        }
        let early_out = self.culling(k) == Culling::EarlyOut;
        if let Some(host) = &mut self.host_early_outs {
            let taken = host.set_view(k, target.scissor, early_out)?;
            if early_out && !taken {
                // A scissor too large for its known depths: drawn without culling.
                if let Some(plan) = self.plans.get_mut(k) {
                    *plan = PassPlan::default();
                }
            }
        }
        Ok(())
    }

    /// On the fragment path with early outs: records the clearing of frame
    /// `frame_index`'s known depths (outside any rendering), after which `record` takes
    /// the early outs; nothing for a frame drawn without them.
    fn record_early_out_clear(&self, cmd: vk::CommandBuffer, frame_index: usize) {
        let Some(host) = &self.host_early_outs else {
            return;
        };
        let Some(Some(slot)) = host.slots.get(frame_index) else {
            return;
        };
        if self.culling(frame_index) != Culling::EarlyOut {
            return;
        }
        let origin = [
            slot.scissor.offset.x.max(0) as u32,
            slot.scissor.offset.y.max(0) as u32,
        ];
        let d = host.ctx.device();
        let word = crate::catalog::codes::VISIBILITY_EARLY_OUT;
        slot.buffers
            .record_frame_start(d, cmd, (word, origin), (Some(host.clear_depth), false));
        slot.cleared.store(true, Ordering::SeqCst);
    }

    /// The known depths that frame `frame_index` is drawn with, where `record_compute`
    /// cleared them since its view was set (and no `record` took them since).
    fn cleared_early_outs(&self, frame_index: usize) -> Option<&VisibilityBuffers> {
        let slot = self
            .host_early_outs
            .as_ref()?
            .slots
            .get(frame_index)?
            .as_ref()?;
        let cleared = slot.cleared.swap(false, Ordering::SeqCst);
        (cleared && self.culling(frame_index) == Culling::EarlyOut).then_some(&slot.buffers)
    }

    /// The ray caster that draws these glyphs: compute or fragment; with `auto` on a GPU,
    /// [`RenderPath::Auto`] until the host has recorded dispatches (the fragment path
    /// draws), then compute (in the frames whose dispatches the host records).
    pub fn path(&self) -> RenderPath {
        match &self.compute {
            Some(compute) if compute.auto && compute.glyphs.is_none() => RenderPath::Auto,
            Some(_) => RenderPath::Compute,
            None => RenderPath::Fragment,
        }
    }

    /// Frame `frame_index`'s view on the compute path and where it is drawn.
    fn compute_view(&self, frame_index: usize) -> Option<(&ComputeSceneGpu, [u32; 2])> {
        let compute = self.compute.as_ref()?;
        let (scene, origin) = compute.views.get(frame_index)?.as_ref()?;
        Some((scene, *origin))
    }

    /// How its frames are culled where they need more than one pass (`Passes`,
    /// `EarlyOut` or `Off`), whatever the camera.
    pub(crate) fn cull(&self) -> Culling {
        self.cull
    }

    /// The passes frame `frame_index` is drawn in by the headless renderer.
    pub fn passes(&self, frame_index: usize) -> usize {
        self.plans.get(frame_index).map_or(0, PassPlan::passes)
    }

    /// Whether frame `frame_index`'s visibility word may be other than 0: it is culled
    /// (in passes or by early outs, the host's included) or `count`s its work.
    pub(crate) fn visibility_active(&self, frame_index: usize, count: bool) -> bool {
        count
            || self.passes(frame_index) > 1
            || self.host_early_outs.is_some()
            || self.plans.get(frame_index).is_some_and(PassPlan::early_out)
    }

    /// How frame `frame_index`'s hidden glyphs are skipped: `Passes`, `EarlyOut`, or
    /// `Off` where its frame is one pass without early outs.
    pub fn culling(&self, frame_index: usize) -> Culling {
        match self.plans.get(frame_index) {
            Some(plan) if plan.early_out() => Culling::EarlyOut,
            Some(plan) if plan.passes() > 1 => Culling::Passes,
            _ => Culling::Off,
        }
    }

    /// Instanced draws per frame (batches).
    pub fn draws(&self) -> usize {
        self.gpu.sets.len()
    }

    /// The uploaded batches.
    pub fn scene(&self) -> &SceneGpu {
        &self.gpu
    }
}

/// Glyphs replaced while frames that read them may be in flight.
struct Retired {
    _glyphs: UploadedGlyphs,
    /// Frame indices that may still read them: cleared as each is begun again.
    pending: Vec<bool>,
}

/// The compute ray caster's pass and composing pipeline, made for the renderer's target
/// when glyphs are first uploaded for it.
struct ComputeRecorder {
    pass: ComputeRayCastPass,
    compose: ComposePipeline,
}

/// Glyphs uploaded for the compute ray caster, with the view of each frame index.
struct ComputeUploaded {
    // Fields drop in order: the views before the glyphs their descriptor sets hold.
    /// Per frame index: the view its frame block was last written for (tile lists,
    /// outputs) and the viewport origin it is drawn at.
    views: Vec<Option<(ComputeSceneGpu, [u32; 2])>>,
    /// The glyphs on the GPU; with `auto`, uploaded at the first `set_view` after the
    /// host showed it records the dispatches (`pending` holds them until then).
    glyphs: Option<ComputeGlyphsGpu>,
    pending: Option<Vec<GlyphSetData>>,
    /// `auto` on a GPU: the glyphs are uploaded for the fragment path too, which draws
    /// every frame whose dispatches the host did not record.
    auto: bool,
    ctx: DeviceContext,
    /// Per frame index: whether its dispatches were recorded since its view was set
    /// (`record_compute`), without which `record` would compose stale outputs; atomic,
    /// as hosts may record from several threads.
    dispatched: Vec<AtomicBool>,
}

/// Refuses what the engine component's compute path does not draw: shadows and
/// ambient occlusion (cast by the fragment path's glyph shaders in a host's pass).
fn check_compute_settings(settings: &RenderSettings) -> Result<()> {
    for (setting, on) in [
        (crate::Setting::Shadows, settings.shadows.enabled()),
        (
            crate::Setting::AmbientOcclusion,
            settings.ambient_occlusion.enabled(),
        ),
    ] {
        if on {
            return Err(Error::setting(
                setting,
                crate::message![
                    "the engine component casts shadow rays on ",
                    crate::Setting::Path.with("fragment"),
                    " only"
                ],
            ));
        }
    }
    Ok(())
}

/// Where the compute ray caster draws a host's view: the viewport's top-left pixel and
/// its size, which must be whole pixels with a positive height (the compute ray caster's
/// rows run down from the top).
fn compute_region(view: &HostView) -> Result<([u32; 2], [u32; 2])> {
    let vp = &view.viewport;
    let whole = |v: f32| v.is_finite() && v >= 0.0 && v.fract() == 0.0;
    if !(whole(vp.x) && whole(vp.y) && whole(vp.width) && whole(vp.height))
        || vp.width == 0.0
        || vp.height == 0.0
    {
        return Err(Error::input(
            "host view",
            "viewport",
            format!(
                "the compute path draws a viewport of whole pixels with a positive height, not \
                 {} x {} at ({}, {})",
                vp.width, vp.height, vp.x, vp.y
            ),
        ));
    }
    Ok((
        [vp.x as u32, vp.y as u32],
        [vp.width as u32, vp.height as u32],
    ))
}

/// The glyph renderer of one host target configuration.
pub struct GlyphRenderer {
    // Scenes drop before the pass (descriptor sets and buffers before pipelines and
    // layouts): fields drop in order.
    glyphs: Option<UploadedGlyphs>,
    retired: Vec<Retired>,
    compute: Option<Box<ComputeRecorder>>,
    /// Whether the host has recorded the compute path's dispatches (`record_compute`):
    /// `auto` then draws with it.
    host_dispatches: AtomicBool,
    pass: RayCastPass,
    ctx: DeviceContext,
    frames_in_flight: usize,
    settings: RenderSettings,
    /// Whether frames are drawn in the passes of their plans (the headless renderer's
    /// `record_glyph_passes`); a host's `record` draws one pass, so its glyphs are
    /// planned for none.
    draws_passes: bool,
}

impl GlyphRenderer {
    /// A renderer for the host's device and target. Pipelines are made by
    /// [`GlyphRenderer::prepare`] or [`GlyphRenderer::set_glyphs`], outside any frame.
    pub fn new(ctx: &DeviceContext, desc: &RendererDesc) -> Result<GlyphRenderer> {
        if desc.frames_in_flight == 0 {
            return Err(Error::Call {
                call: "GlyphRenderer::new",
                expected: "at least one frame in flight",
            });
        }
        desc.settings.validate()?;
        if let Method::Mesh(_) = desc.settings.method {
            return Err(Error::Unsupported {
                what: crate::error::Asked::Method(
                    crate::Setting::Method.with(desc.settings.method),
                ),
                by: "the engine component, which ray-casts".into(),
            });
        }
        let pass = RayCastPass::with_options(ctx, desc.formats, desc.options)?;
        let compute = match desc.settings.path {
            RenderPath::Compute => {
                check_compute_settings(&desc.settings)?;
                let mut pass = ComputeRayCastPass::new(ctx)?;
                let compose = pass.compose_pipeline(desc.formats, desc.options.raster())?;
                Some(Box::new(ComputeRecorder { pass, compose }))
            }
            _ => None,
        };
        Ok(GlyphRenderer {
            glyphs: None,
            retired: Vec::new(),
            compute,
            host_dispatches: AtomicBool::new(false),
            pass,
            ctx: ctx.clone(),
            frames_in_flight: desc.frames_in_flight,
            settings: desc.settings,
            draws_passes: false,
        })
    }

    /// Whether the glyphs uploaded from now on are planned in passes (render::visibility):
    /// for a caller that draws them with `record_glyph_passes`.
    pub(crate) fn set_draws_passes(&mut self, draws_passes: bool) {
        self.draws_passes = draws_passes;
    }

    /// Makes the pipelines that glyph sets of `layouts` need, so that the first
    /// `set_glyphs` of such sets compiles nothing (for example at load time).
    pub fn prepare(&mut self, layouts: &[(TensorLayout, GlyphShape)]) -> Result<()> {
        if let (RenderPath::Compute, Some(compute)) = (self.settings.path, &mut self.compute) {
            for &(layout, shape) in layouts {
                if shape != GlyphShape::Polynomial {
                    return Err(crate::render::settings::compute_refuses_shape(shape));
                }
                compute.pass.pipeline(layout)?;
            }
            return Ok(());
        }
        let method = self.settings.method;
        let variants = layouts
            .iter()
            .map(|&(layout, shape)| crate::render::raycast::batch_variant(layout, shape, method))
            .collect::<Result<Vec<_>>>()?;
        self.pass.set_proxy(self.settings.proxy);
        self.pass.prepare_pipelines(&variants)
    }

    /// Uploads new glyphs for every frame in flight (and makes any pipeline they need),
    /// replacing the current ones without waiting: those are retired until each frame
    /// index has been begun again. Each frame index needs a `set_view` before its next
    /// `record`.
    pub fn set_glyphs(&mut self, sets: &[GlyphSetData]) -> Result<()> {
        let settings = self.settings;
        let glyphs = self.upload(sets, &settings)?;
        if let Some(old) = self.glyphs.replace(glyphs) {
            self.retire(old);
        }
        Ok(())
    }

    /// Uploads glyphs to be drawn with `settings`' method (making the pipelines they
    /// need) for every frame in flight, without making them the renderer's current
    /// ones: the caller keeps them, writes their frame blocks
    /// ([`UploadedGlyphs::set_frame`]) and records them with
    /// [`GlyphRenderer::record_glyphs`]. The headless renderer holds its prepared frames'
    /// glyphs this way.
    pub fn upload(
        &mut self,
        sets: &[GlyphSetData],
        settings: &RenderSettings,
    ) -> Result<UploadedGlyphs> {
        let frame = FrameParams::of_settings(
            &crate::render::frame::SceneExtent {
                near: 0.0,
                far: 0.0,
                max_radius: 1.0,
            },
            settings,
        );
        // On the compute path the glyphs go to the compute ray caster; the fragment path's
        // scene keeps only the frame blocks. `auto` on a GPU, where the compute path draws
        // these glyphs with these settings (one sample per pixel: the compute path casts
        // one ray per pixel), uploads them for both: the compute path draws the frames
        // whose dispatches the host records (`record_compute`), the fragment path the
        // others, so a host that never calls it draws as before.
        let shapes = sets.iter().map(|set| set.shape);
        let auto = settings.path == RenderPath::Auto
            && !settings.casts_rays()
            && self.pass.options().samples == vk::SampleCountFlags::TYPE_1
            && settings.path.on_context(&self.ctx, settings.method, shapes) == RenderPath::Compute;
        let compute = match settings.path {
            _ if settings.path == RenderPath::Compute || auto => {
                check_compute_settings(settings)?;
                let recorder = match &mut self.compute {
                    Some(recorder) => recorder,
                    None => {
                        let mut pass = ComputeRayCastPass::new(&self.ctx)?;
                        let options = self.pass.options();
                        let compose =
                            pass.compose_pipeline(self.pass.formats(), options.raster())?;
                        self.compute
                            .insert(Box::new(ComputeRecorder { pass, compose }))
                    }
                };
                let (glyphs, pending) = match auto {
                    // Uploaded once the host records dispatches (`set_view`).
                    true if !self.host_dispatches.load(Ordering::SeqCst) => {
                        (None, Some(sets.to_vec()))
                    }
                    _ => (Some(recorder.pass.upload_glyphs(&self.ctx, sets)?), None),
                };
                Some(ComputeUploaded {
                    views: (0..self.frames_in_flight).map(|_| None).collect(),
                    glyphs,
                    pending,
                    auto,
                    ctx: self.ctx.clone(),
                    dispatched: (0..self.frames_in_flight)
                        .map(|_| AtomicBool::new(false))
                        .collect(),
                })
            }
            _ => None,
        };
        let fragment_sets = match &compute {
            Some(compute) if !compute.auto => &[][..],
            _ => sets,
        };
        self.pass.set_proxy(settings.proxy);
        let gpu = self.pass.upload_in_flight(
            &self.ctx,
            fragment_sets,
            &frame,
            settings.method,
            self.frames_in_flight,
        )?;
        // Culled glyphs are drawn in passes whose later stages have pipelines of their own,
        // made when a frame first needs more than one pass (`prepare_passes`), or in one
        // pass with early outs. A host's frame is one pass, culled by early outs only,
        // where the host clears their known depths before its rendering
        // (`record_compute`); without them its glyphs are not planned (no sorting at
        // every `set_view`). They need one sample per pixel (with several, the samples a
        // box covers need not be those the known hit covered) and a float depth (a
        // quantised one may round a skipped hit onto the known depth, where a depth test
        // that keeps equal values could have kept it).
        let single_sample = self.pass.options().samples == vk::SampleCountFlags::TYPE_1;
        let float_depth = matches!(
            self.pass.formats().depth,
            vk::Format::D32_SFLOAT | vk::Format::D32_SFLOAT_S8_UINT
        );
        let cull = match crate::render::visibility::culling(&self.ctx, settings) {
            cull if self.draws_passes => cull,
            // (Glyphs on the compute path, `auto` included, draw no fragment pass to cull.)
            Culling::EarlyOut if single_sample && float_depth && compute.is_none() => {
                Culling::EarlyOut
            }
            _ => Culling::Off,
        };
        let host_early_outs = match cull {
            Culling::EarlyOut if !self.draws_passes => Some(HostEarlyOuts {
                ctx: self.ctx.clone(),
                layout: self.pass.visibility_set_layout()?,
                clear_depth: self.pass.options().depth.clear_depth(),
                limit: self.pass.storage_buffer_limit(&self.ctx),
                slots: (0..self.frames_in_flight).map(|_| None).collect(),
            }),
            _ => None,
        };
        if host_early_outs.is_some() {
            // The host's frames take early outs wherever their plan does.
            self.pass
                .prepare_visibility_pipelines(&gpu, settings.method)?;
        }
        Ok(UploadedGlyphs {
            gpu,
            method: settings.method,
            max_radius: glyph_radius(sets, settings),
            views: vec![None; self.frames_in_flight],
            cull,
            cull_asked: settings.cull,
            plans: vec![PassPlan::default(); self.frames_in_flight],
            compute,
            host_early_outs,
        })
    }

    /// Keeps `glyphs` until every frame index has been begun again (`set_view` or
    /// [`GlyphRenderer::begin_frame`]), then drops them: for glyphs replaced while frames
    /// that read them may be in flight. Never waits.
    pub fn retire(&mut self, glyphs: UploadedGlyphs) {
        self.retired.push(Retired {
            _glyphs: glyphs,
            pending: vec![true; self.frames_in_flight],
        });
    }

    /// Marks the start of frame `frame_index` (its previous submission has completed):
    /// retired glyphs that no frame index can still read are dropped. `set_view` does
    /// this itself.
    pub fn begin_frame(&mut self, frame_index: usize) -> Result<()> {
        self.check_index(frame_index)?;
        for retired in &mut self.retired {
            retired.pending[frame_index] = false;
        }
        self.retired.retain(|r| r.pending.iter().any(|&p| p));
        Ok(())
    }

    /// Raises the number of frame indices to `frames_in_flight` (0 to n - 1), for a host
    /// that records more frames (or more views per frame, each with its own index) than
    /// it made the renderer for. The frame indices in use keep their frame blocks and
    /// may be in flight meanwhile; the new indices need `set_view` before `record`. The
    /// number never falls: a smaller one is refused.
    pub fn set_frames_in_flight(&mut self, frames_in_flight: usize) -> Result<()> {
        if frames_in_flight < self.frames_in_flight {
            return Err(Error::Call {
                call: "GlyphRenderer::set_frames_in_flight",
                expected: "at least as many frames in flight as before",
            });
        }
        let n = frames_in_flight;
        if let Some(glyphs) = &mut self.glyphs {
            self.pass.add_frames(&mut glyphs.gpu, n)?;
            glyphs.views.resize(n, None);
            glyphs.plans.resize(n, PassPlan::default());
            if let Some(compute) = &mut glyphs.compute {
                compute.views.resize_with(n, || None);
                compute.dispatched.resize_with(n, || AtomicBool::new(false));
            }
            if let Some(early) = &mut glyphs.host_early_outs {
                early.slots.resize_with(n, || None);
            }
        }
        // Retired glyphs were never drawn at the new indices.
        for retired in &mut self.retired {
            retired.pending.resize(n, false);
        }
        self.frames_in_flight = n;
        Ok(())
    }

    /// The settings the next `set_view` applies (those given at creation or by
    /// [`GlyphRenderer::set_settings`]).
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// Replaces the settings (march, colour, lighting) that the next `set_view` calls
    /// write; the method must stay the one the renderer was made with, and the values
    /// are checked as [`GlyphRenderer::new`] checks them ([`RenderSettings::validate`]):
    /// a refused value leaves the renderer's settings as they were. Shadows or ambient
    /// occlusion switched on take effect for glyphs uploaded after (`set_glyphs`,
    /// `upload`): their pipelines are chosen at upload; switched off, they stop at once.
    pub fn set_settings(&mut self, settings: &RenderSettings) -> Result<()> {
        settings.validate()?;
        if settings.method != self.settings.method {
            return Err(Error::Unsupported {
                what: crate::error::Asked::Method(crate::Setting::Method.with(settings.method)),
                by: format!("a renderer made for method {}", self.settings.method).into(),
            });
        }
        self.settings = *settings;
        Ok(())
    }

    /// Begins frame `frame_index`: writes its camera and settings. Call it once the
    /// host's previous submission of this frame index has completed (its fence), and
    /// before recording the frame; the other frame indices may be in flight meanwhile.
    /// Retired glyphs that no frame index can still read are dropped here.
    pub fn set_view(&mut self, frame_index: usize, view: &HostView) -> Result<()> {
        self.begin_frame(frame_index)?;
        let glyphs = self.glyphs.as_mut().ok_or(Error::Call {
            call: "set_view",
            expected: "set_glyphs first",
        })?;
        // `auto`: the compute path's glyphs once the host records dispatches.
        if let (Some(compute), Some(recorder)) = (&mut glyphs.compute, &mut self.compute)
            && self.host_dispatches.load(Ordering::SeqCst)
            && let Some(sets) = compute.pending.take()
        {
            compute.glyphs = Some(recorder.pass.upload_glyphs(&self.ctx, &sets)?);
        }
        let depth = self.pass.options().depth;
        let frame = host_frame(view, depth, glyphs.max_radius, &self.settings)?;
        let target = FrameTarget {
            frame_index,
            viewport: view.viewport,
            scissor: view.scissor,
        };
        glyphs.set_frame(&frame, &target)
    }

    /// Records frame `frame_index`'s glyphs into `cmd`, which is inside rendering with
    /// the host's attachments (formats and samples as given at creation): dynamic
    /// rendering, or the subpass of the render pass given at creation. Records only:
    /// nothing is compiled, written, submitted or waited on, so several threads may
    /// record at once, each into its own command buffer. A frame planned for early outs
    /// takes them after a [`GlyphRenderer::record_compute`] of the frame (one `record`
    /// per such call), and is drawn as without culling otherwise.
    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize) -> Result<()> {
        let glyphs = self.glyphs.as_ref().ok_or(Error::Call {
            call: "record",
            expected: "set_glyphs first",
        })?;
        self.record_glyphs(cmd, glyphs, frame_index)
    }

    /// On the compute path (`path: compute`): records frame `frame_index`'s dispatches
    /// of the current glyphs into `cmd` outside any rendering, before the rendering in
    /// which [`GlyphRenderer::record`] draws their outputs. Writes only glyphcast's own
    /// buffers, with the barriers they need (module docs). On the fragment path it
    /// records the clearing of the frame's known depths where it culls by early outs
    /// ([`GlyphRenderer::culling`]), which the next `record` of the frame takes, and
    /// nothing otherwise, so a host may call it whichever path it was made for.
    pub fn record_compute(&self, cmd: vk::CommandBuffer, frame_index: usize) -> Result<()> {
        let glyphs = self.glyphs.as_ref().ok_or(Error::Call {
            call: "record_compute",
            expected: "set_glyphs first",
        })?;
        self.record_compute_glyphs(cmd, glyphs, frame_index)
    }

    /// [`GlyphRenderer::record_compute`] for glyphs the caller holds
    /// ([`GlyphRenderer::upload`]).
    pub fn record_compute_glyphs(
        &self,
        cmd: vk::CommandBuffer,
        glyphs: &UploadedGlyphs,
        frame_index: usize,
    ) -> Result<()> {
        self.check_index(frame_index)?;
        let Some(compute) = &glyphs.compute else {
            // The fragment path: the known depths of its early outs, if it takes them.
            glyphs.record_early_out_clear(cmd, frame_index);
            return Ok(());
        };
        self.host_dispatches.store(true, Ordering::SeqCst);
        let Some((scene, _)) = glyphs.compute_view(frame_index) else {
            // `auto` before its glyphs are on the compute path: the fragment path draws.
            if compute.auto {
                return Ok(());
            }
            return Err(Error::Call {
                call: "record_compute",
                expected: "set_view for this frame and the current glyphs first",
            });
        };
        let recorder = self.compute.as_ref().ok_or(Error::Call {
            call: "record_compute",
            expected: "glyphs uploaded by this renderer",
        })?;
        recorder.pass.record(cmd, scene)?;
        if let Some(dispatched) = glyphs
            .compute
            .as_ref()
            .and_then(|c| c.dispatched.get(frame_index))
        {
            dispatched.store(true, Ordering::SeqCst);
        }
        Ok(())
    }

    /// The ray caster the current glyphs are drawn with ([`UploadedGlyphs::path`]):
    /// [`RenderPath::Compute`] when the settings ask for it, or `auto` took it on a GPU
    /// (it draws the frames whose dispatches the host records); [`RenderPath::Auto`]
    /// while `auto` on a GPU waits for the host's first `record_compute`; else
    /// [`RenderPath::Fragment`]. Before any glyphs: the settings'.
    pub fn path(&self) -> RenderPath {
        match &self.glyphs {
            Some(glyphs) => glyphs.path(),
            None => self.settings.path,
        }
    }

    /// How frame `frame_index` of the current glyphs culls hidden glyphs
    /// ([`UploadedGlyphs::culling`]): `EarlyOut` where its view was set for early outs
    /// (they are taken by a `record` after a `record_compute`), else `Off`.
    pub fn culling(&self, frame_index: usize) -> Culling {
        self.glyphs
            .as_ref()
            .map_or(Culling::Off, |g| g.culling(frame_index))
    }

    /// [`GlyphRenderer::record`] for glyphs the caller holds ([`GlyphRenderer::upload`]),
    /// with the method they were uploaded for.
    pub fn record_glyphs(
        &self,
        cmd: vk::CommandBuffer,
        glyphs: &UploadedGlyphs,
        frame_index: usize,
    ) -> Result<()> {
        if let Some(compute) = &glyphs.compute {
            self.check_index(frame_index)?;
            let dispatched = compute
                .dispatched
                .get(frame_index)
                .is_some_and(|d| d.load(Ordering::SeqCst));
            if !dispatched && compute.auto {
                let target = self.frame_target(glyphs, frame_index)?;
                return self
                    .pass
                    .record_frame(cmd, &glyphs.gpu, &target, glyphs.method);
            }
            if !dispatched {
                return Err(Error::Call {
                    call: "record",
                    expected: "record_compute for this frame before its rendering (path \
                               compute)",
                });
            }
            let (scene, origin) = glyphs.compute_view(frame_index).ok_or(Error::Call {
                call: "record",
                expected: "set_view for this frame and the current glyphs first",
            })?;
            let recorder = self.compute.as_ref().ok_or(Error::Call {
                call: "record",
                expected: "glyphs uploaded by this renderer",
            })?;
            recorder
                .pass
                .record_compose(cmd, scene, recorder.compose, origin);
            return Ok(());
        }
        let target = self.frame_target(glyphs, frame_index)?;
        if let Some(visibility) = glyphs.cleared_early_outs(frame_index) {
            // One pass nearest first, with early outs against the cleared known depths.
            let passes = Passes {
                plan: glyphs.plans.get(frame_index),
                visibility,
                active: true,
            };
            let no_restart = &mut |_, _| Ok(());
            return self.pass.record_passes(
                cmd,
                &glyphs.gpu,
                &target,
                glyphs.method,
                passes,
                no_restart,
            );
        }
        self.pass
            .record_frame(cmd, &glyphs.gpu, &target, glyphs.method)
    }

    /// Where frame `frame_index` of `glyphs` is drawn: the viewport and scissor its frame
    /// block was written for.
    fn frame_target(&self, glyphs: &UploadedGlyphs, frame_index: usize) -> Result<FrameTarget> {
        self.check_index(frame_index)?;
        let view = glyphs.views.get(frame_index).copied().flatten();
        let (viewport, scissor) = view.ok_or(Error::Call {
            call: "record",
            expected: "set_view for this frame and the current glyphs first",
        })?;
        Ok(FrameTarget {
            frame_index,
            viewport,
            scissor,
        })
    }

    /// Makes the pipelines of the later passes' stages for `glyphs`, where the plan of
    /// frame `frame_index` has more than one pass and they are not made yet
    /// (render::visibility): a frame drawn in one pass, such as a flat field's, never
    /// creates them.
    ///
    /// Makes the pipelines that run the visibility code too, where the frame is culled or
    /// `count`s its work (the other frames' pipelines have it compiled out).
    pub(crate) fn prepare_passes(
        &mut self,
        glyphs: &UploadedGlyphs,
        frame_index: usize,
        count: bool,
    ) -> Result<()> {
        if count && !self.ctx.fragment_stores() {
            return Err(Error::setup(
                "fragmentStoresAndAtomics on the device, which counting the glyphs' work needs",
                "a device created without it (DeviceContext::with_fragment_stores says it has it)",
            ));
        }
        if glyphs.visibility_active(frame_index, count) {
            self.pass
                .prepare_visibility_pipelines(&glyphs.gpu, glyphs.method)?;
        }
        if glyphs.passes(frame_index) <= 1 {
            return Ok(());
        }
        let variants = glyphs
            .gpu
            .sets
            .iter()
            .map(|set| crate::render::raycast::batch_variant(set.layout, set.shape, glyphs.method))
            .collect::<Result<Vec<_>>>()?;
        self.pass.prepare_stage_pipelines(&variants)
    }

    /// [`GlyphRenderer::record_glyphs`] in the passes of the glyphs' plan for this frame
    /// index (render::visibility): `restart` ends the rendering, moves the depths between
    /// the depth attachment and `visibility`'s known depths and begins the rendering
    /// again, before each stage of a pass after the first (and writes the visibility word
    /// there: [`RayCastPass::record_passes`]).
    pub(crate) fn record_glyph_passes(
        &self,
        cmd: vk::CommandBuffer,
        glyphs: &UploadedGlyphs,
        (frame_index, count): (usize, bool),
        visibility: &VisibilityBuffers,
        restart: &mut dyn FnMut(vk::CommandBuffer, crate::vk::DrawStage) -> Result<()>,
    ) -> Result<()> {
        let target = self.frame_target(glyphs, frame_index)?;
        let active = glyphs.visibility_active(frame_index, count);
        let passes = Passes {
            plan: glyphs.plans.get(frame_index),
            visibility,
            active,
        };
        self.pass
            .record_passes(cmd, &glyphs.gpu, &target, glyphs.method, passes, restart)
    }

    /// How many replaced glyph uploads are still kept for frames that may be in flight.
    pub fn retired_count(&self) -> usize {
        self.retired.len()
    }

    /// The frames in flight the renderer was made for.
    pub fn frames_in_flight(&self) -> usize {
        self.frames_in_flight
    }

    /// The ray-cast pass (its formats and options).
    pub fn pass(&self) -> &RayCastPass {
        &self.pass
    }

    /// The ray-cast pass, for settings such as the storage buffer limit.
    pub fn pass_mut(&mut self) -> &mut RayCastPass {
        &mut self.pass
    }

    fn check_index(&self, frame_index: usize) -> Result<()> {
        if frame_index < self.frames_in_flight {
            return Ok(());
        }
        Err(Error::FrameIndex {
            index: frame_index,
            frames: self.frames_in_flight,
        })
    }
}

/// The largest glyph radius, as the headless renderer's magnitude range takes it
/// ([`crate::render::frame::SceneExtent::for_settings`]): the sets' measured one, else
/// measured here when the settings need it, else the largest bounding box's.
fn glyph_radius(sets: &[GlyphSetData], settings: &RenderSettings) -> f64 {
    let measured = sets.iter().map(|s| s.largest_radius).fold(0.0, f64::max);
    if measured > 0.0 {
        return measured;
    }
    if settings.needs_largest_radius() {
        let largest = sets
            .iter()
            .map(|s| largest_radius(&s.world))
            .fold(0.0, f64::max);
        if largest > 0.0 {
            return largest;
        }
    }
    sets.iter()
        .flat_map(|s| s.instances.iter())
        .map(|i| i[3] as f64 * 3f64.sqrt())
        .fold(0.0, f64::max)
}
