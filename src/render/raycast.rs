//! The ray-casting pass: one instanced draw of bounding boxes per glyph set, the ray cast
//! in the fragment shader of the set's (tensor layout, method) variant. The sphere
//! impostor (`Method::Impostor`) is the same pass with one fragment shader for every
//! layout.
//!
//! The pass records into a command buffer it is given, inside dynamic rendering the caller
//! began, with the colour/depth formats, sample count and depth convention it was told
//! at creation ([`PassOptions`]). Pipelines are made by [`RayCastPass::prepare`] (and by
//! [`RayCastPass::upload`] for the scene's sets), never while recording, so recording
//! takes `&self` and several threads may record at once. A scene holds one frame block
//! per frame in flight, and a descriptor set per (glyph batch, frame), so that the glyph
//! data is uploaded once and frame k+1's camera can be written while frame k renders.
//! The headless renderer, tests, benchmarks and an embedding engine
//! ([`crate::render::component::GlyphRenderer`]) all go through [`RayCastPass::record_frame`].
//! The pass and the scenes keep a [`DeviceContext`], so the device outlives them.
use crate::error::{Error, Result, Setting};
use crate::glyph::pieces::PIECES;
use crate::glyph::{GlyphShape, TensorLayout};
use crate::render::batch::{Batch, batches};
use crate::render::frame::{FRAME_DESCRIPTOR, FRAME_USAGE, FrameParams};
use crate::render::glyph_data::GlyphSetData;
use crate::render::shaders::{
    DepthConvention, IMPOSTOR_FRAGMENT, RAYCAST_VERTEX, for_depth, raycast_shader, with_early_tests,
};
use crate::render::shadow_grid::ShadowGrid;
use crate::render::visibility::{Cluster, PassPlan, VisibilityBuffers, visibility_bindings};
use crate::render::{Method, Proxy, ShapeShader};
use crate::vk::recording::bind_graphics;
use crate::vk::{
    Buffer, BufferBinding, DescriptorPool, DeviceContext, DrawStage, GraphicsPipelineDesc,
    Pipeline, PipelineLayout, Pipelines, RasterTarget, ShaderModule, buffer_binding,
    graphics_pipeline, specialized_stages,
};
use ash::vk;

/// Attachment formats of the rendering the pass is recorded into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetFormats {
    /// The colour attachment's format.
    pub color: vk::Format,
    /// The depth attachment's format. A depth-stencil format (`D24_UNORM_S8_UINT`,
    /// `D32_SFLOAT_S8_UINT`) is taken as the host's rendering binds it: as its depth and
    /// its stencil attachment; the glyphs test and write depth and leave the stencil as
    /// it is.
    pub depth: vk::Format,
    /// A second colour attachment that receives the ray distance (R32_SFLOAT), if any.
    /// Without one, the pass uses fragment shaders that have no distance output.
    pub distance: Option<vk::Format>,
}

/// How the target the pass draws into is rasterised: what a host decides once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassOptions {
    /// Samples per pixel of the attachments: 1, 2, 4 or 8. Above 1 the fragment shaders
    /// run per sample (the device needs the sampleRateShading feature), each casting the
    /// ray through its sample, so silhouettes are anti-aliased by the host's resolve.
    pub samples: vk::SampleCountFlags,
    /// Which end of the depth range is near; the glyphs write depth in it.
    pub depth: DepthConvention,
    /// A pipeline cache of the host's, or null.
    pub pipeline_cache: vk::PipelineCache,
    /// A render pass of the host's and the subpass the glyphs are drawn in, whose
    /// attachments have the formats and samples above (Vulkan 1.0-1.2 style); null: the
    /// host draws in dynamic rendering.
    pub render_pass: vk::RenderPass,
    /// The subpass of `render_pass` the glyphs are drawn in.
    pub subpass: u32,
}

impl Default for PassOptions {
    /// glyphcast's own targets: one sample, reversed depth, no cache, dynamic rendering.
    fn default() -> Self {
        PassOptions {
            samples: vk::SampleCountFlags::TYPE_1,
            depth: DepthConvention::Reversed,
            pipeline_cache: vk::PipelineCache::null(),
            render_pass: vk::RenderPass::null(),
            subpass: 0,
        }
    }
}

impl PassOptions {
    /// The sample count as a number; an error for counts other than 1, 2, 4 and 8.
    pub fn sample_count(&self) -> Result<u32> {
        let count = self.samples.as_raw();
        match count {
            1 | 2 | 4 | 8 => Ok(count),
            _ => Err(Error::setting_value(
                Setting::Samples,
                count,
                "the ray-cast pass takes 1, 2, 4 or 8 samples per pixel",
            )),
        }
    }

    pub(crate) fn raster(&self) -> RasterTarget {
        RasterTarget {
            samples: self.samples,
            sample_shading: self.samples != vk::SampleCountFlags::TYPE_1,
            depth_compare: self.depth.compare_op(),
            cache: self.pipeline_cache,
            render_pass: self.render_pass,
            subpass: self.subpass,
        }
    }
}

/// Where in the target one frame is drawn, and with which frame block.
#[derive(Clone, Copy, Debug)]
pub struct FrameTarget {
    /// Which frame in flight (which of the scene's frame blocks).
    pub frame_index: usize,
    /// The viewport (depth range 0 to 1); it must be the one the frame block was made
    /// for ([`FrameParams::window`]).
    pub viewport: vk::Viewport,
    /// The scissor rectangle.
    pub scissor: vk::Rect2D,
}

impl FrameTarget {
    /// Frame 0 over the whole of a target of size `extent`.
    pub fn whole(extent: vk::Extent2D) -> FrameTarget {
        let (viewport, scissor) = viewport_and_scissor(extent);
        FrameTarget {
            frame_index: 0,
            viewport,
            scissor,
        }
    }
}

/// Pipelines and layouts; created once per device, formats and [`PassOptions`].
pub struct RayCastPass {
    ctx: DeviceContext,
    formats: TargetFormats,
    options: PassOptions,
    // Fields drop in order: the pipelines go before the modules and the layout they were
    // made with, the order the validation layer expects.
    /// Keyed by layout, method and whether it casts shadows; the impostor's pipeline by
    /// method alone.
    pipelines: Pipelines<PipelineKey>,
    /// The pipelines of the early stages of the later passes (render::visibility), made
    /// for scenes uploaded to be culled.
    stage_pipelines: Pipelines<(PipelineKey, DrawStage)>,
    /// The boxes' vertex shader for methods that pass no coefficients (the impostor).
    vertex: ShaderModule,
    layout: PipelineLayout,
    buffer_limit: Option<u64>,
    /// CUBE_INDICES, for every box.
    indices: Buffer,
    /// The visibility set of frames drawn in one pass ([`RayCastPass::record_frame`]):
    /// its counters count nothing and its known depth is never read.
    no_visibility: VisibilityBuffers,
    /// Whether scenes uploaded from now on leave their shadows to a later pass
    /// ([`SceneGpu`]'s `deferred`).
    deferred_shadows: bool,
    /// What scenes uploaded (and pipelines prepared) from now on draw around their
    /// glyphs (`--proxy`).
    proxy: Proxy,
}

