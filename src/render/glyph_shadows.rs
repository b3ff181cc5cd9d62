//! The glyphs' shadows and ambient occlusion cast after the frame (`--shadows`,
//! `--ambient-occlusion`), where the frame has a distance attachment (the headless
//! renderer's). The frame is drawn by the exact method's shaders without shadows; then
//! its distance attachment (each pixel's ray distance to the hit it shows) is copied into
//! a storage buffer, and each exact batch's boxes are drawn again with the glyph receiver
//! fragment shader (raycast_exact.frag compiled with `GLYPHCAST_GLYPH_RECEIVER`). A
//! fragment whose glyph owns its pixel's hit (the point just beyond the hit is inside
//! the glyph, or the hit lies on its surface) casts the hit's rays through the batch's
//! shadow grid and writes the hit's colour lit by the share of the light that reaches
//! it; the draws blend by MIN and are depth tested against the frame's depth (a box
//! wholly behind the pixel's hit cannot own it), without writing it.
//!
//! Casting the rays in the frame's own shader would cast them from every hit a fragment
//! finds, hidden ones too, and would make that shader carry the rays' state through the
//! camera ray's root isolation: on an NVIDIA H200 that shader took 1.46 times the frame
//! without shadows when no ray was cast at all. Here only the visible hits cast rays,
//! once each, and the frame's shaders and depth map are those of a frame without
//! shadows. Targets without a distance attachment (the viewer's window, an engine's)
//! cast the rays in the frame's shader (`RaycastShader::shadows_color_only_fragment`).
use std::collections::HashMap;

use crate::error::{Asked, Error, Result, Setting};
use crate::glyph::{GlyphShape, TensorLayout};
use crate::render::component::UploadedGlyphs;
use crate::render::raycast::{
    CUBE_INDICES, GlyphSetGpu, InstanceInput, SceneGpu, TargetFormats, batch_bindings,
    glyph_pipeline, viewport_and_scissor,
};
use crate::render::shaders::raycast_shader;
use crate::render::{Method, ShapeShader};
use crate::vk::recording::bind_graphics;
use crate::vk::{
    Buffer, BufferBinding, DescriptorPool, DeviceContext, Pipeline, PipelineLayout, RasterTarget,
    ShaderModule, buffer_binding, vertex_fragment_stages,
};
use ash::vk;
use gpu_allocator::MemoryLocation;

/// Binding of the hits buffer in the receiver's set 1 (raycast_exact.frag).
const HITS_BINDING: u32 = 0;

/// Bytes before the hits buffer's distances: a uvec4 whose x is the row length.
pub(crate) const HITS_HEADER: u64 = 16;

/// The receiver's pipelines, one per tensor layout, for a rendering of a colour and a
/// depth attachment.
pub(crate) struct GlyphShadowPass {
    ctx: DeviceContext,
    formats: TargetFormats,
    pipelines: HashMap<TensorLayout, Pipeline>,
    /// Set 0: a glyph batch's bindings; set 1: the hits buffer.
    layout: PipelineLayout,
    indices: Buffer,
}

/// A frame's hits: the ray distance of each pixel's hit (-1 where none), in bands of
/// whole rows, each in a buffer of its own within the storage-buffer range.
pub(crate) struct HitsBuffer {
    pub(crate) bands: Vec<HitsBand>,
    _pool: DescriptorPool,
}

/// Rows `first..first + rows` of a frame's hits: a 16-byte header (the row length, the
/// first row, the rows), then the distances row after row; and the receiver's set 1
/// pointing at them.
pub(crate) struct HitsBand {
    pub(crate) first: u32,
    pub(crate) rows: u32,
    pub(crate) buffer: Buffer,
    set: vk::DescriptorSet,
}

