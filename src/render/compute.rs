//! The compute ray caster (`--path compute`): a second path beside the proxy boxes of
//! [`raycast`](crate::render::raycast), for the exact method. The CPU bins each glyph's
//! oriented box into screen tiles, sorted front to back ([`tiles`](crate::render::tiles));
//! a compute shader per tensor layout (glsl/raycast_exact.comp) runs one invocation per
//! pixel that walks its tile's list with the fragment shader's root isolation
//! (glsl/exact_root.glsl) and stops behind its nearest hit.
//!
//! The outputs are three storage buffers of the image's size, colour (RGBA8 sRGB, the
//! colour target's bytes), ray distance (negative: no hit) and window depth, that
//! [`ComputeRayCastPass::record`] clears and the dispatches fill, outside any rendering.
//! Inside the frame's rendering, [`ComputeRayCastPass::record_compose`] then draws them
//! into the attachments with one full-viewport triangle (glsl/compose.frag): colour,
//! distance and depth as the fragment path's glyph shader writes them, depth-tested, so
//! that an underlay, peaks, shadows or a host's own geometry compose with the glyphs
//! exactly as they do on the fragment path. Every part of every glyph
//! set is dispatched into the same outputs, one slice of the tile lists at a time, and
//! each dispatch starts from the distances the earlier ones stored, so the parts compose
//! as a depth test would. A glyph set is split into parts where its coefficients or
//! boxes would exceed one storage buffer (maxStorageBufferRange); lavapipe has no
//! descriptor indexing, so every part has its own descriptor set.
use crate::camera::Camera;
use crate::error::{Error, Result, Setting};
use crate::glyph::TensorLayout;
use crate::render::Method;
use crate::render::batch::batches;
use crate::render::frame::{FRAME_DESCRIPTOR, FRAME_USAGE, FrameParams};
use crate::render::glyph_data::GlyphSetData;
use crate::render::raycast::TargetFormats;
use crate::render::shaders::{
    COMPOSE_COLOR_ONLY_FRAGMENT, COMPOSE_FRAGMENT, COMPOSE_VERTEX, compute_raycast_shader,
};
use crate::render::tiles::{ScreenView, TileBins, WALK_PER_DISPATCH, bin_glyphs};
use crate::vk::recording::{Access, TRANSFER_WRITES, memory_barrier};
use crate::vk::{
    Buffer, BufferBinding, DescriptorPool, DeviceContext, GraphicsPipelineDesc, Pipeline,
    PipelineLayout, Pipelines, RasterTarget, ShaderModule, buffer_binding, compute_pipeline,
    graphics_pipeline, vertex_fragment_stages,
};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use gpu_allocator::MemoryLocation;

/// Push constants of glsl/raycast_exact.comp (`GlyphSetParams` of glsl/frame.glsl with
/// GLYPHCAST_COMPUTE defined).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct ComputeParams {
    pub(crate) hide_negative: u32,
    /// Which of the part's dispatches this is (each goes on where the one before left
    /// every pixel's walk, at most [`WALK_PER_DISPATCH`] root isolations further).
    pub(crate) slice: u32,
    pub(crate) width: u32,
    pub(crate) height: u32,
}

/// Storage buffers of a part, at bindings 1 to 5 (0 is the frame's parameter buffer, 6 to
/// 8 the outputs).
const INPUT_BINDINGS: u32 = 5;
/// The outputs: colour, distance, depth (bindings 6 to 8 of the ray caster, 0 to 2 of
/// the composing draw).
pub(crate) const OUTPUT_BINDINGS: u32 = 3;
/// The walk's state, at bindings 9 and 10: per pixel the entries walked, per dispatch the
/// next one's group counts.
const WALK_BINDINGS: u32 = 2;
/// Every binding: frame, five inputs, three outputs, the walk's state.
pub(crate) const BINDINGS: u32 = 1 + INPUT_BINDINGS + OUTPUT_BINDINGS + WALK_BINDINGS;