/// The 12 triangles of a box as corner indices (bit 0: x, bit 1: y, bit 2: z), counter-
/// clockwise seen from outside. Every triangle starts at corner 0 or corner 7, its
/// provoking vertex: only those two corners load the glyph's coefficients for the flat
/// inputs of the fragment shader (raycast.vert), and the indexed draw lets the eight
/// corners be shaded once each per box.
pub(crate) const CUBE_INDICES: [u16; 36] = [
    0, 2, 3, 0, 3, 1, // -z
    7, 4, 5, 7, 6, 4, // +z
    0, 1, 5, 0, 5, 4, // -y
    7, 2, 6, 7, 3, 2, // +y
    0, 4, 6, 0, 6, 2, // -x
    7, 1, 3, 7, 5, 1, // +x
];

/// The 6 triangles of the hull's outline (an octagon: vertex k where its edges k and
/// k + 1 meet), fanned from vertex 0, the provoking vertex of each.
pub(crate) const OUTLINE_INDICES: [u16; 18] =
    [0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 6, 0, 6, 7];

/// The pieces' octagons (`--proxy pieces`): [`OUTLINE_INDICES`] for each of the eight
/// pieces, piece p's vertices 8 p to 8 p + 7 (raycast.vert).
pub(crate) fn pieces_indices() -> Vec<u16> {
    (0..PIECES as u16)
        .flat_map(|p| OUTLINE_INDICES.map(|i| i + 8 * p))
        .collect()
}

/// The pass's index buffer: [`CUBE_INDICES`], [`OUTLINE_INDICES`], then
/// [`pieces_indices`].
fn proxy_indices() -> Vec<u16> {
    [CUBE_INDICES.as_slice(), &OUTLINE_INDICES, &pieces_indices()].concat()
}

/// The range of the pass's index buffer ([`proxy_indices`]) a draw of `proxy` takes.
pub(crate) fn proxy_index_range(proxy: Proxy) -> (u32, u32) {
    let (cube, outline) = (CUBE_INDICES.len() as u32, OUTLINE_INDICES.len() as u32);
    match proxy {
        Proxy::Box => (0, cube),
        Proxy::Hull => (cube, outline),
        Proxy::Pieces => (cube + outline, PIECES as u32 * outline),
    }
}

/// Components the proxy boxes' vertex shader passes to a ray-casting fragment shader of
/// a layout: four flat vec4/uint locations (glyph index, sphere, rotation, extent) and
/// the monomial coefficients four to a location (raycast.vert), counted as whole
/// locations.
pub fn varying_components(layout: TensorLayout, shape: ShapeShader) -> u32 {
    let mut monomials = crate::glyph::monomials::symmetric_count(layout.order) as u32;
    if shape == ShapeShader::Plane {
        // The plane glyph's T follows D.
        monomials += crate::glyph::PLANE_TRACE_COEFFICIENTS as u32;
    }
    if shape == ShapeShader::Ratio {
        // The ratio glyph's T and Q follow D.
        monomials += crate::glyph::RATIO_EXTRA_COEFFICIENTS as u32;
    }
    4 * (4 + monomials.div_ceil(4))
}

/// Binding of the frame's parameter block (glsl/frame.glsl `FrameParams`); the test in
/// `render::interface` holds the shaders to it.
pub(crate) const FRAME_BINDING: u32 = 0;
/// Binding of a glyph batch's coefficients (glsl/frame.glsl `Coefficients`).
pub(crate) const COEFFICIENTS_BINDING: u32 = 1;
/// Bindings of what shadow rays read (glsl/shadow.glsl): the batch's instances and boxes
/// (its vertex buffers, read as storage buffers too), its grid's header and cells, and
/// the grid's entries ([`ShadowGrid`]).
pub(crate) const SHADOW_BINDINGS: [u32; 4] = [2, 3, 4, 5];
/// Binding of the batch's pieces (glsl/raycast.vert `Pieces`; `--proxy pieces`), read by
/// the vertex shader.
pub(crate) const PIECES_BINDING: u32 = 6;

/// The bindings of a glyph batch's descriptor set: the frame block, the coefficients,
/// what shadow rays read and the pieces.
pub(crate) fn batch_bindings() -> [vk::DescriptorSetLayoutBinding<'static>; 7] {
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    let storage = vk::DescriptorType::STORAGE_BUFFER;
    let shadow = |binding| buffer_binding(binding, storage, vk::ShaderStageFlags::FRAGMENT);
    [
        buffer_binding(FRAME_BINDING, FRAME_DESCRIPTOR, stages),
        buffer_binding(COEFFICIENTS_BINDING, storage, stages),
        shadow(SHADOW_BINDINGS[0]),
        shadow(SHADOW_BINDINGS[1]),
        shadow(SHADOW_BINDINGS[2]),
        shadow(SHADOW_BINDINGS[3]),
        buffer_binding(PIECES_BINDING, storage, vk::ShaderStageFlags::VERTEX),
    ]
}

/// Specialisation constant 0 of raycast.vert (`ORIENTED_BOX`): 1 draws each glyph's
/// oriented box, 0 the cube around its bounding sphere (the sphere impostor's proxy).
const ORIENTED_BOX_CONSTANT: u32 = 0;

/// Specialisation constant 2 of raycast.vert (`OUTLINE`): 1 draws each glyph as the
/// octagon around its hull's outline ([`OUTLINE_INDICES`]), 0 as its box. A constant, not
/// a value of the frame block: the outline's code is left out of the box's pipelines,
/// whose creation it slowed by a third on lavapipe.
const OUTLINE_CONSTANT: u32 = 2;

/// Specialisation constant 3 of raycast.vert and of the ray-casting fragment shaders
/// (`PIECES`): 1 draws the pieces' octagons and clips each ray to its piece.
const PIECES_CONSTANT: u32 = 3;

/// Specialisation constant 1 of the ray-casting fragment shaders (`VISIBILITY`,
/// glsl/raycast_common.glsl): 0 compiles the visibility code out, for the frames whose
/// visibility word is 0. Mesa 22.3's lavapipe runs skipped branches masked, and every
/// fragment of every frame paid for that code: a flat field of 256 band-8 fODFs drew 11
/// to 12 % slower than before the code existed (measured by building the history).
const VISIBILITY_CONSTANT: u32 = 1;

/// A pipeline's key: the layout (none for the impostor), the method, the glyph shape's
/// shader, and whether it casts shadows (the exact method only).
/// and whether its fragments run the visibility code (culling, work counters).
/// A pipeline's variant: layout, method, shape shader, shadows, visibility code and the
/// hull's outline (raycast.vert's OUTLINE).
type PipelineKey = (Option<TensorLayout>, Method, ShapeShader, bool, bool, Proxy);

