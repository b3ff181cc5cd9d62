//! The tessellated-glyph pass: the baseline that FURY/DIPY's `odf_slicer` and MRtrix's
//! `mrview` stand for, drawn into the same colour, distance and depth targets as the ray
//! caster so that images and depth maps compare directly.
//!
//! Design: the unit sphere's triangulation ([`SphereMesh`]) is one index buffer shared by
//! every glyph; the vertices (offset from the centre and normal, 24 bytes, generated on
//! the CPU by [`tessellate`]) sit glyph-major in a storage buffer that the vertex shader
//! pulls from by instance and vertex index, and the glyph centres come from the ray
//! caster's own 16-byte instances. So a whole set is one instanced indexed draw, however
//! many glyphs it has, and the index buffer does not grow with the glyph count (one index
//! buffer per glyph with absolute indices would, by 12 bytes a triangle). The number of
//! vertices per glyph is a specialization constant, so there is one pipeline per mesh
//! kind. Sets larger than one storage buffer are split, as the ray caster splits its
//! coefficients. The pass and its scenes keep a [`DeviceContext`], so the device
//! outlives them.
use crate::error::{Error, Result, Setting};
use crate::glyph::intersect::WorldGlyph;
use crate::glyph::tessellate::{MeshKind, MeshVertex, SphereMesh, tessellate};
use crate::render::frame::{FRAME_DESCRIPTOR, FRAME_USAGE, FrameParams};
use crate::render::glyph_data::GlyphSetData;
use crate::render::raycast::{InstanceInput, TargetFormats, glyph_pipeline, viewport_and_scissor};
use crate::render::shaders::{MESH_FRAGMENT, MESH_VERTEX};
use crate::vk::{
    Buffer, BufferBinding, DescriptorPool, DeviceContext, PipelineLayout, Pipelines, RasterTarget,
    ShaderModule, buffer_binding, vertex_fragment_stages,
};
use ash::vk;
use std::time::Instant;

/// The meshes of every glyph of a scene, ready for upload.
pub struct GlyphMeshes {
    /// The unit sphere every glyph deforms; V is its vertex count.
    pub sphere: SphereMesh,
    /// Glyph-major: glyph i owns `vertices[i * V..(i + 1) * V]`.
    pub vertices: Vec<MeshVertex>,
    /// The ray caster's instances (centre, box half-size), in the same glyph order.
    pub instances: Vec<[f32; 4]>,
    /// Wall-clock time of the vertex generation (all threads), ms.
    pub generate_ms: f64,
}

impl GlyphMeshes {
    /// Tessellates every glyph of `sets` on `kind`'s sphere. Sets of any tensor layout
    /// share one draw: the mesh no longer depends on the layout.
    pub fn build(sets: &[GlyphSetData], kind: MeshKind) -> Result<GlyphMeshes> {
        // Only the polynomial glyph is tessellated.
        if let Some(what) = sets
            .iter()
            .find_map(|s| crate::render::ShapeShader::of(s.shape).asked())
        {
            // The data decide (exit code 1), so not a Setting error.
            return Err(Error::Unsupported {
                what,
                by: Setting::Method.with(kind),
            });
        }
        let sphere = SphereMesh::new(kind)?;
        let glyphs: Vec<WorldGlyph> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
        let instances = sets
            .iter()
            .flat_map(|s| s.instances.iter().copied())
            .collect();
        let started = Instant::now();
        let vertices = tessellate(&glyphs, &sphere);
        let generate_ms = started.elapsed().as_secs_f64() * 1e3;
        Ok(GlyphMeshes {
            sphere,
            vertices,
            instances,
            generate_ms,
        })
    }

    /// Number of glyphs.
    pub fn glyphs(&self) -> usize {
        self.instances.len()
    }
}

/// What a tessellated scene costs: sizes and the CPU generation time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshStats {
    /// The tessellation.
    pub kind: MeshKind,
    /// Glyphs drawn.
    pub glyphs: usize,
    /// Vertices of the sphere mesh.
    pub vertices_per_glyph: usize,
    /// Triangles of the sphere mesh.
    pub triangles_per_glyph: usize,
    /// Wall-clock time of the vertex generation (all threads), ms.
    pub generate_ms: f64,
    /// Vertex storage on the GPU (24 bytes a vertex).
    pub vertex_bytes: usize,
    /// The shared index buffer (4 bytes an index), once per scene.
    pub index_bytes: usize,
    /// Glyph instances (16 bytes each).
    pub instance_bytes: usize,
}

impl MeshStats {
    /// Triangles per frame, all glyphs.
    pub fn triangles(&self) -> usize {
        self.glyphs * self.triangles_per_glyph
    }

