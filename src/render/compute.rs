//! The compute ray caster (`--path compute`): a second path beside the proxy boxes of
//! [`raycast`](crate::render::raycast), for the exact method. The CPU bins each glyph's
//! oriented box into screen tiles, sorted front to back ([`tiles`](crate::render::tiles));
//! a compute shader per tensor layout (glsl/raycast_exact.comp) runs one invocation per
//! pixel that walks its tile's list with the fragment shader's root isolation
//! (glsl/exact_root.glsl) and stops behind its nearest hit.
//!
//! The outputs are two storage buffers of the image's size, colour (RGBA8 sRGB, the
//! colour target's bytes) and ray distance (negative: no hit), that [`ComputeRayCastPass::record`]
//! clears and the dispatches fill; the caller copies them out. Every part of every glyph
//! set is dispatched into the same outputs, one slice of the tile lists at a time, and
//! each dispatch starts from the distances the earlier ones stored, so the parts compose
//! as a depth test would. A glyph set is split into parts where its coefficients or
//! boxes would exceed one storage buffer (maxStorageBufferRange); lavapipe has no
//! descriptor indexing, so every part has its own descriptor set.
use crate::camera::Camera;
use crate::error::{Error, Result, Setting};
use crate::glyph::TensorLayout;
use crate::render::Method;
use crate::render::batch::{Batch, batches};
use crate::render::frame::{FRAME_DESCRIPTOR, FRAME_USAGE, FrameParams};
use crate::render::glyph_data::GlyphSetData;
use crate::render::shaders::compute_raycast_shader;
use crate::render::tiles::{ScreenView, TileBins, WALK_PER_DISPATCH, bin_glyphs};
use crate::vk::{
    Buffer, BufferBinding, DescriptorPool, DeviceContext, PipelineLayout, Pipelines,
    buffer_binding, compute_pipeline,
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
    /// Which [`WALK_PER_DISPATCH`] entries of each tile's list this dispatch walks.
    pub(crate) slice: u32,
    pub(crate) width: u32,
    pub(crate) height: u32,
}

/// Storage buffers of a part, at bindings 1 to 5 (0 is the frame's parameter buffer, 6 and
/// 7 the outputs).
const INPUT_BINDINGS: u32 = 5;
/// Every binding: frame, five inputs, two outputs.
pub(crate) const BINDINGS: u32 = 1 + INPUT_BINDINGS + 2;

/// Pipelines and layouts of the compute ray caster; created once per device.
pub struct ComputeRayCastPass {
    ctx: DeviceContext,
    // Fields drop in order: the pipelines go before the modules and the layout they were
    // made with, the order the validation layer expects.
    pipelines: Pipelines<TensorLayout>,
    layout: PipelineLayout,
    buffer_limit: Option<u64>,
}

/// One part of a glyph set on the GPU, with its tile lists.
struct ComputePartGpu {
    layout: TensorLayout,
    negative: crate::glyph::NegativeMode,
    /// Dispatches that walk its longest tile list.
    slices: u32,
    descriptor_set: vk::DescriptorSet,
    /// Coefficients, instances, boxes, tile ranges and tile entries, kept alive for the
    /// descriptor set.
    _inputs: Vec<Buffer>,
}

/// A scene uploaded for the compute ray caster at one image size and camera (the tile
/// lists depend on both).
pub struct ComputeSceneGpu {
    frame: Buffer,
    pool: DescriptorPool,
    parts: Vec<ComputePartGpu>,
    /// RGBA8 sRGB per pixel, row-major from the top-left.
    pub colors: Buffer,
    /// Ray distance per pixel (f32), negative for a miss.
    pub distances: Buffer,
    width: u32,
    height: u32,
    tiles: (u32, u32),
    /// The background as the colour target's clear would store it.
    background: u32,
    /// Tile list entries over every part, for reports.
    pub tile_entries: usize,
}