/// Push constants of glsl/compose.frag: where the image lies in the attachments.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct ComposeRegion {
    /// The image's top-left pixel in the attachments.
    pub(crate) origin: [u32; 2],
    /// The image's width: its rows' length in the outputs.
    pub(crate) row_length: u32,
    pub(crate) pad: u32,
}

/// What a composing pipeline was made for: the attachments' formats and the target's
/// samples, depth test and cache.
type ComposeTarget = (TargetFormats, RasterTarget);

/// Pipelines and layouts of the compute ray caster; created once per device.
pub struct ComputeRayCastPass {
    ctx: DeviceContext,
    // Fields drop in order: the pipelines go before the modules and the layout they were
    // made with, the order the validation layer expects.
    pipelines: Pipelines<TensorLayout>,
    /// The composing draw's pipeline, for the target it was last asked for.
    compose: Option<(ComposeTarget, Pipeline)>,
    layout: PipelineLayout,
    compose_layout: PipelineLayout,
    buffer_limit: Option<u64>,
}

/// One part of a glyph set on the GPU, with its tile lists.
struct ComputePartGpu {
    layout: TensorLayout,
    negative: crate::glyph::NegativeMode,
    /// Dispatches that walk its longest tile list in the worst case (every entry needing
    /// a root isolation); those after the first are indirect, and launch nothing once
    /// every pixel's walk is over.
    slices: u32,
    descriptor_set: vk::DescriptorSet,
    /// Per dispatch, the group counts the dispatch before wrote (glsl/raycast_exact.comp
    /// `NextDispatch`).
    next_dispatch: Buffer,
    /// Tile ranges and tile entries, kept alive for the descriptor set (which holds the
    /// glyphs' buffers too: [`ComputeGlyphsGpu`] outlives the view).
    _tiles: [Buffer; 2],
}

/// Glyph sets uploaded once for the compute ray caster: per part (a batch of glyphs whose
/// coefficients and boxes fit one storage buffer), its coefficients, instances and boxes
/// on the GPU, and the instances and boxes on the host for binning each view.
pub struct ComputeGlyphsGpu {
    parts: Vec<ComputePartInputs>,
    /// The set layouts of the pass that uploaded them (a part's, the composing draw's),
    /// which outlives them.
    set_layouts: (vk::DescriptorSetLayout, vk::DescriptorSetLayout),
}

/// One part's glyphs.
struct ComputePartInputs {
    layout: TensorLayout,
    negative: crate::glyph::NegativeMode,
    instances: Vec<[f32; 4]>,
    boxes: Vec<[f32; 8]>,
    /// Coefficients, instances, boxes.
    buffers: [Buffer; 3],
}

/// The composing draw's pipeline and layout, as [`ComputeRayCastPass::compose_pipeline`]
/// makes them for one target.
#[derive(Clone, Copy, Debug)]
pub struct ComposePipeline {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
}

/// A view of [`ComputeGlyphsGpu`] for the compute ray caster at one image size and
/// camera (the tile lists depend on both): the tile lists, the frame block and the
/// outputs. The glyphs it was made from must outlive it.
pub struct ComputeSceneGpu {
    frame: Buffer,
    pool: DescriptorPool,
    parts: Vec<ComputePartGpu>,
    /// RGBA8 sRGB per pixel, row-major from the top-left.
    pub colors: Buffer,
    /// Ray distance per pixel (f32), negative for a miss.
    pub distances: Buffer,
    /// Window depth per pixel (f32) where there is a hit.
    pub depths: Buffer,
    /// Per pixel, the entries of the current part's tile list its walk has passed.
    walked: Buffer,
    /// The outputs for the composing draw (glsl/compose.frag).
    compose_set: vk::DescriptorSet,
    width: u32,
    height: u32,
    tiles: (u32, u32),
    /// Tile list entries over every part, for reports.
    pub tile_entries: usize,
}

