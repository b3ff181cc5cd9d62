//! Fibre peaks (`--peaks`): each peak a thin capsule through its voxel's centre, ray-cast
//! in the glyphs' depth buffer, so that a peak and the lobe it comes from cut each other
//! where they meet (as mrview draws fixels: lines through the voxel centres).
//!
//! A pass of its own, beside the glyph pass and the underlay's: one instanced draw of a
//! screen quad per capsule (glsl/peaks.vert: two triangles that hold its projection),
//! whose fragments intersect the pixel's ray with the
//! capsule in closed form (glsl/peaks.frag) and write colour, depth and the ray
//! distance (the depth map holds the first glyph or peak a ray meets). Capsules need no
//! per-order shaders, so they are not a glyph kind of the catalog. The float64 reference
//! is [`crate::glyph::capsule`]; [`PeakSet::intersect`] ray-casts a whole set with it.
//!
//! Streamlines may instead be drawn as lines ([`PeakSet::lines`]): the same quad as a
//! flat ribbon, at least a pixel wide, at the depth of the axis, unlit, depth-tested
//! before its fragment shader runs (glsl/lines.frag): not exact, but a fragment behind
//! something nearer costs nothing, which a whole brain's overlapping segments need.
//!
//! `crate::volume` reads peak files and turns the peaks of a view's slices into a
//! [`PeakSet`]; an embedder builds one from its own segments and hands it to
//! [`FrameView::with_peaks`](crate::render::headless::FrameView::with_peaks) or records
//! [`PeaksPass::record`] into its own frame.
use crate::camera::{Camera, Ray};
use crate::error::Result;
use crate::glyph::capsule::{Capsule, CapsuleHit};
use crate::render::frame::{FRAME_DESCRIPTOR, FRAME_USAGE, FrameParams, SceneExtent};
use crate::render::raycast::{TargetFormats, viewport_and_scissor};
use crate::render::shaders::{LINES_FRAGMENT, LINES_VERTEX, PEAKS_FRAGMENT, PEAKS_VERTEX};
use crate::vk::recording::bind_graphics;
use crate::vk::{
    Buffer, BufferBinding, DescriptorPool, DeviceContext, GraphicsPipelineDesc, Pipeline,
    PipelineLayout, ShaderModule, buffer_binding, graphics_pipeline, vertex_fragment_stages,
};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use std::sync::OnceLock;

/// One peak as drawn: its capsule and its colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakSegment {
    /// The capsule, world space.
    pub capsule: Capsule,
    /// sRGB colour, each channel 0 to 1 (as the PNG stores round(255 c)).
    pub color: [f64; 3],
}

/// The peaks of a frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PeakSet {
    /// Every capsule drawn, ray-cast exactly.
    pub segments: Vec<PeakSegment>,
    /// Segments drawn as lines instead: flat ribbons of each capsule's projected width
    /// (at least a pixel), at the depth of its axis, unlit (glsl/lines.frag); not part
    /// of the float64 reference.
    pub lines: Vec<PeakSegment>,
}

impl PeakSet {
    /// The nearest capsule entry along `ray` and the index of its segment (float64: the
    /// reference of the pass).
    pub fn intersect(&self, ray: &Ray) -> Option<(CapsuleHit, usize)> {
        self.segments
            .iter()
            .enumerate()
            .filter_map(|(n, s)| s.capsule.intersect(ray).map(|hit| (hit, n)))
            .min_by(|a, b| a.0.t.total_cmp(&b.0.t))
    }

    /// Whether there is nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty() && self.lines.is_empty()
    }

    /// The capsules and the lines, in that order.
    pub fn all(&self) -> impl Iterator<Item = &PeakSegment> {
        self.segments.iter().chain(&self.lines)
    }

    /// Appends `other`'s capsules and lines.
    pub fn extend(&mut self, other: PeakSet) {
        self.segments.extend(other.segments);
        self.lines.extend(other.lines);
    }

    /// `extent` (the glyphs') widened to the capsules' bounding spheres, so that no peak
    /// is cut by the near or far plane; the magnitude range stays the glyphs'.
    pub fn widen(&self, camera: &Camera, extent: SceneExtent) -> SceneExtent {
        if self.is_empty() {
            return extent;
        }
        let spheres = self.all().map(|s| {
            (
                s.capsule.center().to_array(),
                s.capsule.bounding_radius() * 1.01,
            )
        });
        let peaks = SceneExtent::of_spheres(camera, spheres);
        let fwd = camera.frame().fwd;
        let seen = self
            .all()
            .any(|s| fwd.dot(s.capsule.center() - camera.eye) > 0.0);
        if !seen {
            return extent;
        }
        SceneExtent {
            near: extent.near.min(peaks.near),
            far: extent.far.max(peaks.far),
            max_radius: extent.max_radius,
        }
    }
}