impl ComputeSceneGpu {
    /// Parts dispatched (glyph sets, split where a storage buffer could not hold one).
    pub fn parts(&self) -> usize {
        self.parts.len()
    }

    /// Dispatches per frame.
    pub fn dispatches(&self) -> usize {
        self.parts.iter().map(|p| p.slices as usize).sum()
    }
}

/// The 8-bit sRGB encoding of a linear value, as an sRGB colour target stores it.
fn srgb_byte(linear: f32) -> u32 {
    let c = linear.clamp(0.0, 1.0);
    let encoded = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (encoded * 255.0 + 0.5) as u32
}

/// A linear RGB colour with its alpha as the bytes of an R8G8B8A8_SRGB pixel, in one
/// word (alpha is stored linearly).
pub(crate) fn packed_srgb(rgba: [f32; 4]) -> u32 {
    let alpha = (rgba[3].clamp(0.0, 1.0) * 255.0 + 0.5) as u32;
    srgb_byte(rgba[0]) | srgb_byte(rgba[1]) << 8 | srgb_byte(rgba[2]) << 16 | alpha << 24
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
            pipelines: Pipelines::new(),
            buffer_limit: None,
        })
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

    /// Bins and uploads glyph sets for `camera` at `width` x `height`, with the frame
    /// parameters and the output buffers.
    #[allow(clippy::too_many_arguments)]
    pub fn upload(
        &mut self,
        ctx: &DeviceContext,
        sets: &[GlyphSetData],
        frame: &FrameParams,
        camera: &Camera,
        width: u32,
        height: u32,
        background: [f32; 4],
    ) -> Result<ComputeSceneGpu> {
        let limit = self.storage_buffer_limit();
        let view = ScreenView::new(camera, width, height);
        // Parts: batches of glyphs whose coefficients and boxes fit one storage buffer
        // each, sets that share a pipeline together.
        let parts = batches(sets, limit, |layout, _| {
            (4 * layout.coefficient_count() as u64).max(32)
        })?;
        for part in &parts {
            // Only the polynomial glyph has a compute ray caster.
            let unsupported = crate::render::ShapeShader::of(part.shape).asked();
            if let Some(what) = unsupported {
                // The data decide (exit code 1), so not a Setting error.
                return Err(Error::Unsupported {
                    what,
                    by: Setting::Path.with("compute"),
                });
            }
            self.pipeline(part.layout)?;
        }
        let device_limit = ctx.max_storage_buffer_range();
        let pixels = width as u64 * height as u64;
        if 4 * pixels > device_limit {
            return Err(Error::Limit {
                what: "bytes of the compute path's image buffer",
                value: 4 * pixels,
                limit: device_limit,
                settings: &[],
            });
        }
        let pool = DescriptorPool::new(ctx, parts.len(), 0, BINDINGS)?;
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
        let mut scene = ComputeSceneGpu {
            frame: Buffer::with_data(ctx, "frame", std::slice::from_ref(frame), FRAME_USAGE)?,
            pool,
            parts: Vec::new(),
            colors: output("compute colour")?,
            distances: output("compute distance")?,
            width,
            height,
            tiles: (view.tiles_x(), view.tiles_y()),
            background: packed_srgb(background),
            tile_entries: 0,
        };
        for part in &parts {
            let (instances, boxes) = (part.instances()?, part.boxes()?);
            let bins = bin_glyphs(&view, &instances, &boxes);
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
            let glyphs = PartGlyphs {
                batch: part,
                instances: &instances,
                boxes: &boxes,
            };
            let part = upload_part(ctx, &scene, self.layout.set_layout(), glyphs, &bins)?;
            scene.parts.push(part);
        }
        Ok(scene)
    }

    /// Records the clearing of the outputs and every dispatch, then a barrier that makes
    /// the outputs readable by transfers (the caller copies them out).
    pub fn record(&mut self, cmd: vk::CommandBuffer, scene: &ComputeSceneGpu) -> Result<()> {
        let pipelines = scene
            .parts
            .iter()
            .map(|part| self.pipeline(part.layout))
            .collect::<Result<Vec<_>>>()?;
        let d = self.ctx.device();
        let no_hit = (-1.0f32).to_bits();
        let after_fill = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::CLEAR)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .dst_access_mask(
                vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            )];
        // Each dispatch reads the distances the one before wrote.
        let between = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .dst_access_mask(
                vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            )];
        let to_transfer = [vk::MemoryBarrier2::default()
            .src_stage_mask(
                vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::CLEAR,
            )
            .src_access_mask(
                vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::TRANSFER_WRITE,
            )
            .dst_stage_mask(vk::PipelineStageFlags2::COPY)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)];
        // SAFETY: recording state is the caller's; all handles are alive.
        unsafe {
            d.cmd_fill_buffer(
                cmd,
                scene.colors.handle,
                0,
                vk::WHOLE_SIZE,
                scene.background,
            );
            d.cmd_fill_buffer(cmd, scene.distances.handle, 0, vk::WHOLE_SIZE, no_hit);
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&after_fill),
            );
        }
        let mut first = true;
        for (part, &pipeline) in scene.parts.iter().zip(&pipelines) {
            for slice in 0..part.slices {
                let params = ComputeParams {
                    hide_negative: part.negative.shader_code(),
                    slice,
                    width: scene.width,
                    height: scene.height,
                };
                // SAFETY: as above.
                unsafe {
                    if !first {
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
                    d.cmd_dispatch(cmd, scene.tiles.0, scene.tiles.1, 1);
                }
                first = false;
            }
        }
        // SAFETY: as above.
        unsafe {
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&to_transfer),
            );
        }
        Ok(())
    }
}

