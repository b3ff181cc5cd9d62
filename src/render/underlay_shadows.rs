//! The underlay receiving the glyphs' shadows and ambient occlusion (`--shadows`,
//! `--ambient-occlusion`). After the glyphs are drawn, each underlay plane is drawn again
//! once per exact glyph batch, with the exact method's receiver fragment shader
//! (raycast_exact.frag compiled with `GLYPHCAST_RECEIVER`): where the plane is what the
//! pixel shows (depth tested EQUAL against the plane's own draw, whose position the
//! receiver's vertex shader computes the same way), the rays of a glyph's hit are cast
//! from the plane's point through the batch's shadow grid, and the pixel keeps the share
//! ambient * (occlusion share) + (1 - ambient) * (lit share) of the underlay's colour: the
//! plane is a matte surface facing the light whose colour in full light is the
//! underlay's. The draws blend by MIN, so that where batches overlap the darkest share
//! holds (exact for hard shadows, whose shares are 0 or 1). The float64 reference is
//! `glyph::shadow::plane_share`.
use std::collections::HashMap;

use crate::error::{Asked, Error, Result, Setting};
use crate::glyph::{GlyphShape, TensorLayout};
use crate::render::component::UploadedGlyphs;
use crate::render::raycast::{
    GlyphSetGpu, SceneGpu, TargetFormats, batch_bindings, viewport_and_scissor,
};
use crate::render::shaders::{UNDERLAY_RECEIVER_VERTEX, raycast_shader};
use crate::render::underlay::{PlanePush, UnderlayGpu, UnderlayPlane, underlay_bindings};
use crate::render::{Method, ShapeShader};
use crate::vk::{
    DeviceContext, GraphicsPipelineDesc, Pipeline, PipelineLayout, RasterTarget, ShaderModule,
    graphics_pipeline, vertex_fragment_stages,
};
use ash::vk;
use bytemuck::{Pod, Zeroable};

/// The receiver's push constants: the batch's word (frame.glsl `GlyphSetParams`), then
/// the plane at byte 16 (glsl/underlay.vert with `GLYPHCAST_RECEIVER`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct ReceiverPush {
    pub(crate) hide_negative: u32,
    pub(crate) _pad: [u32; 3],
    pub(crate) plane: PlanePush,
}

/// The receiver's pipelines, one per tensor layout, for a rendering of a colour and a
/// depth attachment (a pipeline that blends one colour attachment and writes none of
/// another needs the independentBlend feature, so the headless renderer records the
/// receivers in a second rendering without its distance attachment).
pub struct UnderlayShadowPass {
    ctx: DeviceContext,
    formats: TargetFormats,
    pipelines: HashMap<TensorLayout, Pipeline>,
    vertex: ShaderModule,
    /// Set 0: a glyph batch's bindings; set 1: the underlay's.
    layout: PipelineLayout,
}

impl UnderlayShadowPass {
    /// The layout and vertex shader for attachments of `formats`, which has no distance
    /// attachment; pipelines are made by [`UnderlayShadowPass::prepare`].
    pub fn new(ctx: &DeviceContext, formats: TargetFormats) -> Result<Self> {
        if formats.distance.is_some() {
            return Err(Error::Call {
                call: "UnderlayShadowPass::new",
                expected: "formats without a distance attachment",
            });
        }
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let push = std::mem::size_of::<ReceiverPush>() as u32;
        let layout = PipelineLayout::with_sets(
            ctx,
            &[&batch_bindings(), &underlay_bindings()],
            stages,
            push,
        )?;
        Ok(UnderlayShadowPass {
            ctx: ctx.clone(),
            formats,
            pipelines: HashMap::new(),
            // SAFETY: the SPIR-V comes from build.rs and was validated by glslang.
            vertex: unsafe { ShaderModule::new(ctx, UNDERLAY_RECEIVER_VERTEX)? },
            layout,
        })
    }