/// What a glyph batch is drawn with: its layout, the method and the shape's shader
/// (`batch_variant`); the pipelines [`RayCastPass::prepare_pipelines`] makes.
pub type Variant = (TensorLayout, Method, ShapeShader);

/// One glyph set on the GPU: a batch of glyphs that share a pipeline and one draw (a
/// set larger than a storage buffer is split into several).
pub struct GlyphSetGpu {
    /// The tensor layout of its coefficients.
    pub layout: TensorLayout,
    /// How negative lobes are drawn.
    pub negative: crate::glyph::NegativeMode,
    /// The batch's glyph shape, which picks its shader (`batch_variant`).
    pub shape: GlyphShape,
    /// Glyphs in the batch (instances drawn).
    pub count: u32,
    instances: Buffer,
    boxes: Buffer,
    hulls: Buffer,
    /// The pieces' words (`PIECE_WORDS` a glyph), or one placeholder word where the
    /// batch draws no pieces.
    pieces: Buffer,
    /// What the batch draws around its glyphs ([`drawn_proxy`] of the scene's).
    pub(crate) proxy: Proxy,
    _coefficients: Buffer,
    /// The shadow rays' grid over the batch's boxes: its cells and its entries.
    _grid: [Buffer; 2],
    /// One per frame in flight: the coefficients with that frame's block.
    pub(crate) descriptor_sets: Vec<vk::DescriptorSet>,
    /// Its glyphs in clusters, for the order of the passes (render::visibility).
    pub(crate) clusters: Vec<Cluster>,
}

impl GlyphSetGpu {
    /// The batch's descriptor set for frame block `frame_index`.
    pub(crate) fn descriptor_set(&self, frame_index: usize) -> Result<vk::DescriptorSet> {
        self.descriptor_sets
            .get(frame_index)
            .copied()
            .ok_or(Error::FrameIndex {
                index: frame_index,
                frames: self.descriptor_sets.len(),
            })
    }

    /// Records the draw of the batch's boxes (`indices`: [`CUBE_INDICES`]), one instance
    /// per glyph.
    ///
    /// # Safety
    /// `cmd` is recording inside a rendering, with a pipeline of the boxes' vertex
    /// input bound; the buffers stay alive until the submission completes.
    pub(crate) unsafe fn record_boxes(
        &self,
        d: &ash::Device,
        cmd: vk::CommandBuffer,
        indices: vk::Buffer,
        proxy: Proxy,
    ) {
        let (first, count) = proxy_index_range(proxy);
        let buffers = [self.instances.handle, self.boxes.handle, self.hulls.handle];
        // SAFETY: the caller's promise.
        unsafe {
            d.cmd_bind_vertex_buffers(cmd, 0, &buffers, &[0, 0, 0]);
            d.cmd_bind_index_buffer(cmd, indices, 0, vk::IndexType::UINT16);
            d.cmd_draw_indexed(cmd, count, self.count, first, 0, 0);
        }
    }

    /// Records the draws of the given clusters' boxes, as [`GlyphSetGpu::record_boxes`].
    ///
    /// # Safety
    /// As [`GlyphSetGpu::record_boxes`].
    unsafe fn record_clusters(
        &self,
        d: &ash::Device,
        cmd: vk::CommandBuffer,
        indices: vk::Buffer,
        proxy: Proxy,
        clusters: &mut dyn Iterator<Item = u32>,
    ) {
        let (first, count) = proxy_index_range(proxy);
        let buffers = [self.instances.handle, self.boxes.handle, self.hulls.handle];
        // SAFETY: the caller's promise.
        unsafe {
            d.cmd_bind_vertex_buffers(cmd, 0, &buffers, &[0, 0, 0]);
            d.cmd_bind_index_buffer(cmd, indices, 0, vk::IndexType::UINT16);
            for c in clusters {
                let cluster = &self.clusters[c as usize];
                d.cmd_draw_indexed(cmd, count, cluster.count, first, 0, cluster.first);
            }
        }
    }
}

/// Everything a scene needs on the GPU: the glyph sets, uploaded once, and one frame
/// parameter buffer per frame in flight.
pub struct SceneGpu {
    frames: Vec<Buffer>,
    /// What its glyphs are drawn with (`--proxy`; the pass's
    /// mode at upload), which picks the pipelines and the index range of the draws.
    pub(crate) proxy: Proxy,
    /// Whether its exact batches cast shadows (the first frame block asked for them): by
    /// the pipelines that cast them, or by a later pass (`deferred`).
    pub(crate) shadows: bool,
    /// Whether the shadows are cast after the frame, by `glyph_shadows::GlyphShadowPass`:
    /// the batches are drawn by the pipelines without shadows.
    pub(crate) deferred: bool,
    pool: DescriptorPool,
    /// The pools of the descriptor sets of frames added after the upload
    /// ([`SceneGpu::add_frames`]).
    added_pools: Vec<DescriptorPool>,
    /// The batches, one draw each.
    pub sets: Vec<GlyphSetGpu>,
}

impl RayCastPass {
    /// Layouts and the proxy boxes' shaders for attachments of `formats` with one sample
    /// and reversed depth; pipelines are made by [`RayCastPass::prepare`] and
    /// [`RayCastPass::upload`].
    pub fn new(ctx: &DeviceContext, formats: TargetFormats) -> Result<RayCastPass> {
        RayCastPass::with_options(ctx, formats, PassOptions::default())
    }

    /// [`RayCastPass::new`] for a host's samples, depth convention and pipeline cache.
    pub fn with_options(
        ctx: &DeviceContext,
        formats: TargetFormats,
        options: PassOptions,
    ) -> Result<RayCastPass> {
        options.sample_count()?;
        let bindings = batch_bindings();
        // Set 1: what the fragments know of visibility (render::visibility).
        let visibility = visibility_bindings();
        // The fragment shaders' push constant: the glyph set's negative mode, or a plane
        // set's root (one u32).
        let layout = PipelineLayout::with_sets(
            ctx,
            &[&bindings, &visibility],
            vk::ShaderStageFlags::FRAGMENT,
            4,
        )?;
        let indices = Buffer::with_data(
            ctx,
            "proxy indices",
            &proxy_indices(),
            vk::BufferUsageFlags::INDEX_BUFFER,
        )?;
        let no_visibility = VisibilityBuffers::without_passes(ctx, visibility_layout(&layout)?)?;
        Ok(RayCastPass {
            no_visibility,
            indices,
            ctx: ctx.clone(),
            formats,
            options,
            layout,
            // SAFETY: the SPIR-V comes from build.rs and was validated by glslang.
            vertex: unsafe { ShaderModule::new(ctx, RAYCAST_VERTEX)? },
            pipelines: Pipelines::new(),
            stage_pipelines: Pipelines::new(),
            buffer_limit: None,
            deferred_shadows: false,
            proxy: Proxy::Box,
        })
    }