    /// Vertex, index and instance bytes on the GPU.
    pub fn gpu_bytes(&self) -> usize {
        self.vertex_bytes + self.index_bytes + self.instance_bytes
    }
}

/// Pipelines and layouts of the mesh pass; created once per device and formats.
pub struct MeshPass {
    ctx: DeviceContext,
    formats: TargetFormats,
    // Fields drop in order: the pipelines go before the modules and the layout they were
    // made with, the order the validation layer expects.
    /// Keyed by vertices per glyph (the specialization constant).
    pipelines: Pipelines<u32>,
    vertex: ShaderModule,
    fragment: ShaderModule,
    layout: PipelineLayout,
    buffer_limit: Option<u64>,
}

/// Glyphs of one storage buffer's worth.
struct MeshChunk {
    count: u32,
    instances: Buffer,
    _vertices: Buffer,
    descriptor_set: vk::DescriptorSet,
}

/// A tessellated scene on the GPU.
pub struct MeshSceneGpu {
    frame: Buffer,
    pool: DescriptorPool,
    indices: Buffer,
    index_count: u32,
    vertices_per_glyph: u32,
    chunks: Vec<MeshChunk>,
    /// Its sizes and generation time.
    pub stats: MeshStats,
}

impl MeshSceneGpu {
    /// Instanced draws per frame.
    pub fn draws(&self) -> usize {
        self.chunks.len()
    }

    /// Replaces the frame parameters (camera, settings); not while a frame is in flight.
    pub fn set_frame(&mut self, frame: &FrameParams) -> Result<()> {
        self.frame.write(bytemuck::bytes_of(frame))
    }
}

const FRAME_BINDING: u32 = 0;
/// Binding 1 is the coefficient buffer in glsl/frame.glsl, which the mesh shaders include
/// for the frame block; the vertices take the next one.
const VERTEX_BINDING: u32 = 2;

impl MeshPass {
    /// Layouts and shader modules for attachments of `formats`; the pipeline of a mesh
    /// kind is made at its first upload.
    pub fn new(ctx: &DeviceContext, formats: TargetFormats) -> Result<MeshPass> {
        let bindings = [
            buffer_binding(
                FRAME_BINDING,
                FRAME_DESCRIPTOR,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            ),
            buffer_binding(
                VERTEX_BINDING,
                vk::DescriptorType::STORAGE_BUFFER,
                vk::ShaderStageFlags::VERTEX,
            ),
        ];
        let layout = PipelineLayout::new(ctx, &bindings, vk::ShaderStageFlags::empty(), 0)?;
        Ok(MeshPass {
            ctx: ctx.clone(),
            formats,
            layout,
            // SAFETY: the SPIR-V comes from build.rs and was validated by glslang.
            vertex: unsafe { ShaderModule::new(ctx, MESH_VERTEX)? },
            // SAFETY: as above.
            fragment: unsafe { ShaderModule::fragment(ctx, MESH_FRAGMENT)? },
            pipelines: Pipelines::new(),
            buffer_limit: None,
        })
    }

    /// The pipeline for meshes of `vertices_per_glyph` vertices, created on first use.
    fn pipeline(&mut self, vertices_per_glyph: u32) -> Result<vk::Pipeline> {
        if let Some(p) = self.pipelines.get(&vertices_per_glyph) {
            return Ok(p);
        }
        let entries = [vk::SpecializationMapEntry {
            constant_id: 0,
            offset: 0,
            size: 4,
        }];
        let data = vertices_per_glyph.to_ne_bytes();
        let specialization = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(&data);
        let (vertex, fragment) = (self.vertex.handle(), self.fragment.handle());
        let stages = vertex_fragment_stages(vertex, fragment, Some(&specialization));
        let pipeline = glyph_pipeline(
            &self.ctx,
            self.formats,
            self.layout.handle(),
            &stages,
            InstanceInput::Instance,
            RasterTarget::default(),
            (None, crate::vk::DrawStage::Normal),
        )?;
        Ok(self.pipelines.insert(vertices_per_glyph, pipeline))
    }

    /// Caps the bytes of vertices per storage buffer below the device's
    /// maxStorageBufferRange (tests use it to force the split path); `None` lifts the cap.
    pub fn set_storage_buffer_limit(&mut self, bytes: Option<u64>) {
        self.buffer_limit = bytes;
    }