/// A batch of glyphs with its instances and boxes (gathered once: binning reads them too).
struct PartGlyphs<'a> {
    batch: &'a Batch<'a>,
    instances: &'a [[f32; 4]],
    boxes: &'a [[f32; 8]],
}

/// Uploads a batch of glyphs and their tile lists into buffers of their own.
fn upload_part(
    ctx: &DeviceContext,
    scene: &ComputeSceneGpu,
    set_layout: vk::DescriptorSetLayout,
    glyphs: PartGlyphs,
    bins: &TileBins,
) -> Result<ComputePartGpu> {
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let inputs = vec![
        Buffer::with_data(ctx, "coefficients", &glyphs.batch.coefficients()?, storage)?,
        Buffer::with_data(ctx, "instances", glyphs.instances, storage)?,
        Buffer::with_data(ctx, "boxes", glyphs.boxes, storage)?,
        Buffer::with_data(ctx, "tile ranges", &bins.ranges, storage)?,
        Buffer::with_data(ctx, "tile entries", &bins.entries, storage)?,
    ];
    // The frame, then the inputs and the outputs, at bindings 0, 1, 2, ... in order.
    let buffers = std::iter::once(&scene.frame)
        .chain(&inputs)
        .chain([&scene.colors, &scene.distances]);
    let bindings: Vec<BufferBinding> = buffers
        .enumerate()
        .map(|(binding, buffer)| BufferBinding::storage(binding as u32, buffer))
        .collect();
    let descriptor_set = scene.pool.buffer_set(set_layout, &bindings)?;
    Ok(ComputePartGpu {
        layout: glyphs.batch.layout,
        negative: glyphs.batch.negative,
        slices: bins.slices,
        descriptor_set,
        _inputs: inputs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_bytes_of_the_ends_and_the_middle() {
        assert_eq!(packed_srgb([0.0, 1.0, 0.5, 1.0]), 0xff_bc_ff_00);
        assert_eq!(srgb_byte(0.002), 7); // the linear segment: 12.92 * 0.002 * 255 = 6.6
    }
}
