//! The headless frame loop: K frames in flight, each with its own colour and depth
//! textures (as a swapchain's images would be); the plane drawn by a wgpu render pass,
//! the glyphs by glyphcast-wgpu into the same textures; the last frame read back.
use crate::plane::PlanePass;
use crate::scene::{self, COLOR_FORMAT, DEPTH_FORMAT, HEIGHT, WIDTH};
use glyphcast_wgpu::{GlyphPass, GlyphPassDesc, GlyphTarget};

/// What a headless run is asked to do.
#[derive(Clone, Debug)]
pub struct Options {
    pub frames: u32,
    pub in_flight: usize,
    /// Whether the application draws its plane (the glyph-only comparison leaves it out).
    pub plane: bool,
    /// Whether the layer's synchronization validation is on too.
    pub sync_validation: bool,
    /// Samples per pixel: above 1, the scene and the glyphs draw into multisampled
    /// textures resolved into the one-sample colour.
    pub samples: u32,
    /// Views per frame, each into textures of its own, view v seeing the camera of frame
    /// `frame + VIEW_STEP * v` (`GlyphPass::encode_views`); the plane only with one.
    pub views: usize,
}

/// How many frames of the orbit apart the views of one frame look.
pub const VIEW_STEP: u32 = 40;

impl Default for Options {
    fn default() -> Self {
        Options {
            frames: 30,
            in_flight: 3,
            plane: true,
            sync_validation: true,
            samples: 1,
            views: 1,
        }
    }
}

/// The last frame's pictures, its camera frame number, and the layer's messages.
pub struct Run {
    pub rgba: Vec<u8>,
    /// Window depth, row-major from the top-left (one-sample runs only).
    #[cfg_attr(not(test), allow(dead_code))]
    pub depth: Vec<f32>,
    #[cfg_attr(not(test), allow(dead_code))]
    pub last_frame: u32,
    pub validation: Vec<String>,
    /// The adapter and its driver, as wgpu reports them.
    pub adapter: String,
    /// With several views per frame, each view's last frame (its camera's frame number
    /// in `last_frame`); the fields above are view 0's.
    #[cfg_attr(not(test), allow(dead_code))]
    pub views: Vec<Run>,
}

pub type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

/// One frame slot's textures: the one-sample colour and depth that are read back, and
/// the multisampled colour and depth drawn into when there are several samples.
struct Slot {
    color: wgpu::Texture,
    depth: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    multisampled: Option<(wgpu::TextureView, wgpu::TextureView)>,
}

fn texture(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    samples: u32,
) -> wgpu::Texture {
    let copy = if samples == 1 {
        wgpu::TextureUsages::COPY_SRC
    } else {
        wgpu::TextureUsages::empty()
    };
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | copy,
        view_formats: &[],
    })
}

impl Slot {
    fn new(device: &wgpu::Device, samples: u32) -> Slot {
        let color = texture(device, "colour", COLOR_FORMAT, 1);
        let depth = texture(device, "depth", DEPTH_FORMAT, 1);
        let multisampled = (samples > 1).then(|| {
            let view = |t: wgpu::Texture| t.create_view(&Default::default());
            (
                view(texture(device, "msaa colour", COLOR_FORMAT, samples)),
                view(texture(device, "msaa depth", DEPTH_FORMAT, samples)),
            )
        });
        Slot {
            color_view: color.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            color,
            depth,
            multisampled,
        }
    }

    /// Where the scene and the glyphs draw: the multisampled textures, resolved into the
    /// one-sample colour, or the one-sample ones.
    fn target(&self) -> GlyphTarget<'_> {
        match &self.multisampled {
            Some((color, depth)) => GlyphTarget {
                color,
                depth,
                resolve: Some(&self.color_view),
            },
            None => GlyphTarget {
                color: &self.color_view,
                depth: &self.depth_view,
                resolve: None,
            },
        }
    }
}

/// Runs the frames on a validated instance's first adapter.
pub fn run(options: &Options) -> Result<Run> {
    let validated = glyphcast_wgpu::validation::ValidatedInstance::new(options.sync_validation)?;
    let adapter = validated.adapter()?;
    let mut run = draw_frames(&adapter, options)?;
    let info = adapter.get_info();
    run.adapter = format!("{} ({})", info.name, info.driver_info);
    drop(adapter);
    run.validation = validated.messages();
    Ok(run)
}