impl GlyphShadowPass {
    /// The layout for attachments of `formats` (colour and depth; no distance), whose
    /// depth is reversed as the headless renderer's is.
    pub(crate) fn new(ctx: &DeviceContext, formats: TargetFormats) -> Result<Self> {
        if formats.distance.is_some() {
            return Err(Error::Call {
                call: "GlyphShadowPass::new",
                expected: "formats without a distance attachment",
            });
        }
        let hits = [buffer_binding(
            HITS_BINDING,
            vk::DescriptorType::STORAGE_BUFFER,
            vk::ShaderStageFlags::FRAGMENT,
        )];
        // The fragment shader's push constant: the batch's negative mode (one u32).
        let layout = PipelineLayout::with_sets(
            ctx,
            &[&batch_bindings(), &hits],
            vk::ShaderStageFlags::FRAGMENT,
            4,
        )?;
        Ok(GlyphShadowPass {
            ctx: ctx.clone(),
            formats,
            pipelines: HashMap::new(),
            layout,
            indices: Buffer::with_data(
                ctx,
                "box indices",
                &CUBE_INDICES,
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
        })
    }

    /// Makes the pipelines of the batches of `glyphs` that cast rays.
    pub(crate) fn prepare(&mut self, glyphs: &UploadedGlyphs) -> Result<()> {
        for set in casting_batches(&glyphs.gpu) {
            if self.pipelines.contains_key(&set.layout) {
                continue;
            }
            let shader = raycast_shader(set.layout, Method::Exact, ShapeShader::Polynomial);
            let (vertex, fragment) = shader
                .and_then(|s| Some((s.vertex, s.glyph_receiver_fragment?)))
                .ok_or_else(|| Error::Unsupported {
                    what: Asked::Layout(set.layout.into()),
                    by: Setting::Shadows.with("hard"),
                })?;
            // SAFETY: the SPIR-V comes from build.rs and was validated by glslang; the
            // modules may go once the pipeline exists.
            let vertex = unsafe { ShaderModule::new(&self.ctx, vertex)? };
            // SAFETY: as above.
            let fragment = unsafe { ShaderModule::fragment(&self.ctx, fragment)? };
            // raycast.vert's ORIENTED_BOX keeps its default (the oriented boxes).
            let stages = vertex_fragment_stages(vertex.handle(), fragment.handle(), None);
            // Reversed depth: a box in front of the pixel's hit, or at it, may own it.
            let pipeline = glyph_pipeline(
                &self.ctx,
                self.formats,
                self.layout.handle(),
                &stages,
                InstanceInput::WithBoxes,
                RasterTarget::default(),
                (
                    Some(vk::CompareOp::GREATER_OR_EQUAL),
                    crate::vk::DrawStage::Normal,
                ),
            )?;
            self.pipelines.insert(set.layout, pipeline);
        }
        Ok(())
    }

    /// The hits of frames of `extent`, in bands of at most `limit` bytes each (the
    /// storage-buffer range, or the ray-cast pass's cap on it); their headers and
    /// distances are written by the headless renderer's copy after each frame.
    pub(crate) fn hits(&self, extent: vk::Extent2D, limit: u64) -> Result<HitsBuffer> {
        let row = 4 * u64::from(extent.width);
        let band_rows = (limit.saturating_sub(HITS_HEADER) / row.max(1)).max(1);
        let band_rows = u32::try_from(band_rows).unwrap_or(u32::MAX);
        let count = extent.height.div_ceil(band_rows).max(1);
        let pool = DescriptorPool::new(&self.ctx, count as usize, 0, 1)?;
        let set_layout = self.layout.set_layout_at(1).ok_or(Error::Call {
            call: "GlyphShadowPass::hits",
            expected: "a pipeline layout of two sets",
        })?;
        let mut bands = Vec::with_capacity(count as usize);
        for k in 0..count {
            let first = k * band_rows;
            let rows = band_rows.min(extent.height - first);
            let buffer = Buffer::new(
                &self.ctx,
                "hits",
                HITS_HEADER + row * u64::from(rows),
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuOnly,
            )?;
            let binding = [BufferBinding::storage(HITS_BINDING, &buffer)];
            let set = pool.buffer_set(set_layout, &binding)?;
            bands.push(HitsBand {
                first,
                rows,
                buffer,
                set,
            });
        }
        Ok(HitsBuffer { bands, _pool: pool })
    }

    /// Records, for each band of `hits` and each batch of `glyphs` that casts rays, the
    /// batch's boxes drawn again over the band's rows to cast the rays of the hits they
    /// own (with frame block `frame_index`). The caller has drawn the frame, copied its
    /// distances into `hits` and begun a rendering of this pass's formats over the
    /// frame's colour and depth, of size `extent`.
    pub(crate) fn record(
        &self,
        cmd: vk::CommandBuffer,
        (glyphs, frame_index): (&UploadedGlyphs, usize),
        hits: &HitsBuffer,
        extent: vk::Extent2D,
    ) -> Result<()> {
        let (viewport, whole) = viewport_and_scissor(extent);
        for band in &hits.bands {
            let mut scissor = whole;
            scissor.offset.y = band.first as i32;
            scissor.extent.height = band.rows;
            self.record_band(cmd, (glyphs, frame_index), band, (viewport, scissor))?;
        }
        Ok(())
    }

    /// [`GlyphShadowPass::record`] of one band, its rows the scissor.
    fn record_band(
        &self,
        cmd: vk::CommandBuffer,
        (glyphs, frame_index): (&UploadedGlyphs, usize),
        band: &HitsBand,
        (viewport, scissor): (vk::Viewport, vk::Rect2D),
    ) -> Result<()> {
        let d = self.ctx.device();
        for set in casting_batches(&glyphs.gpu) {
            let pipeline = self.pipelines.get(&set.layout).ok_or(Error::Call {
                call: "GlyphShadowPass::record",
                expected: "GlyphShadowPass::prepare for these glyphs first",
            })?;
            let batch = set.descriptor_set(frame_index)?;
            let layout = self.layout.handle();
            // SAFETY: recording state is the caller's; every handle is alive until the
            // submission completes.
            unsafe {
                bind_graphics(
                    d,
                    cmd,
                    (pipeline.handle(), layout),
                    batch,
                    (viewport, scissor),
                );
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    layout,
                    1,
                    &[band.set],
                    &[],
                );
                d.cmd_push_constants(
                    cmd,
                    layout,
                    vk::ShaderStageFlags::FRAGMENT,
                    0,
                    &set.negative.shader_code().to_ne_bytes(),
                );
                // The boxes: this pass's pipelines keep raycast.vert's OUTLINE off.
                set.record_boxes(d, cmd, self.indices.handle, crate::render::Proxy::Box);
            }
        }
        Ok(())
    }
}

/// The batches of `scene` whose shadows this pass casts: the exact method's polynomial
/// glyphs of a scene uploaded to leave its shadows to a later pass.
pub(crate) fn casting_batches(scene: &SceneGpu) -> impl Iterator<Item = &GlyphSetGpu> {
    scene
        .sets
        .iter()
        .filter(move |set| scene.deferred && set.shape == GlyphShape::Polynomial)
}