    /// Whether scenes uploaded from now on that cast shadows are drawn without them, the
    /// shadows left to `glyph_shadows::GlyphShadowPass` (the headless renderer's frames,
    /// whose distance attachment tells that pass each pixel's hit).
    pub(crate) fn set_deferred_shadows(&mut self, deferred: bool) {
        self.deferred_shadows = deferred;
    }

    /// The attachment formats the pass was made for.
    pub fn formats(&self) -> TargetFormats {
        self.formats
    }

    /// What scenes uploaded from now on draw around each glyph (their pipelines are
    /// prepared for it): [`Proxy::Hull`]'s outline or [`Proxy::Box`].
    pub fn set_proxy(&mut self, proxy: Proxy) {
        self.proxy = proxy;
    }

    /// The samples, depth convention and cache the pass was made for.
    pub fn options(&self) -> PassOptions {
        self.options
    }

    /// Makes the pipeline of a variant if it is not made yet: what recording it needs.
    pub fn prepare(&mut self, layout: TensorLayout, method: Method) -> Result<()> {
        self.pipeline(layout, method).map(|_| ())
    }

    /// The pipeline of a variant (without shadows), made now if it was not.
    pub fn pipeline(&mut self, layout: TensorLayout, method: Method) -> Result<vk::Pipeline> {
        let key = pipeline_key(
            (layout, method, ShapeShader::Polynomial),
            false,
            false,
            self.proxy,
        );
        if let Some(p) = self.pipelines.get(&key) {
            return Ok(p);
        }
        let (vertex, fragment) = self.shaders((layout, method, ShapeShader::Polynomial), false)?;
        let pipeline = self.create_pipeline(vertex, fragment, key, DrawStage::Normal)?;
        Ok(self.pipelines.insert(key, pipeline))
    }

    /// Creates the pipelines of `variants` that do not exist yet, each on a thread of its
    /// own: drivers compile a pipeline on the creating thread, and a scene of several
    /// orders needs several (creating them is most of a one-shot render's time).
    pub fn prepare_pipelines(&mut self, variants: &[Variant]) -> Result<()> {
        self.prepare_pipelines_for(variants, false)
    }

    /// [`RayCastPass::prepare_pipelines`] of the variants that cast shadows (`shadows`),
    /// where the method has them, or that do not.
    fn prepare_pipelines_for(&mut self, variants: &[Variant], shadows: bool) -> Result<()> {
        self.prepare_normal_pipelines(variants, (shadows, false), self.proxy)
    }

    /// The pipelines that draw the frames of `scene` whose visibility word is not 0
    /// (culled by early outs or in passes, or counting their work), where they are not
    /// made yet: made when a frame first needs them, so that a frame without culling
    /// or counters never compiles them.
    pub(crate) fn prepare_visibility_pipelines(
        &mut self,
        scene: &SceneGpu,
        method: Method,
    ) -> Result<()> {
        let variants = scene
            .sets
            .iter()
            .map(|set| batch_variant(set.layout, set.shape, method))
            .collect::<Result<Vec<_>>>()?;
        let shadows = scene.shadows && !scene.deferred;
        self.prepare_normal_pipelines(&variants, (shadows, true), scene.proxy)
    }

    /// The normal-stage pipelines of `variants`, casting shadows or not, running the
    /// visibility code or not.
    fn prepare_normal_pipelines(
        &mut self,
        variants: &[Variant],
        (shadows, visibility): (bool, bool),
        proxy: Proxy,
    ) -> Result<()> {
        type Missing = (PipelineKey, Option<&'static [u32]>, &'static [u32]);
        let mut missing: Vec<Missing> = Vec::new();
        for &variant in variants {
            let key = pipeline_key(variant, shadows, visibility, proxy);
            if self.pipelines.get(&key).is_none() && !missing.iter().any(|(k, ..)| *k == key) {
                let (vertex, fragment) = self.shaders(variant, key.3)?;
                missing.push((key, vertex, fragment));
            }
        }
        let this = &*self;
        let created: Vec<Result<Pipeline>> = std::thread::scope(|scope| {
            let threads: Vec<_> = missing
                .iter()
                .skip(1)
                .map(|&(key, vertex, fragment)| {
                    scope.spawn(move || {
                        this.create_pipeline(vertex, fragment, key, DrawStage::Normal)
                    })
                })
                .collect();
            let first = missing.first().map(|&(key, vertex, fragment)| {
                this.create_pipeline(vertex, fragment, key, DrawStage::Normal)
            });
            first
                .into_iter()
                .chain(threads.into_iter().map(|t| {
                    t.join().unwrap_or_else(|_| {
                        Err(Error::Thread {
                            what: "pipeline creation",
                        })
                    })
                }))
                .collect()
        });
        for ((key, ..), pipeline) in missing.into_iter().zip(created) {
            self.pipelines.insert(key, pipeline?);
        }
        Ok(())
    }

    /// The vertex (`None`: the shared one) and fragment shaders of a variant, or why it
    /// cannot be drawn by this pass on this device.
    fn shaders(
        &self,
        (layout, method, shape): Variant,
        shadows: bool,
    ) -> Result<(Option<&'static [u32]>, &'static [u32])> {
        Ok(match method {
            Method::Impostor if self.formats.distance.is_none() => {
                return Err(Error::Call {
                    call: "RayCastPass::pipeline",
                    expected: "a distance attachment for the impostor pass",
                });
            }
            Method::Impostor => (None, IMPOSTOR_FRAGMENT),
            Method::Mesh(_) => {
                return Err(Error::Unsupported {
                    what: crate::error::Asked::Method(Setting::Method.with(method)),
                    by: "the ray-casting pass".into(),
                });
            }
            Method::Fixed | Method::Interval | Method::Affine | Method::Exact => {
                let needed = varying_components(layout, shape);
                let available = self.ctx.max_varying_components();
                if needed > available {
                    return Err(Error::Layout {
                        layout: layout.into(),
                        error: Box::new(Error::Limit {
                            what: "vertex-to-fragment components \
                                   (maxVertexOutputComponents, maxFragmentInputComponents)",
                            value: u64::from(needed),
                            limit: u64::from(available),
                            settings: &[],
                        }),
                    });
                }
                let shader =
                    raycast_shader(layout, method, shape).ok_or_else(|| Error::Unsupported {
                        what: crate::error::Asked::Layout(layout.into()),
                        by: Setting::Method.with(method),
                    })?;
                let fragment =
                    match (self.formats.distance, shadows) {
                        (Some(_), false) => shader.fragment,
                        (None, false) => shader.color_only_fragment,
                        (Some(_), true) => {
                            shader.shadows_fragment.ok_or_else(|| Error::Unsupported {
                                what: crate::error::Asked::Method(Setting::Method.with(method)),
                                by: Setting::Shadows.with("hard"),
                            })?
                        }
                        (None, true) => shader.shadows_color_only_fragment.ok_or_else(|| {
                            Error::Unsupported {
                                what: crate::error::Asked::Method(Setting::Method.with(method)),
                                by: Setting::Shadows.with("hard"),
                            }
                        })?,
                    };
                (Some(shader.vertex), fragment)
            }
        })
    }