impl ComputeSceneGpu {
    /// Parts dispatched (glyph sets, split where a storage buffer could not hold one).
    pub fn parts(&self) -> usize {
        self.parts.len()
    }

    /// Dispatches recorded per frame (those after each part's first launch workgroups
    /// only while some pixel's walk goes on).
    pub fn dispatches(&self) -> usize {
        self.parts.iter().map(|p| p.slices as usize).sum()
    }
}

impl ComputeRayCastPass {
    /// The descriptor-set and pipeline layouts; pipelines are created when first needed.
    pub fn new(ctx: &DeviceContext) -> Result<ComputeRayCastPass> {
        let bindings: Vec<_> = (0..BINDINGS)
            .map(|binding| {
                // The frame at 0 (FRAME_DESCRIPTOR: a storage buffer too), then storage.
                buffer_binding(binding, FRAME_DESCRIPTOR, vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let push = std::mem::size_of::<ComputeParams>() as u32;
        Ok(ComputeRayCastPass {
            ctx: ctx.clone(),
            layout: PipelineLayout::new(ctx, &bindings, vk::ShaderStageFlags::COMPUTE, push)?,
            compose_layout: compose_layout(ctx)?,
            pipelines: Pipelines::new(),
            compose: None,
            buffer_limit: None,
        })
    }

    /// The composing draw's pipeline for attachments of `formats` drawn as `raster`
    /// says (samples, depth test, cache): made on first use, and again when the target
    /// changes (the previous one must not be in use any more).
    pub fn compose_pipeline(
        &mut self,
        formats: TargetFormats,
        raster: RasterTarget,
    ) -> Result<ComposePipeline> {
        let target = (formats, raster);
        let pipeline = match &self.compose {
            Some((made_for, pipeline)) if *made_for == target => pipeline.handle(),
            _ => {
                let pipeline = create_compose_pipeline(&self.ctx, target, &self.compose_layout)?;
                let handle = pipeline.handle();
                self.compose = Some((target, pipeline));
                handle
            }
        };
        Ok(ComposePipeline {
            pipeline,
            layout: self.compose_layout.handle(),
        })
    }

    /// Records the draw of `scene`'s outputs into the attachments of the rendering that
    /// `cmd` is inside (formats and samples as `pipeline` was made for), at `origin` (the
    /// image's top-left pixel in the attachments): colour, ray distance (where the
    /// target has a distance attachment) and depth of every pixel the glyphs cover,
    /// depth-tested against what the rendering holds. [`ComputeRayCastPass::record`]
    /// must have been recorded before the rendering began.
    pub fn record_compose(
        &self,
        cmd: vk::CommandBuffer,
        scene: &ComputeSceneGpu,
        pipeline: ComposePipeline,
        origin: [u32; 2],
    ) {
        let viewport = vk::Viewport {
            x: origin[0] as f32,
            y: origin[1] as f32,
            width: scene.width as f32,
            height: scene.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let scissor = vk::Rect2D {
            offset: vk::Offset2D {
                x: origin[0] as i32,
                y: origin[1] as i32,
            },
            extent: vk::Extent2D {
                width: scene.width,
                height: scene.height,
            },
        };
        let region = ComposeRegion {
            origin,
            row_length: scene.width,
            pad: 0,
        };
        let d = self.ctx.device();
        // SAFETY: recording state is the caller's; every handle is alive; the set holds
        // the scene's outputs, which `record` made readable by fragment shaders.
        unsafe {
            let bound = (pipeline.pipeline, pipeline.layout);
            crate::vk::recording::bind_graphics(
                d,
                cmd,
                bound,
                scene.compose_set,
                (viewport, scissor),
            );
            d.cmd_push_constants(
                cmd,
                pipeline.layout,
                vk::ShaderStageFlags::FRAGMENT,
                0,
                bytemuck::bytes_of(&region),
            );
            d.cmd_draw(cmd, 3, 1, 0, 0);
        }
    }

    /// Caps the bytes of coefficients and boxes per part below the device's
    /// maxStorageBufferRange (tests use it to force the split into parts); `None` lifts
    /// the cap. The outputs and tile lists are held against the device's limit.
    pub fn set_storage_buffer_limit(&mut self, bytes: Option<u64>) {
        self.buffer_limit = bytes;
    }

    fn storage_buffer_limit(&self) -> u64 {
        let device = self.ctx.max_storage_buffer_range();
        self.buffer_limit.map_or(device, |cap| cap.min(device))
    }

    /// The compute pipeline of a tensor layout, created on first use.
    pub fn pipeline(&mut self, layout: TensorLayout) -> Result<vk::Pipeline> {
        if let Some(p) = self.pipelines.get(&layout) {
            return Ok(p);
        }
        if !self.ctx.compute_votes() {
            return Err(Error::setup(
                "subgroup vote and ballot operations in compute shaders (the compute walk)",
                "this device has none; the fragment path (--path fragment) draws without them",
            ));
        }
        let shader =
            compute_raycast_shader(layout, Method::Exact).ok_or_else(|| Error::Unsupported {
                what: crate::error::Asked::Layout(layout.into()),
                by: Setting::Path.with("compute"),
            })?;
        let entries = [vk::SpecializationMapEntry {
            constant_id: 0,
            offset: 0,
            size: 4,
        }];
        let walk = WALK_PER_DISPATCH.to_ne_bytes();
        let specialization = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(&walk);
        // SAFETY: the SPIR-V comes from build.rs and was validated by glslang; it declares
        // the bindings and push constants of this layout.
        let pipeline = unsafe {
            compute_pipeline(
                &self.ctx,
                self.layout.handle(),
                shader.spirv,
                Some(&specialization),
            )?
        };
        Ok(self.pipelines.insert(layout, pipeline))
    }

    /// Uploads glyph sets for the compute ray caster (and makes the pipelines they need):
    /// once, for every view drawn of them (each binned again for its camera).
    pub fn upload_glyphs(
        &mut self,
        ctx: &DeviceContext,
        sets: &[GlyphSetData],
    ) -> Result<ComputeGlyphsGpu> {
        let limit = self.storage_buffer_limit();
        // Parts: batches of glyphs whose coefficients and boxes fit one storage buffer
        // each, sets that share a pipeline together.
        let batches = batches(sets, limit, |layout, _| {
            (4 * layout.coefficient_count() as u64).max(32)
        })?;
        let mut parts = Vec::with_capacity(batches.len());
        for batch in &batches {
            // Only the polynomial glyph has a compute ray caster: `compute` is refused
            // for the others as a setting (exit code 2), as for another method.
            if batch.shape != crate::glyph::GlyphShape::Polynomial {
                return Err(crate::render::settings::compute_refuses_shape(batch.shape));
            }
            self.pipeline(batch.layout)?;
            let (instances, boxes) = (batch.instances()?.into_owned(), batch.boxes()?.into_owned());
            let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
            let buffers = [
                Buffer::with_data(ctx, "coefficients", &batch.coefficients()?, storage)?,
                Buffer::with_data(ctx, "instances", &instances, storage)?,
                Buffer::with_data(ctx, "boxes", &boxes, storage)?,
            ];
            parts.push(ComputePartInputs {
                layout: batch.layout,
                negative: batch.negative,
                instances,
                boxes,
                buffers,
            });
        }
        Ok(ComputeGlyphsGpu {
            parts,
            set_layouts: (self.layout.set_layout(), self.compose_layout.set_layout()),
        })
    }

    /// Uploads glyph sets and bins them for `camera` at `width` x `height`, with the
    /// frame parameters and the output buffers: [`ComputeRayCastPass::upload_glyphs`],
    /// then the tile lists of that view.
    pub fn upload(
        &mut self,
        ctx: &DeviceContext,
        sets: &[GlyphSetData],
        frame: &FrameParams,
        camera: &Camera,
        (width, height): (u32, u32),
    ) -> Result<(ComputeGlyphsGpu, ComputeSceneGpu)> {
        let glyphs = self.upload_glyphs(ctx, sets)?;
        let view = ScreenView::new(camera, width, height);
        let scene = glyphs.view(ctx, frame, view)?;
        Ok((glyphs, scene))
    }

    /// Records, outside any rendering, the clearing of the distances and every dispatch,
    /// then a barrier that makes the outputs readable by the composing draw
    /// ([`ComputeRayCastPass::record_compose`]) and by transfers.
    pub fn record(&self, cmd: vk::CommandBuffer, scene: &ComputeSceneGpu) -> Result<()> {
        // Made when the glyphs were uploaded (upload_glyphs).
        let pipelines = scene
            .parts
            .iter()
            .map(|part| {
                self.pipelines.get(&part.layout).ok_or(Error::Call {
                    call: "ComputeRayCastPass::record",
                    expected: "glyphs uploaded by this pass",
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let d = self.ctx.device();
        let no_hit = (-1.0f32).to_bits();
        // Who touches the outputs and the walk's state: the composing draw and the copies
        // read the outputs; the dispatches read and write them and launch with the group
        // counts; the clears write them.
        let readers: Access = (
            vk::PipelineStageFlags2::FRAGMENT_SHADER | vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::TRANSFER_READ,
        );
        let dispatches: Access = (
            vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::DRAW_INDIRECT,
            vk::AccessFlags2::SHADER_STORAGE_READ
                | vk::AccessFlags2::SHADER_STORAGE_WRITE
                | vk::AccessFlags2::INDIRECT_COMMAND_READ,
        );
        let clears = (
            TRANSFER_WRITES.0 | vk::PipelineStageFlags2::COMPUTE_SHADER,
            TRANSFER_WRITES.1 | vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        let written = (
            vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::ALL_TRANSFER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::TRANSFER_WRITE,
        );
        // The last frame's composing draw and copies read the outputs before they are
        // cleared and written again, and its dispatches the walk's state (a part's
        // dispatches too before the next part's clear it).
        let before_fill = [memory_barrier(
            (readers.0 | dispatches.0, readers.1 | dispatches.1),
            clears,
        )];
        // The dispatches read what the clears wrote, the indirect ones their group counts.
        let after_fill = [memory_barrier(TRANSFER_WRITES, dispatches)];
        // Each dispatch reads the distances and the walk's state the one before wrote, and
        // is launched with the group counts it wrote.
        let between = [memory_barrier(
            (
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_WRITE,
            ),
            dispatches,
        )];
        let to_readers = [memory_barrier(written, readers)];
        // SAFETY: recording state is the caller's; all handles are alive.
        unsafe {
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&before_fill),
            );
            // A pixel's colour and depth are read only where its distance says it has a
            // hit, so only the distances are cleared.
            d.cmd_fill_buffer(cmd, scene.distances.handle, 0, vk::WHOLE_SIZE, no_hit);
        }
        for (k, (part, &pipeline)) in scene.parts.iter().zip(&pipelines).enumerate() {
            // SAFETY: as above.
            unsafe {
                if k > 0 {
                    d.cmd_pipeline_barrier2(
                        cmd,
                        &vk::DependencyInfo::default().memory_barriers(&before_fill),
                    );
                }
                // No dispatch after the first until one leaves a walk unfinished (the
                // first starts every walk from the start of its list).
                d.cmd_fill_buffer(cmd, part.next_dispatch.handle, 0, vk::WHOLE_SIZE, 0);
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default().memory_barriers(&after_fill),
                );
            }
            for slice in 0..part.slices {
                let params = ComputeParams {
                    hide_negative: part.negative.shader_code(),
                    slice,
                    width: scene.width,
                    height: scene.height,
                };
                // SAFETY: as above.
                unsafe {
                    if slice > 0 {
                        d.cmd_pipeline_barrier2(
                            cmd,
                            &vk::DependencyInfo::default().memory_barriers(&between),
                        );
                    }
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
                    d.cmd_bind_descriptor_sets(
                        cmd,
                        vk::PipelineBindPoint::COMPUTE,
                        self.layout.handle(),
                        0,
                        &[part.descriptor_set],
                        &[],
                    );
                    d.cmd_push_constants(
                        cmd,
                        self.layout.handle(),
                        vk::ShaderStageFlags::COMPUTE,
                        0,
                        bytemuck::bytes_of(&params),
                    );
                    if slice == 0 {
                        d.cmd_dispatch(cmd, scene.tiles.0, scene.tiles.1, 1);
                    } else {
                        let offset = 12 * u64::from(slice);
                        d.cmd_dispatch_indirect(cmd, part.next_dispatch.handle, offset);
                    }
                }
            }
        }
        // SAFETY: as above.
        unsafe {
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&to_readers),
            );
        }
        Ok(())
    }
}

impl ComputeGlyphsGpu {
    /// Bins the glyphs into the tiles of `view` and uploads the tile lists with the frame
    /// block `frame` and the output buffers.
    pub(crate) fn view(
        &self,
        ctx: &DeviceContext,
        frame: &FrameParams,
        view: ScreenView,
    ) -> Result<ComputeSceneGpu> {
        let (width, height) = view.size();
        let device_limit = ctx.max_storage_buffer_range();
        let pixels = width as u64 * height as u64;
        if 4 * pixels > device_limit {
            // The request sets the size, so the way out is a smaller one or the fragment
            // path (a refused setting, exit code 2).
            return Err(Error::setting_value(
                Setting::Path,
                "compute",
                crate::message![
                    format!(
                        "its image buffer of {} bytes ({width} x {height} pixels, samples \
                         included) is over this device's storage buffer limit of \
                         {device_limit} bytes; ask for fewer samples (",
                        4 * pixels
                    ),
                    Setting::Samples,
                    ") or a smaller image (",
                    Setting::Width,
                    "/",
                    Setting::Height,
                    "), or use ",
                    Setting::Path.with("fragment")
                ],
            ));
        }
        // A set per part, and the composing draw's.
        let pool = DescriptorPool::new(ctx, self.parts.len() + 1, 0, BINDINGS)?;
        let output = |name: &str| {
            Buffer::new(
                ctx,
                name,
                4 * pixels,
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )
        };
        let (colors, distances, depths, walked) = (
            output("compute colour")?,
            output("compute distance")?,
            output("compute depth")?,
            output("compute walk")?,
        );
        let compose_set = pool.buffer_set(
            self.set_layouts.1,
            &[
                BufferBinding::storage(0, &colors),
                BufferBinding::storage(1, &distances),
                BufferBinding::storage(2, &depths),
            ],
        )?;
        let mut scene = ComputeSceneGpu {
            frame: Buffer::with_data(ctx, "frame", std::slice::from_ref(frame), FRAME_USAGE)?,
            pool,
            parts: Vec::new(),
            colors,
            distances,
            depths,
            walked,
            compose_set,
            width,
            height,
            tiles: (view.tiles_x(), view.tiles_y()),
            tile_entries: 0,
        };
        for part in &self.parts {
            let bins = bin_glyphs(&view, &part.instances, &part.boxes);
            let entry_bytes = 8 * bins.entries.len() as u64;
            if entry_bytes > device_limit {
                return Err(Error::Limit {
                    what: "bytes of the compute path's tile lists",
                    value: entry_bytes,
                    limit: device_limit,
                    settings: &[],
                });
            }
            scene.tile_entries += bins.entries.len();
            let part = upload_part(ctx, &scene, self.set_layouts.0, part, &bins)?;
            scene.parts.push(part);
        }
        Ok(scene)
    }
}

/// Uploads the tile lists of one part and makes its descriptor set.
fn upload_part(
    ctx: &DeviceContext,
    scene: &ComputeSceneGpu,
    set_layout: vk::DescriptorSetLayout,
    part: &ComputePartInputs,
    bins: &TileBins,
) -> Result<ComputePartGpu> {
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let tiles = [
        Buffer::with_data(ctx, "tile ranges", &bins.ranges, storage)?,
        Buffer::with_data(ctx, "tile entries", &bins.entries, storage)?,
    ];
    let next_dispatch = Buffer::new(
        ctx,
        "compute next dispatch",
        12 * u64::from(bins.slices.max(1)),
        storage | vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )?;
    // The frame, then the inputs, the outputs and the walk's state, at bindings 0, 1,
    // 2, ... in order.
    let buffers = std::iter::once(&scene.frame)
        .chain(&part.buffers)
        .chain(&tiles)
        .chain([&scene.colors, &scene.distances, &scene.depths])
        .chain([&scene.walked, &next_dispatch]);
    let bindings: Vec<BufferBinding> = buffers
        .enumerate()
        .map(|(binding, buffer)| BufferBinding::storage(binding as u32, buffer))
        .collect();
    let descriptor_set = scene.pool.buffer_set(set_layout, &bindings)?;
    Ok(ComputePartGpu {
        layout: part.layout,
        negative: part.negative,
        slices: bins.slices,
        descriptor_set,
        next_dispatch,
        _tiles: tiles,
    })
}

/// The composing draw's layout: the three outputs at bindings 0 to 2 and the region's
/// push constants, for the fragment stage.
fn compose_layout(ctx: &DeviceContext) -> Result<PipelineLayout> {
    let bindings: Vec<_> = (0..OUTPUT_BINDINGS)
        .map(|binding| {
            buffer_binding(
                binding,
                vk::DescriptorType::STORAGE_BUFFER,
                vk::ShaderStageFlags::FRAGMENT,
            )
        })
        .collect();
    let push = std::mem::size_of::<ComposeRegion>() as u32;
    PipelineLayout::new(ctx, &bindings, vk::ShaderStageFlags::FRAGMENT, push)
}

/// The composing draw's pipeline: one triangle over the viewport, no face culled, depth
/// tested and written as the target's glyphs are, every colour attachment written whole.
fn create_compose_pipeline(
    ctx: &DeviceContext,
    (formats, raster): ComposeTarget,
    layout: &PipelineLayout,
) -> Result<Pipeline> {
    // SAFETY: the SPIR-V comes from build.rs and was validated by glslang.
    let vertex = unsafe { ShaderModule::new(ctx, COMPOSE_VERTEX)? };
    let fragment_spirv = match formats.distance {
        Some(_) => COMPOSE_FRAGMENT,
        None => COMPOSE_COLOR_ONLY_FRAGMENT,
    };
    // SAFETY: as above.
    let fragment = unsafe { ShaderModule::fragment(ctx, fragment_spirv)? };
    let stages = vertex_fragment_stages(vertex.handle(), fragment.handle(), None);
    let mut color_formats = vec![formats.color];
    color_formats.extend(formats.distance);
    let desc = GraphicsPipelineDesc {
        stages: &stages,
        vertex_bindings: &[],
        vertex_attributes: &[],
        cull: vk::CullModeFlags::NONE,
        color_formats: &color_formats,
        depth_format: formats.depth,
        layout: layout.handle(),
        raster,
        darken: None,
        stage: crate::vk::DrawStage::Normal,
    };
    // SAFETY: the modules are alive until the call returns; their SPIR-V declares the
    // blocks of `layout` (render::interface checks it).
    unsafe { graphics_pipeline(ctx, &desc) }
}
