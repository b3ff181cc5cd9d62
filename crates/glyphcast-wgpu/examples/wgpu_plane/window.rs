//! The windowed mode: winit and a wgpu surface; the glyphs drawn straight into the
//! surface's texture after the plane, with wgpu's frame pacing.
use crate::frames::Result;
use crate::plane::PlanePass;
use crate::scene;
use glyphcast::DepthConvention;
use glyphcast::render::host_view::{look_at, perspective};
use glyphcast_wgpu::{GlyphPass, GlyphPassDesc, GlyphTarget, WgpuCamera};
use std::sync::Arc;
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

/// Everything made once the window exists.
struct Gpu {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    device: wgpu::Device,
    queue: wgpu::Queue,
    depth: wgpu::TextureView,
    plane: PlanePass,
    glyphs: GlyphPass,
    frame: u32,
}

#[derive(Default)]
struct App {
    gpu: Option<Gpu>,
    error: Option<Box<dyn std::error::Error>>,
    /// Frames to draw before closing, if not until the window is closed.
    frames: Option<u32>,
}

pub fn run(frames: Option<u32>) -> Result<()> {
    let event_loop = EventLoop::new()?;
    let mut app = App {
        frames,
        ..App::default()
    };
    event_loop.run_app(&mut app)?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

fn depth_view(device: &wgpu::Device, config: &wgpu::SurfaceConfiguration) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d {
                width: config.width,
                height: config.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: scene::DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

impl Gpu {
    fn new(window: Arc<Window>) -> Result<Gpu> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let surface = instance.create_surface(window.clone())?;
        let adapter = glyphcast_wgpu::validation::block_on(instance.request_adapter(
            &wgpu::RequestAdapterOptions {
                compatible_surface: Some(&surface),
                ..Default::default()
            },
        ))?;
        let (device, queue) = glyphcast_wgpu::request_device(&adapter, &Default::default())?;
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(&adapter, size.width.max(1), size.height.max(1))
            .ok_or("the surface does not fit this adapter")?;
        let caps = surface.get_capabilities(&adapter);
        if let Some(srgb) = caps.formats.iter().find(|f| f.is_srgb()) {
            config.format = *srgb;
        }
        surface.configure(&device, &config);
        let desc = GlyphPassDesc {
            color_format: config.format,
            depth_format: scene::DEPTH_FORMAT,
            ..GlyphPassDesc::default()
        };
        // SAFETY: the device was made by `request_device`; the frame's textures live
        // until wgpu has presented them.
        let mut glyphs = unsafe { GlyphPass::new(&adapter, &device, &desc)? };
        glyphs.set_glyphs(&scene::glyph_sets()?)?;
        Ok(Gpu {
            depth: depth_view(&device, &config),
            plane: PlanePass::new(&device, (config.format, scene::DEPTH_FORMAT), 1),
            window,
            surface,
            config,
            device,
            queue,
            glyphs,
            frame: 0,
        })
    }

    fn resize(&mut self, width: u32, height: u32) {
        self.config.width = width.max(1);
        self.config.height = height.max(1);
        self.surface.configure(&self.device, &self.config);
        self.depth = depth_view(&self.device, &self.config);
    }

    fn draw(&mut self) -> Result<()> {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame)
            | wgpu::CurrentSurfaceTexture::Suboptimal(frame) => frame,
            _ => {
                self.surface.configure(&self.device, &self.config);
                return Ok(());
            }
        };
        let view = frame.texture.create_view(&Default::default());
        let c = scene::camera(self.frame);
        let aspect = self.config.width as f64 / self.config.height as f64;
        let vulkan = perspective(
            scene::FOV_Y_DEG.to_radians(),
            aspect,
            scene::NEAR,
            Some(scene::FAR),
            DepthConvention::Standard,
        );
        let camera = WgpuCamera {
            view: look_at(c.eye, c.target, c.up),
            projection: glam::DMat4::from_diagonal(glam::DVec4::new(1.0, -1.0, 1.0, 1.0)) * vulkan,
        };
        self.plane
            .set(&self.queue, camera.projection * camera.view, &scene::SQUARE);
        let mut encoder = self.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(scene::CLEAR_COLOR),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            self.plane.draw(&mut pass);
        }
        let target = GlyphTarget {
            color: &view,
            depth: &self.depth,
            resolve: None,
        };
        let [states, glyphs] = self.glyphs.encode(&camera, &target)?;
        self.queue.submit([encoder.finish(), states, glyphs]);
        // (wgpu 29 presents through the frame, wgpu 30 through the queue.)
        #[cfg(feature = "wgpu30")]
        self.queue.present(frame);
        #[cfg(not(feature = "wgpu30"))]
        frame.present();
        self.frame += 1;
        self.window.request_redraw();
        Ok(())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gpu.is_some() {
            return;
        }
        let attributes = Window::default_attributes().with_title("glyphcast in wgpu");
        let made = event_loop
            .create_window(attributes)
            .map_err(|e| e.into())
            .and_then(|window| Gpu::new(Arc::new(window)));
        match made {
            Ok(gpu) => {
                gpu.window.request_redraw();
                self.gpu = Some(gpu);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(gpu) = self.gpu.as_mut() else {
            return;
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => gpu.resize(size.width, size.height),
            WindowEvent::RedrawRequested => {
                if let Err(e) = gpu.draw() {
                    self.error = Some(e);
                    event_loop.exit();
                }
                if self.frames.is_some_and(|n| gpu.frame >= n) {
                    println!("{} frames drawn in a window", gpu.frame);
                    event_loop.exit();
                }
            }
            _ => {}
        }
    }
}