    /// The pipeline of a prepared variant; an error (not a compile) if it was not made.
    fn prepared(
        &self,
        variant: Variant,
        (shadows, visibility, proxy): (bool, bool, Proxy),
    ) -> Result<vk::Pipeline> {
        self.pipelines
            .get(&pipeline_key(variant, shadows, visibility, proxy))
            .ok_or(Error::Call {
                call: "RayCastPass::record",
                expected: "RayCastPass::prepare (or upload) for this layout and method first",
            })
    }

    /// A pipeline of the given fragment shader and vertex shader (`None`: the shared one,
    /// which passes no coefficients) for the variant `key`.
    fn create_pipeline(
        &self,
        vertex_spirv: Option<&[u32]>,
        fragment_spirv: &[u32],
        key: PipelineKey,
        stage: DrawStage,
    ) -> Result<Pipeline> {
        // The host's depth convention is one word of the fragment shader's SPIR-V, and
        // so is the early depth test of the later passes' stages.
        let fragment_spirv = match stage {
            DrawStage::Normal => for_depth(fragment_spirv, self.options.depth),
            _ => with_early_tests(fragment_spirv),
        };
        // SAFETY: the SPIR-V comes from build.rs and was validated by glslang; the modules
        // may go once the pipeline exists.
        let fragment = unsafe { ShaderModule::fragment(&self.ctx, &fragment_spirv)? };
        let vertex = match vertex_spirv {
            // SAFETY: as above.
            Some(spirv) => Some(unsafe { ShaderModule::new(&self.ctx, spirv)? }),
            None => None,
        };
        let vertex = vertex.as_ref().unwrap_or(&self.vertex);
        self.create_pipeline_with(vertex.handle(), fragment.handle(), key, stage)
    }

    fn create_pipeline_with(
        &self,
        vertex: vk::ShaderModule,
        fragment: vk::ShaderModule,
        (_, method, _, _, visibility, proxy): PipelineKey,
        stage: DrawStage,
    ) -> Result<Pipeline> {
        let entries = [
            vk::SpecializationMapEntry {
                constant_id: ORIENTED_BOX_CONSTANT,
                offset: 0,
                size: 4,
            },
            vk::SpecializationMapEntry {
                constant_id: OUTLINE_CONSTANT,
                offset: 4,
                size: 4,
            },
            vk::SpecializationMapEntry {
                constant_id: PIECES_CONSTANT,
                offset: 8,
                size: 4,
            },
        ];
        // A SPIR-V boolean specialisation constant takes a 32-bit value.
        let pieces = u32::from(proxy == Proxy::Pieces).to_ne_bytes();
        let mut constants = [0u8; 12];
        constants[..4].copy_from_slice(&u32::from(method != Method::Impostor).to_ne_bytes());
        constants[4..8].copy_from_slice(&u32::from(proxy != Proxy::Box).to_ne_bytes());
        constants[8..].copy_from_slice(&pieces);
        let specialization = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(&constants);
        // The later passes' stages always run the visibility code.
        let visibility = u32::from(visibility || stage != DrawStage::Normal).to_ne_bytes();
        let fragment_entries = [
            vk::SpecializationMapEntry {
                constant_id: VISIBILITY_CONSTANT,
                offset: 0,
                size: 4,
            },
            vk::SpecializationMapEntry {
                constant_id: PIECES_CONSTANT,
                offset: 4,
                size: 4,
            },
        ];
        let fragment_data = [visibility, pieces].concat();
        let fragment_constants = vk::SpecializationInfo::default()
            .map_entries(&fragment_entries)
            .data(&fragment_data);
        let stages = specialized_stages(
            vertex,
            fragment,
            (Some(&specialization), Some(&fragment_constants)),
        );
        glyph_pipeline(
            &self.ctx,
            self.formats,
            self.layout.handle(),
            &stages,
            InstanceInput::WithBoxes,
            self.options.raster(),
            (None, stage),
        )
    }

    /// Makes the pipelines of the later passes' early stages for `variants` (without
    /// shadows), where they are not made yet: what culling a scene needs
    /// (render::visibility). The impostor's variant has none (it is not culled).
    pub(crate) fn prepare_stage_pipelines(&mut self, variants: &[Variant]) -> Result<()> {
        type Missing = (
            (PipelineKey, DrawStage),
            Option<&'static [u32]>,
            &'static [u32],
        );
        let mut missing: Vec<Missing> = Vec::new();
        for &variant in variants {
            if variant.1 == Method::Impostor {
                continue;
            }
            let key = pipeline_key(variant, false, true, self.proxy);
            for stage in [DrawStage::Nearest, DrawStage::Shade] {
                let staged = (key, stage);
                if self.stage_pipelines.get(&staged).is_none()
                    && !missing.iter().any(|(k, ..)| *k == staged)
                {
                    let (vertex, fragment) = self.shaders(variant, false)?;
                    missing.push((staged, vertex, fragment));
                }
            }
        }
        let this = &*self;
        let created: Vec<Result<Pipeline>> = std::thread::scope(|scope| {
            let threads: Vec<_> = missing
                .iter()
                .map(|&((key, stage), vertex, fragment)| {
                    scope.spawn(move || this.create_pipeline(vertex, fragment, key, stage))
                })
                .collect();
            threads
                .into_iter()
                .map(|t| {
                    t.join().unwrap_or_else(|_| {
                        Err(Error::Thread {
                            what: "pipeline creation",
                        })
                    })
                })
                .collect()
        });
        for ((staged, ..), pipeline) in missing.into_iter().zip(created) {
            self.stage_pipelines.insert(staged, pipeline?);
        }
        Ok(())
    }

    /// Uploads glyph sets and the frame parameters for one frame in flight; prepares
    /// their pipelines and creates their descriptor sets.
    pub fn upload(
        &mut self,
        ctx: &DeviceContext,
        sets: &[GlyphSetData],
        frame: &FrameParams,
        method: Method,
    ) -> Result<SceneGpu> {
        self.upload_in_flight(ctx, sets, frame, method, 1)
    }