/// The per-instance input of glsl/peaks.vert: 48 bytes per capsule.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct CapsuleInstance {
    /// xyz: end a; w: radius.
    pub(crate) end_a_radius: [f32; 4],
    /// xyz: end b; w unused.
    pub(crate) end_b: [f32; 4],
    /// rgb: linear colour.
    pub(crate) color: [f32; 4],
}

/// Binding of the frame's parameter block (glsl/frame.glsl), as in the glyph passes.
pub(crate) const PEAKS_FRAME_BINDING: u32 = 0;

/// The peaks' pipelines (capsules, and lines), for attachments of given formats;
/// created once per device.
pub struct PeaksPass {
    ctx: DeviceContext,
    formats: TargetFormats,
    // Fields drop in order: the pipelines before the layout they were made with.
    pipeline: Pipeline,
    /// Made by the first upload that has lines: most peak sets have none.
    lines_pipeline: OnceLock<Pipeline>,
    layout: PipelineLayout,
    indices: Buffer,
}

/// A peak set on the GPU: its capsules and lines, and its own copy of the frame block.
pub struct PeaksGpu {
    capsules: Option<Buffer>,
    lines: Option<Buffer>,
    counts: [u32; 2],
    frame: Buffer,
    _pool: DescriptorPool,
    descriptor_set: vk::DescriptorSet,
}