/// The frame loop on `adapter`: the device and everything on it are dropped on return.
pub fn draw_frames(adapter: &wgpu::Adapter, options: &Options) -> Result<Run> {
    let (device, queue) = glyphcast_wgpu::request_device(adapter, &Default::default())?;
    let desc = GlyphPassDesc {
        color_format: COLOR_FORMAT,
        depth_format: DEPTH_FORMAT,
        frames_in_flight: options.in_flight,
        samples: options.samples,
        ..GlyphPassDesc::default()
    };
    // SAFETY: the device was made by `request_device`, with glyphcast's features; the
    // slots' textures live until the device is idle.
    let mut glyphs = unsafe { GlyphPass::new(adapter, &device, &desc)? };
    glyphs.set_glyph_sets(&[scene::glyph_arrays()?])?;
    let plane = PlanePass::new(&device, (COLOR_FORMAT, DEPTH_FORMAT), options.samples);
    let views = options.views.max(1);
    // Frame slot k's view v draws into slots[k * views + v].
    let slots: Vec<Slot> = (0..options.in_flight * views)
        .map(|_| Slot::new(&device, options.samples))
        .collect();
    let bytes = 4 * WIDTH as u64 * HEIGHT as u64;
    let readback = |label| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        })
    };
    let readbacks: Vec<_> = (0..views)
        .map(|_| (readback("colour readback"), readback("depth readback")))
        .collect();
    let plane_drawn = options.plane && views == 1;
    let last = options.frames - 1;
    for frame in 0..options.frames {
        let frame_slots = &slots[(frame as usize % options.in_flight) * views..][..views];
        let cameras: Vec<_> = (0..views as u32)
            .map(|v| scene::wgpu_camera_f32(frame + VIEW_STEP * v))
            .collect();
        plane.set(
            &queue,
            cameras[0].projection * cameras[0].view,
            &scene::SQUARE,
        );
        let mut encoder = device.create_command_encoder(&Default::default());
        for slot in frame_slots {
            draw_scene(&mut encoder, slot, plane_drawn.then_some(&plane));
        }
        let [states, glyph_commands] = if views == 1 {
            glyphs.encode(&cameras[0], &frame_slots[0].target())?
        } else {
            let pairs: Vec<_> = cameras
                .iter()
                .zip(frame_slots)
                .map(|(camera, slot)| (*camera, slot.target()))
                .collect();
            glyphs.encode_views(&pairs)?
        };
        let mut after = device.create_command_encoder(&Default::default());
        if frame == last {
            for (slot, (color, depth)) in frame_slots.iter().zip(&readbacks) {
                copy_out(&mut after, slot, color, depth, options.samples);
            }
        }
        queue.submit([encoder.finish(), states, glyph_commands, after.finish()]);
    }
    let mut runs = Vec::new();
    for (v, (color, depth)) in readbacks.iter().enumerate() {
        let rgba = read(&device, color)?;
        let depth = if options.samples == 1 {
            read(&device, depth)?
        } else {
            Vec::new()
        };
        runs.push(Run {
            rgba,
            depth: depth
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect(),
            last_frame: last + VIEW_STEP * v as u32,
            validation: Vec::new(),
            adapter: String::new(),
            views: Vec::new(),
        });
    }
    let mut run = runs.remove(0);
    if views > 1 {
        let first = Run {
            rgba: run.rgba.clone(),
            depth: run.depth.clone(),
            last_frame: run.last_frame,
            validation: Vec::new(),
            adapter: String::new(),
            views: Vec::new(),
        };
        run.views = std::iter::once(first).chain(runs).collect();
    }
    Ok(run)
}

/// The application's own pass: clear, and the plane if it draws one (resolved into the
/// one-sample colour when multisampled).
fn draw_scene(encoder: &mut wgpu::CommandEncoder, slot: &Slot, plane: Option<&PlanePass>) {
    let target = slot.target();
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("scene"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target.color,
            depth_slice: None,
            resolve_target: target.resolve,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(scene::CLEAR_COLOR),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: target.depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        ..Default::default()
    });
    if let Some(plane) = plane {
        plane.draw(&mut pass);
    }
}

/// Copies the slot's colour and (at one sample) depth into the readback buffers (rows
/// of 512 bytes, a multiple of wgpu's 256).
fn copy_out(
    encoder: &mut wgpu::CommandEncoder,
    slot: &Slot,
    color: &wgpu::Buffer,
    depth: &wgpu::Buffer,
    samples: u32,
) {
    let size = wgpu::Extent3d {
        width: WIDTH,
        height: HEIGHT,
        depth_or_array_layers: 1,
    };
    let copies = [
        (&slot.color, color, wgpu::TextureAspect::All),
        (&slot.depth, depth, wgpu::TextureAspect::DepthOnly),
    ];
    let count = if samples == 1 { 2 } else { 1 };
    for (texture, buffer, aspect) in copies.into_iter().take(count) {
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect,
            },
            wgpu::TexelCopyBufferInfo {
                buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * WIDTH),
                    rows_per_image: Some(HEIGHT),
                },
            },
            size,
        );
    }
}

/// A readback buffer's bytes, once the GPU has written them.
fn read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
    let slice = buffer.slice(..);
    let (send, receive) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        let _ = send.send(result);
    });
    device.poll(wgpu::PollType::wait_indefinitely())?;
    receive.recv()??;
    // (wgpu 30 reports a failed mapping here; wgpu 29 panics.)
    #[cfg(feature = "wgpu30")]
    let bytes = slice.get_mapped_range()?.to_vec();
    #[cfg(not(feature = "wgpu30"))]
    let bytes = slice.get_mapped_range().to_vec();
    buffer.unmap();
    Ok(bytes)
}