    /// [`RayCastPass::upload`] for `frames_in_flight` frames: the glyphs once, and that
    /// many frame blocks, each starting as `frame`.
    pub fn upload_in_flight(
        &mut self,
        ctx: &DeviceContext,
        sets: &[GlyphSetData],
        frame: &FrameParams,
        method: Method,
        frames_in_flight: usize,
    ) -> Result<SceneGpu> {
        if frames_in_flight == 0 {
            return Err(Error::Call {
                call: "SceneGpu::new",
                expected: "at least one frame in flight",
            });
        }
        let frames = (0..frames_in_flight)
            .map(|_| Buffer::with_data(ctx, "frame", std::slice::from_ref(frame), FRAME_USAGE))
            .collect::<Result<Vec<_>>>()?;
        // Sets that share a pipeline share buffers and a draw; a batch larger than one
        // storage buffer is split (the method's "render successively").
        let limit = self.storage_buffer_limit(ctx);
        let chunks = batches(sets, limit, |layout, shape| {
            4 * shape.coefficient_count(layout.coefficient_count()) as u64
        })?;
        let variants: Vec<_> = chunks
            .iter()
            .map(|chunk| batch_variant(chunk.layout, chunk.shape, method))
            .collect::<Result<_>>()?;
        // Shadows or ambient occlusion, as the first frame block asks: the rays from the
        // hits need a pipeline of their own.
        let shadows = frame.casts_rays();
        let deferred = shadows && self.deferred_shadows;
        self.prepare_pipelines_for(&variants, shadows && !deferred)?;
        let pool = DescriptorPool::new(ctx, chunks.len() * frames_in_flight, 0, 7)?;
        let mut scene = SceneGpu {
            frames,
            proxy: self.proxy,
            shadows,
            deferred,
            pool,
            added_pools: Vec::new(),
            sets: Vec::new(),
        };
        for (chunk, variant) in chunks.iter().zip(&variants) {
            let proxy = drawn_proxy(self.proxy, variant.1, variant.2);
            let set = upload_chunk(ctx, &scene, self.layout.set_layout(), chunk, proxy)?;
            scene.sets.push(set);
        }
        Ok(scene)
    }

    /// Adds frame blocks to `scene` until it has `frames_in_flight`, each with its
    /// frame parameters (a copy of frame 0's until the frame's view is set) and its
    /// descriptor set per batch; the frames in flight keep theirs, untouched.
    pub(crate) fn add_frames(&self, scene: &mut SceneGpu, frames_in_flight: usize) -> Result<()> {
        let old = scene.frames.len();
        if frames_in_flight <= old {
            return Ok(());
        }
        let ctx = self.ctx.clone();
        let bytes = scene.frames[0].read()?;
        let size = std::mem::size_of::<FrameParams>();
        let first: FrameParams =
            bytemuck::pod_read_unaligned(bytes.get(..size).ok_or(Error::Call {
                call: "RayCastPass::add_frames",
                expected: "a frame block of the frame parameters' size",
            })?);
        let added = frames_in_flight - old;
        let pool = DescriptorPool::new(&ctx, scene.sets.len().max(1) * added, 0, 7)?;
        for _ in old..frames_in_flight {
            scene.frames.push(Buffer::with_data(
                &ctx,
                "frame",
                std::slice::from_ref(&first),
                FRAME_USAGE,
            )?);
        }
        for k in 0..scene.sets.len() {
            for frame in old..frames_in_flight {
                let set = frame_descriptor_set(
                    &pool,
                    self.layout.set_layout(),
                    &scene.frames[frame],
                    &scene.sets[k],
                )?;
                scene.sets[k].descriptor_sets.push(set);
            }
        }
        scene.added_pools.push(pool);
        Ok(())
    }

    /// Caps the bytes of coefficients per storage buffer below the device's
    /// maxStorageBufferRange (tests use it to force the split path); `None` lifts the cap.
    pub fn set_storage_buffer_limit(&mut self, bytes: Option<u64>) {
        self.buffer_limit = bytes;
    }

    /// The bytes a storage buffer of this pass may hold: the device's range, or the cap
    /// set on it.
    pub(crate) fn storage_buffer_limit(&self, ctx: &DeviceContext) -> u64 {
        let device = ctx.max_storage_buffer_range();
        self.buffer_limit.map_or(device, |cap| cap.min(device))
    }

