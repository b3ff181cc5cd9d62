//! The application's own geometry: a square plane at a height, drawn by a wgpu render
//! pipeline (plane.wgsl) with depth test and write, as any wgpu mesh would be.
use glam::{DMat4, DVec3};

/// A horizontal square: its height (z) and half size, centred on the z axis.
#[derive(Clone, Copy, Debug)]
pub struct Square {
    pub height: f64,
    pub half: f64,
}

impl Square {
    /// Where a ray from `origin` along unit `dir` meets the square (its distance).
    #[cfg_attr(not(test), allow(dead_code))]
    pub fn hit(&self, origin: DVec3, dir: DVec3) -> Option<f64> {
        if dir.z.abs() < 1e-12 {
            return None;
        }
        let t = (self.height - origin.z) / dir.z;
        let p = origin + t * dir;
        (t > 0.0 && p.x.abs() <= self.half && p.y.abs() <= self.half).then_some(t)
    }
}

/// The plane's pipeline and its uniform block.
pub struct PlanePass {
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

impl PlanePass {
    pub fn new(
        device: &wgpu::Device,
        (color, depth): (wgpu::TextureFormat, wgpu::TextureFormat),
        samples: u32,
    ) -> PlanePass {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("plane"),
            source: wgpu::ShaderSource::Wgsl(include_str!("plane.wgsl").into()),
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("plane uniforms"),
            size: 80,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("plane"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("plane"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("plane"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("plane"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(color.into())],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: depth,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: samples,
                ..Default::default()
            },
            multiview_mask: None,
            cache: None,
        });
        PlanePass {
            pipeline,
            uniforms,
            bind_group,
        }
    }

    /// Writes the camera and square for the next draw (before the frame is submitted).
    pub fn set(&self, queue: &wgpu::Queue, view_proj: DMat4, square: &Square) {
        let mut block = view_proj.as_mat4().to_cols_array().to_vec();
        block.extend([0.0, square.height as f32, square.half as f32, 0.0]);
        let bytes: Vec<u8> = block.iter().flat_map(|v| v.to_le_bytes()).collect();
        queue.write_buffer(&self.uniforms, 0, &bytes);
    }

    /// Draws the square in `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.draw(0..6, 0..1);
    }
}