    /// Makes the pipelines of the batches of `glyphs` that cast rays onto the underlay.
    pub fn prepare(&mut self, glyphs: &UploadedGlyphs) -> Result<()> {
        for set in receiving_batches(&glyphs.gpu) {
            if self.pipelines.contains_key(&set.layout) {
                continue;
            }
            let spirv = raycast_shader(set.layout, Method::Exact, ShapeShader::Polynomial)
                .and_then(|s| s.receiver_fragment)
                .ok_or_else(|| Error::Unsupported {
                    what: Asked::Layout(set.layout.into()),
                    by: Setting::Shadows.with("hard"),
                })?;
            // SAFETY: as in `new`.
            let fragment = unsafe { ShaderModule::fragment(&self.ctx, spirv)? };
            let stages = vertex_fragment_stages(self.vertex.handle(), fragment.handle(), None);
            let mut color_formats = vec![self.formats.color];
            color_formats.extend(self.formats.distance);
            let desc = GraphicsPipelineDesc {
                stages: &stages,
                vertex_bindings: &[],
                vertex_attributes: &[],
                cull: vk::CullModeFlags::NONE,
                color_formats: &color_formats,
                depth_format: self.formats.depth,
                layout: self.layout.handle(),
                raster: RasterTarget::default(),
                darken: Some(vk::CompareOp::EQUAL),
                stage: crate::vk::DrawStage::Normal,
            };
            // SAFETY: the modules are alive until the call returns; their SPIR-V declares
            // the blocks of the layout (render::interface checks them).
            let pipeline = unsafe { graphics_pipeline(&self.ctx, &desc)? };
            self.pipelines.insert(set.layout, pipeline);
        }
        Ok(())
    }

    /// Records, for each batch of `glyphs` that casts rays and each plane, the plane drawn
    /// again darkened by the batch's shadows (with frame block `frame_index`). The caller
    /// has drawn the planes ([`UnderlayPass::record`](crate::render::underlay::UnderlayPass::record))
    /// and the glyphs into the attachments of the rendering begun with this pass's
    /// formats, of size `extent`, and prepared `glyphs`.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        (glyphs, frame_index): (&UploadedGlyphs, usize),
        (volume, planes): (&UnderlayGpu, &[UnderlayPlane]),
        view_proj: [[f32; 4]; 4],
        extent: vk::Extent2D,
    ) -> Result<()> {
        let scene = &glyphs.gpu;
        let (viewport, scissor) = viewport_and_scissor(extent);
        let d = self.ctx.device();
        for set in receiving_batches(scene) {
            let pipeline = self.pipelines.get(&set.layout).ok_or(Error::Call {
                call: "UnderlayShadowPass::record",
                expected: "UnderlayShadowPass::prepare for these glyphs first",
            })?;
            let batch = set.descriptor_set(frame_index)?;
            let sets = [batch, volume.descriptor_set];
            // SAFETY: recording state is the caller's; every handle is alive.
            unsafe {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.handle());
                d.cmd_set_viewport(cmd, 0, &[viewport]);
                d.cmd_set_scissor(cmd, 0, &[scissor]);
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.layout.handle(),
                    0,
                    &sets,
                    &[],
                );
            }
            for plane in planes {
                let push = ReceiverPush {
                    hide_negative: set.negative.shader_code(),
                    _pad: [0; 3],
                    plane: PlanePush::new(plane, view_proj),
                };
                // SAFETY: as above; the push range covers the whole block for both stages.
                unsafe {
                    d.cmd_push_constants(
                        cmd,
                        self.layout.handle(),
                        vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                        0,
                        bytemuck::bytes_of(&push),
                    );
                    d.cmd_draw(cmd, 6, 1, 0, 0);
                }
            }
        }
        Ok(())
    }
}

/// The batches of `scene` whose glyphs cast rays onto the underlay: those drawn by the
/// exact method's shadow-casting pipelines (polynomial glyphs), when the scene casts rays.
fn receiving_batches(scene: &SceneGpu) -> impl Iterator<Item = &GlyphSetGpu> {
    scene
        .sets
        .iter()
        .filter(move |set| scene.shadows && set.shape == GlyphShape::Polynomial)
}