    /// Records the draws of every glyph set with frame block 0 over the whole target. The
    /// caller has begun dynamic rendering with attachments of this pass's formats, of
    /// size `extent`.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        scene: &SceneGpu,
        extent: vk::Extent2D,
        method: Method,
    ) -> Result<()> {
        self.record_frame(cmd, scene, &FrameTarget::whole(extent), method)
    }

    /// Records the draws of every glyph set with the frame block and viewport of
    /// `target`. The caller has begun rendering with attachments of this pass's formats
    /// and samples. Records only: no pipeline is made (an unprepared variant is an error),
    /// nothing is written or submitted, so threads may record into their own command
    /// buffers at once.
    pub fn record_frame(
        &self,
        cmd: vk::CommandBuffer,
        scene: &SceneGpu,
        target: &FrameTarget,
        method: Method,
    ) -> Result<()> {
        let passes = Passes {
            plan: None,
            visibility: &self.no_visibility,
            active: false,
        };
        self.record_passes(cmd, scene, target, method, passes, &mut |_, _| Ok(()))
    }

    /// [`RayCastPass::record_frame`] in the passes of `passes.plan` (one pass of every
    /// glyph without a plan): before each stage of a pass after the first, `restart`
    /// ends the rendering, moves the depths between the depth attachment and the known
    /// depths of `passes.visibility` (the known depths, the gate) and begins the rendering
    /// again; the fragments of later passes are not launched where their box lies behind
    /// the depth they are tested against (render::visibility). The
    /// visibility word in the known depths' header says what each pass does: the caller
    /// writes it (and clears the counters) before the first pass, `restart` before each
    /// later one.
    pub(crate) fn record_passes(
        &self,
        cmd: vk::CommandBuffer,
        scene: &SceneGpu,
        target: &FrameTarget,
        method: Method,
        passes: Passes,
        restart: &mut dyn FnMut(vk::CommandBuffer, DrawStage) -> Result<()>,
    ) -> Result<()> {
        let frames = scene.frames.len();
        if target.frame_index >= frames {
            return Err(Error::FrameIndex {
                index: target.frame_index,
                frames,
            });
        }
        let Some(plan) = passes.plan.filter(|p| p.passes() > 0) else {
            for set in &scene.sets {
                let normal = (&passes, DrawStage::Normal);
                self.record_batch(cmd, scene, target, method, set, normal, None)?;
            }
            return Ok(());
        };
        for k in 0..plan.passes() {
            let stages: &[DrawStage] = if k == 0 {
                &[DrawStage::Normal]
            } else {
                &[DrawStage::Nearest, DrawStage::Shade]
            };
            for &stage in stages {
                if k > 0 {
                    restart(cmd, stage)?;
                }
                let draws = plan.pass(k);
                for (b, set) in scene.sets.iter().enumerate() {
                    let mut clusters = draws
                        .iter()
                        .filter(|(batch, _)| *batch as usize == b)
                        .map(|&(_, c)| c)
                        .peekable();
                    if clusters.peek().is_none() {
                        continue;
                    }
                    let staged = (&passes, stage);
                    self.record_batch(
                        cmd,
                        scene,
                        target,
                        method,
                        set,
                        staged,
                        Some(&mut clusters),
                    )?;
                }
            }
            if k > 0 {
                restart(cmd, DrawStage::Normal)?;
            }
        }
        Ok(())
    }

    /// Records the draws of one batch's `clusters` (`None`: the whole batch in one draw)
    /// with the visibility set of `passes`.
    #[allow(clippy::too_many_arguments)]
    fn record_batch(
        &self,
        cmd: vk::CommandBuffer,
        scene: &SceneGpu,
        target: &FrameTarget,
        method: Method,
        set: &GlyphSetGpu,
        (passes, stage): (&Passes, DrawStage),
        clusters: Option<&mut dyn Iterator<Item = u32>>,
    ) -> Result<()> {
        let variant = batch_variant(set.layout, set.shape, method)?;
        let pipeline = match stage {
            DrawStage::Normal => {
                let shadows = scene.shadows && !scene.deferred;
                self.prepared(variant, (shadows, passes.active, scene.proxy))?
            }
            _ => self
                .stage_pipelines
                .get(&(pipeline_key(variant, false, true, scene.proxy), stage))
                .ok_or(Error::Call {
                    call: "RayCastPass::record_passes",
                    expected: "the stage pipelines of a culled scene (prepare_stage_pipelines)",
                })?,
        };
        // A plane or ratio glyph set has no negative lobes: the word says which root
        // it draws.
        let hide = match set.shape {
            GlyphShape::PlaneMin => crate::catalog::codes::PLANE_MIN,
            GlyphShape::PlaneMax => crate::catalog::codes::PLANE_MAX,
            GlyphShape::RatioMin => crate::catalog::codes::RATIO_MIN,
            GlyphShape::RatioMax => crate::catalog::codes::RATIO_MAX,
            _ => set.negative.shader_code(),
        };
        // SAFETY: recording state is the caller's; all handles are alive.
        unsafe {
            let d = self.ctx.device();
            let descriptor_set = set.descriptor_sets[target.frame_index];
            let pipeline = (pipeline, self.layout.handle());
            bind_graphics(
                d,
                cmd,
                pipeline,
                descriptor_set,
                (target.viewport, target.scissor),
            );
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout.handle(),
                1,
                &[passes.visibility.set],
                &[],
            );
            d.cmd_push_constants(
                cmd,
                self.layout.handle(),
                vk::ShaderStageFlags::FRAGMENT,
                0,
                &hide.to_ne_bytes(),
            );
            let proxy = set.proxy;
            match clusters {
                Some(clusters) => set.record_clusters(d, cmd, self.indices.handle, proxy, clusters),
                None => set.record_boxes(d, cmd, self.indices.handle, proxy),
            }
        }
        Ok(())
    }

    /// The layout of the visibility set (set 1), for a target's [`VisibilityBuffers`].
    pub(crate) fn visibility_set_layout(&self) -> Result<vk::DescriptorSetLayout> {
        visibility_layout(&self.layout)
    }
}

/// How a frame's passes see visibility: the plan of its passes and the target's
/// visibility buffers.
pub(crate) struct Passes<'a> {
    /// The passes; `None`: one pass of every glyph.
    pub plan: Option<&'a PassPlan>,
    /// The target's counters and known depths.
    pub visibility: &'a VisibilityBuffers,
    /// Whether the frame's visibility word may be other than 0 (it is culled or counts
    /// its work): its normal stage is then drawn by the pipelines that run the
    /// visibility code ([`RayCastPass::prepare_visibility_pipelines`]).
    pub active: bool,
}

/// Set 1 of the ray-casting pass's layout.
fn visibility_layout(layout: &PipelineLayout) -> Result<vk::DescriptorSetLayout> {
    layout.set_layout_at(1).ok_or(Error::Call {
        call: "RayCastPass::visibility_set_layout",
        expected: "the pass's layout of two sets",
    })
}

/// The key of a variant's pipeline: the impostor's is shared by every layout and shape,
/// and only the exact method casts shadows, from polynomial glyphs (the other shapes'
/// shaders take no rays: they are drawn without shadows).
fn pipeline_key(
    (layout, method, shape): Variant,
    shadows: bool,
    visibility: bool,
    proxy: Proxy,
) -> PipelineKey {
    let proxy = drawn_proxy(proxy, method, shape);
    match (method, shape) {
        // (The impostor's shader has no visibility code.)
        (Method::Impostor, _) => (None, method, ShapeShader::Polynomial, false, false, proxy),
        (Method::Exact, ShapeShader::Polynomial) => {
            (Some(layout), method, shape, shadows, visibility, proxy)
        }
        _ => (Some(layout), method, shape, false, visibility, proxy),
    }
}

/// What a batch drawn by `method` with the shader of `shape` draws when the scene asks
/// for `proxy`: the pieces only where the exact method isolates roots of a polynomial
/// glyph (whose first root in a clipped interval is a surface point even where the
/// interval starts inside the glyph); elsewhere the hull's outline, which gives the
/// box's image.
pub(crate) fn drawn_proxy(proxy: Proxy, method: Method, shape: ShapeShader) -> Proxy {
    match proxy {
        Proxy::Pieces if !(method == Method::Exact && shape == ShapeShader::Polynomial) => {
            Proxy::Hull
        }
        proxy => proxy,
    }
}

/// What a batch of `layout` and `shape` is drawn with when the scene's method is
/// `method`: under the impostor, every glyph's bounding sphere; else the shape's shader
/// (the catalog's glyph shapes): the polynomial glyph's is the method's, the
/// ellipsoid's closed form serves every method, and the other shapes' are the exact
/// method's, which the other methods lack (an [`Error::Unsupported`] naming the method).
pub(crate) fn batch_variant(
    layout: TensorLayout,
    shape: GlyphShape,
    method: Method,
) -> Result<Variant> {
    let shader = ShapeShader::of(shape);
    if method == Method::Impostor {
        return Ok((layout, method, ShapeShader::Polynomial));
    }
    match (shader.entry(), shader.asked()) {
        (Some(entry), _) if entry.every_method || method == Method::Exact => {
            Ok((layout, Method::Exact, shader))
        }
        (Some(_), Some(what)) => Err(Error::Unsupported {
            what,
            by: Setting::Method.with(method),
        }),
        _ => Ok((layout, method, shader)),
    }
}

/// The per-instance vertex input of a glyph pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum InstanceInput {
    /// Binding 0: the 16-byte glyph instance (centre, sphere radius) at location 0.
    Instance,
    /// Binding 0 as above, and binding 1: the 32-byte oriented box (rotation quaternion
    /// at location 1, half extents at location 2).
    WithBoxes,
}