    /// Uploads the meshes, the shared indices and the frame parameters.
    pub fn upload(
        &mut self,
        ctx: &DeviceContext,
        meshes: &GlyphMeshes,
        frame: &FrameParams,
    ) -> Result<MeshSceneGpu> {
        let per_glyph = meshes.sphere.directions.len();
        let vertices_per_glyph = u32::try_from(per_glyph).map_err(|_| Error::Limit {
            what: "vertices per glyph",
            value: per_glyph as u64,
            limit: u64::from(u32::MAX),
            settings: &[Setting::Method],
        })?;
        self.pipeline(vertices_per_glyph)?;
        let glyph_bytes = (per_glyph * size_of::<MeshVertex>()) as u64;
        let device_limit = ctx.max_storage_buffer_range();
        let limit = self
            .buffer_limit
            .map_or(device_limit, |cap| cap.min(device_limit));
        let per_chunk = (limit / glyph_bytes).min(u32::MAX as u64) as usize;
        if per_chunk == 0 {
            return Err(Error::Limit {
                what: "vertex bytes of one tessellated glyph",
                value: glyph_bytes,
                limit,
                settings: &[Setting::Method],
            });
        }
        let ranges: Vec<_> = (0..meshes.glyphs())
            .step_by(per_chunk)
            .map(|start| start..(start + per_chunk).min(meshes.glyphs()))
            .collect();
        let indices: Vec<u32> = meshes.sphere.triangles.iter().flatten().copied().collect();
        let frame_buffer =
            Buffer::with_data(ctx, "frame", std::slice::from_ref(frame), FRAME_USAGE)?;
        let index_buffer = Buffer::with_data(
            ctx,
            "mesh indices",
            &indices,
            vk::BufferUsageFlags::INDEX_BUFFER,
        )?;
        let pool = DescriptorPool::new(ctx, ranges.len(), 0, 2)?;
        let mut scene = MeshSceneGpu {
            frame: frame_buffer,
            pool,
            indices: index_buffer,
            index_count: indices.len() as u32,
            vertices_per_glyph,
            chunks: Vec::with_capacity(ranges.len()),
            stats: MeshStats {
                kind: meshes.sphere.kind,
                glyphs: meshes.glyphs(),
                vertices_per_glyph: per_glyph,
                triangles_per_glyph: meshes.sphere.triangles.len(),
                generate_ms: meshes.generate_ms,
                vertex_bytes: meshes.vertices.len() * size_of::<MeshVertex>(),
                index_bytes: indices.len() * 4,
                instance_bytes: meshes.instances.len() * 16,
            },
        };
        for range in ranges {
            let chunk = self.upload_chunk(ctx, &scene, meshes, range)?;
            scene.chunks.push(chunk);
        }
        Ok(scene)
    }

    fn upload_chunk(
        &self,
        ctx: &DeviceContext,
        scene: &MeshSceneGpu,
        meshes: &GlyphMeshes,
        range: std::ops::Range<usize>,
    ) -> Result<MeshChunk> {
        let per_glyph = meshes.sphere.directions.len();
        let instances = Buffer::with_data(
            ctx,
            "mesh instances",
            &meshes.instances[range.clone()],
            vk::BufferUsageFlags::VERTEX_BUFFER,
        )?;
        let vertices = Buffer::with_data(
            ctx,
            "mesh vertices",
            &meshes.vertices[range.start * per_glyph..range.end * per_glyph],
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let descriptor_set = scene.pool.buffer_set(
            self.layout.set_layout(),
            &[
                BufferBinding::storage(FRAME_BINDING, &scene.frame),
                BufferBinding::storage(VERTEX_BINDING, &vertices),
            ],
        )?;
        Ok(MeshChunk {
            count: range.len() as u32,
            instances,
            _vertices: vertices,
            descriptor_set,
        })
    }

    /// Records the draws of a tessellated scene. The caller has begun dynamic rendering
    /// with attachments of this pass's formats, of size `extent`.
    pub fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        scene: &MeshSceneGpu,
        extent: vk::Extent2D,
    ) -> Result<()> {
        let pipeline = self.pipeline(scene.vertices_per_glyph)?;
        let (viewport, scissor) = viewport_and_scissor(extent);
        // SAFETY: recording state is the caller's; all handles are alive.
        unsafe {
            let d = self.ctx.device();
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            d.cmd_set_viewport(cmd, 0, &[viewport]);
            d.cmd_set_scissor(cmd, 0, &[scissor]);
            d.cmd_bind_index_buffer(cmd, scene.indices.handle, 0, vk::IndexType::UINT32);
            for chunk in &scene.chunks {
                d.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.layout.handle(),
                    0,
                    &[chunk.descriptor_set],
                    &[],
                );
                d.cmd_bind_vertex_buffers(cmd, 0, &[chunk.instances.handle], &[0]);
                d.cmd_draw_indexed(cmd, scene.index_count, chunk.count, 0, 0, 0);
            }
        }
        Ok(())
    }
}