impl PeaksPass {
    /// The pipeline for attachments of `formats`: the glyphs' depth test (reversed,
    /// GREATER) and outputs.
    pub fn new(ctx: &DeviceContext, formats: TargetFormats) -> Result<PeaksPass> {
        let bindings = [buffer_binding(
            PEAKS_FRAME_BINDING,
            FRAME_DESCRIPTOR,
            vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
        )];
        let layout = PipelineLayout::new(ctx, &bindings, vk::ShaderStageFlags::empty(), 0)?;
        let pipeline = create_pipeline(ctx, formats, layout.handle(), false)?;
        Ok(PeaksPass {
            ctx: ctx.clone(),
            formats,
            pipeline,
            lines_pipeline: OnceLock::new(),
            layout,
            indices: Buffer::with_data(
                ctx,
                "peak quad indices",
                &QUAD_INDICES,
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
        })
    }

    /// Uploads `peaks` with the frame block `frame` (the glyph pass's); `None` when
    /// there is no segment to draw.
    pub fn upload(
        &self,
        ctx: &DeviceContext,
        peaks: &PeakSet,
        frame: &FrameParams,
    ) -> Result<Option<PeaksGpu>> {
        if peaks.is_empty() {
            return Ok(None);
        }
        if !peaks.lines.is_empty() && self.lines_pipeline.get().is_none() {
            let lines = create_pipeline(ctx, self.formats, self.layout.handle(), true)?;
            // Another thread's upload may have set it meanwhile: either pipeline serves.
            let _ = self.lines_pipeline.set(lines);
        }
        let upload = |segments: &[PeakSegment]| -> Result<Option<Buffer>> {
            if segments.is_empty() {
                return Ok(None);
            }
            let instances: Vec<CapsuleInstance> = segments.iter().map(instance).collect();
            Buffer::with_data(
                ctx,
                "peak capsules",
                &instances,
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )
            .map(Some)
        };
        let frame =
            Buffer::with_data(ctx, "peaks frame", std::slice::from_ref(frame), FRAME_USAGE)?;
        let pool = DescriptorPool::new(ctx, 1, 0, 1)?;
        let descriptor_set = pool.buffer_set(
            self.layout.set_layout(),
            &[BufferBinding::storage(PEAKS_FRAME_BINDING, &frame)],
        )?;
        Ok(Some(PeaksGpu {
            capsules: upload(&peaks.segments)?,
            lines: upload(&peaks.lines)?,
            counts: [peaks.segments.len() as u32, peaks.lines.len() as u32],
            frame,
            _pool: pool,
            descriptor_set,
        }))
    }

    /// Records the draw of every capsule, then of every line. The caller has begun
    /// dynamic rendering with attachments of this pass's formats, of size `extent`.
    pub fn record(&self, cmd: vk::CommandBuffer, peaks: &PeaksGpu, extent: vk::Extent2D) {
        let (viewport, scissor) = viewport_and_scissor(extent);
        let d = self.ctx.device();
        let draws = [
            (Some(&self.pipeline), &peaks.capsules, peaks.counts[0]),
            (self.lines_pipeline.get(), &peaks.lines, peaks.counts[1]),
        ];
        for (pipeline, instances, count) in draws {
            // (A set with lines was uploaded after the lines' pipeline was made.)
            let (Some(pipeline), Some(instances)) = (pipeline, instances) else {
                continue;
            };
            // SAFETY: recording state is the caller's; every handle is alive.
            unsafe {
                let pipeline = (pipeline.handle(), self.layout.handle());
                bind_graphics(d, cmd, pipeline, peaks.descriptor_set, (viewport, scissor));
                d.cmd_bind_vertex_buffers(cmd, 0, &[instances.handle], &[0]);
                d.cmd_bind_index_buffer(cmd, self.indices.handle, 0, vk::IndexType::UINT16);
                d.cmd_draw_indexed(cmd, QUAD_INDICES.len() as u32, count, 0, 0, 0);
            }
        }
    }
}

impl PeaksGpu {
    /// Replaces the frame block (camera, lighting); not while a frame is in flight.
    pub fn set_frame(&mut self, frame: &FrameParams) -> Result<()> {
        self.frame.write(bytemuck::bytes_of(frame))
    }
}

/// The GPU instance of a segment: float32 ends and radius, the colour in linear light
/// (the shaders' sRGB decoding, c^2.2, as the glyphs' direction colour).
fn instance(segment: &PeakSegment) -> CapsuleInstance {
    let c = segment.capsule;
    let [r, g, b] = segment.color.map(|v| v.clamp(0.0, 1.0).powf(2.2) as f32);
    CapsuleInstance {
        end_a_radius: [c.a.x as f32, c.a.y as f32, c.a.z as f32, c.radius as f32],
        end_b: [c.b.x as f32, c.b.y as f32, c.b.z as f32, 0.0],
        color: [r, g, b, 1.0],
    }
}

/// The two triangles of a capsule's screen quad (glsl/peaks.vert), corners 0 to 3.
const QUAD_INDICES: [u16; 6] = [0, 1, 2, 2, 1, 3];

/// The peaks' pipeline (or with `lines` the lines'): instanced screen quads (one
/// 48-byte instance each), either winding, the glyphs' attachments and depth test.
fn create_pipeline(
    ctx: &DeviceContext,
    formats: TargetFormats,
    layout: vk::PipelineLayout,
    lines: bool,
) -> Result<Pipeline> {
    let (vertex, fragment) = match lines {
        false => (PEAKS_VERTEX, PEAKS_FRAGMENT),
        true => (LINES_VERTEX, LINES_FRAGMENT),
    };
    // SAFETY: the SPIR-V comes from build.rs and was validated by glslang.
    let vertex = unsafe { ShaderModule::new(ctx, vertex)? };
    // SAFETY: as above.
    let fragment = unsafe { ShaderModule::fragment(ctx, fragment)? };
    let stages = vertex_fragment_stages(vertex.handle(), fragment.handle(), None);
    let bindings = [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<CapsuleInstance>() as u32,
        input_rate: vk::VertexInputRate::INSTANCE,
    }];
    let attributes: Vec<_> = (0..3)
        .map(|location| vk::VertexInputAttributeDescription {
            location,
            binding: 0,
            format: vk::Format::R32G32B32A32_SFLOAT,
            offset: 16 * location,
        })
        .collect();
    let mut color_formats = vec![formats.color];
    color_formats.extend(formats.distance);
    let desc = GraphicsPipelineDesc {
        stages: &stages,
        vertex_bindings: &bindings,
        vertex_attributes: &attributes,
        cull: vk::CullModeFlags::NONE,
        color_formats: &color_formats,
        depth_format: formats.depth,
        layout,
        // glyphcast's own targets: one sample, reversed depth (the headless renderer's).
        raster: crate::vk::RasterTarget::default(),
        darken: None,
        stage: crate::vk::DrawStage::Normal,
    };
    // SAFETY: the modules are alive until the call returns; their SPIR-V declares the
    // frame block of `layout` (render::interface checks it).
    unsafe { graphics_pipeline(ctx, &desc) }
}