/// A graphics pipeline of the glyph passes: per-instance attributes of `input`, triangle
/// lists with back faces culled (counter-clockwise is front), depth test and write, and
/// the colour (and distance) targets of `formats`. The ray caster's boxes and the
/// tessellated meshes differ only in their shader stages, layouts and instance input.
pub(crate) fn glyph_pipeline(
    ctx: &DeviceContext,
    formats: TargetFormats,
    layout: vk::PipelineLayout,
    stages: &[vk::PipelineShaderStageCreateInfo],
    input: InstanceInput,
    raster: RasterTarget,
    (darken, stage): (Option<vk::CompareOp>, DrawStage),
) -> Result<Pipeline> {
    let bindings = [
        vk::VertexInputBindingDescription {
            binding: 0,
            stride: 16,
            input_rate: vk::VertexInputRate::INSTANCE,
        },
        vk::VertexInputBindingDescription {
            binding: 1,
            stride: 32,
            input_rate: vk::VertexInputRate::INSTANCE,
        },
        vk::VertexInputBindingDescription {
            binding: 2,
            stride: 48,
            input_rate: vk::VertexInputRate::INSTANCE,
        },
    ];
    let attribute =
        |location: u32, binding: u32, offset: u32| vk::VertexInputAttributeDescription {
            location,
            binding,
            format: vk::Format::R32G32B32A32_SFLOAT,
            offset,
        };
    let attributes = [
        attribute(0, 0, 0),
        attribute(1, 1, 0),
        attribute(2, 1, 16),
        attribute(3, 2, 0),
        attribute(4, 2, 16),
        attribute(5, 2, 32),
    ];
    let (bindings, attributes) = match input {
        InstanceInput::Instance => (&bindings[..1], &attributes[..1]),
        InstanceInput::WithBoxes => (&bindings[..], &attributes[..]),
    };
    let mut color_formats = vec![formats.color];
    color_formats.extend(formats.distance);
    // Front faces only: the box faces the ray enters through (the paper's choice), and
    // the outside of a closed mesh.
    let desc = GraphicsPipelineDesc {
        stages,
        vertex_bindings: bindings,
        vertex_attributes: attributes,
        cull: vk::CullModeFlags::BACK,
        color_formats: &color_formats,
        depth_format: formats.depth,
        layout,
        raster,
        darken,
        stage,
    };
    // SAFETY: the callers' stages hold live modules of build.rs's SPIR-V for `layout`.
    unsafe { graphics_pipeline(ctx, &desc) }
}

/// The whole target as viewport (depth 0 to 1) and scissor.
pub(crate) fn viewport_and_scissor(extent: vk::Extent2D) -> (vk::Viewport, vk::Rect2D) {
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    let scissor = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    };
    (viewport, scissor)
}

/// Uploads one batch of glyphs into buffers of its own.
fn upload_chunk(
    ctx: &DeviceContext,
    scene: &SceneGpu,
    set_layout: vk::DescriptorSetLayout,
    batch: &Batch,
    proxy: Proxy,
) -> Result<GlyphSetGpu> {
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    // Vertex buffers of the draw, and storage buffers of the shadow rays.
    let vertex = vk::BufferUsageFlags::VERTEX_BUFFER | storage;
    let (instance_data, box_data) = (batch.instances()?, batch.boxes()?);
    let instances = Buffer::with_data(ctx, "instances", &instance_data, vertex)?;
    let boxes = Buffer::with_data(ctx, "boxes", &box_data, vertex)?;
    let hulls = Buffer::with_data(ctx, "hulls", &batch.hulls()?, vertex)?;
    let pieces = match proxy {
        Proxy::Pieces => Buffer::with_data(ctx, "pieces", &batch.piece_words()?, storage)?,
        _ => Buffer::with_data(ctx, "no pieces", &[0u32], storage)?,
    };
    let coefficients = Buffer::with_data(ctx, "coefficients", &batch.coefficients()?, storage)?;
    let grid = ShadowGrid::new(&instance_data, &box_data);
    let grid_cells = Buffer::with_data(ctx, "shadow grid", &grid.cell_bytes(), storage)?;
    let grid_entries = Buffer::with_data(ctx, "shadow grid entries", &grid.entries, storage)?;
    let clusters = crate::render::visibility::clusters(&instance_data);
    let mut set = GlyphSetGpu {
        clusters,
        layout: batch.layout,
        negative: batch.negative,
        shape: batch.shape,
        count: batch.len() as u32,
        instances,
        boxes,
        hulls,
        pieces,
        proxy,
        _coefficients: coefficients,
        _grid: [grid_cells, grid_entries],
        descriptor_sets: Vec::new(),
    };
    set.descriptor_sets = scene
        .frames
        .iter()
        .map(|frame| frame_descriptor_set(&scene.pool, set_layout, frame, &set))
        .collect::<Result<Vec<_>>>()?;
    Ok(set)
}

/// The descriptor set of batch `set` with the frame block `frame`, from `pool`.
fn frame_descriptor_set(
    pool: &DescriptorPool,
    set_layout: vk::DescriptorSetLayout,
    frame: &Buffer,
    set: &GlyphSetGpu,
) -> Result<vk::DescriptorSet> {
    pool.buffer_set(
        set_layout,
        &[
            BufferBinding::storage(FRAME_BINDING, frame),
            BufferBinding::storage(COEFFICIENTS_BINDING, &set._coefficients),
            BufferBinding::storage(SHADOW_BINDINGS[0], &set.instances),
            BufferBinding::storage(SHADOW_BINDINGS[1], &set.boxes),
            BufferBinding::storage(SHADOW_BINDINGS[2], &set._grid[0]),
            BufferBinding::storage(SHADOW_BINDINGS[3], &set._grid[1]),
            BufferBinding::storage(PIECES_BINDING, &set.pieces),
        ],
    )
}

impl SceneGpu {
    /// Replaces the frame parameters (camera, settings) of every frame in flight; not
    /// while a frame that reads them is in flight.
    pub fn set_frame(&mut self, frame: &FrameParams) -> Result<()> {
        for buffer in &mut self.frames {
            buffer.write(bytemuck::bytes_of(frame))?;
        }
        Ok(())
    }

    /// Replaces frame `index`'s parameters: only once the host's last submission that
    /// read that frame has completed (other frames may be in flight meanwhile).
    pub fn set_frame_in_flight(&mut self, index: usize, frame: &FrameParams) -> Result<()> {
        let frames = self.frames.len();
        let buffer = self
            .frames
            .get_mut(index)
            .ok_or(Error::FrameIndex { index, frames })?;
        buffer.write(bytemuck::bytes_of(frame))
    }

    /// How many frames in flight the scene was uploaded for.
    pub fn frames_in_flight(&self) -> usize {
        self.frames.len()
    }
}
