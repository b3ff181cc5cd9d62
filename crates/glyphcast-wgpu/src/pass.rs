//! The glyphs of one wgpu target configuration: the core's [`GlyphRenderer`] on wgpu's
//! Vulkan device, fed wgpu's textures and wgpu's camera convention.
//!
//! Frames in flight without fences: wgpu applications never see a fence, so each frame
//! slot remembers whether the command buffer that read its frame block may still run. The
//! slot's flag is set when its commands are encoded and cleared by a guard that the raw
//! encoder's `on_submitted_work_done` callback owns: run when the GPU has finished the
//! submission, or dropped with a command buffer that was never submitted. Beginning a
//! slot whose flag is still set polls the device until it clears, which is the wait a
//! Vulkan engine does on the slot's fence.
use crate::device::{has_sample_rate_shading, not_vulkan};
use crate::target::{Attachments, record_glyph_pass};
use crate::{Error, Result};
use glam::DMat4;
use glyphcast::ash::vk;
use glyphcast::gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use glyphcast::{
    DepthConvention, DeviceContext, GlyphRenderer, GlyphSetData, HostView, PassOptions, RenderPath,
    RenderSettings, RendererDesc, TargetFormats,
};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use wgpu::hal::api::Vulkan;

/// What the application decides once: its targets' formats and samples, its depth
/// convention, how many frames it lets wgpu run ahead, and how the glyphs are drawn.
#[derive(Clone, Debug)]
pub struct GlyphPassDesc {
    /// The colour texture's format (any colour-renderable format).
    pub color_format: wgpu::TextureFormat,
    /// The depth texture's format: `Depth32Float`, `Depth24Plus`, or one with stencil,
    /// whose stencil the glyphs leave as it is.
    pub depth_format: wgpu::TextureFormat,
    /// Samples per pixel of both textures: 1, 2, 4 or 8.
    pub samples: u32,
    /// Which end of the depth range is near: what the application clears depth to and
    /// compares with (`Standard`: cleared to 1, `Less`; `Reversed`: cleared to 0,
    /// `Greater`). Glyph depth is written in it.
    pub depth: DepthConvention,
    /// Frame slots: how many frames may be encoded before the first has finished. A
    /// slot still running when its turn comes again is waited for.
    pub frames_in_flight: usize,
    /// How the glyphs are drawn (method, march, colour, lighting), by the fragment ray
    /// caster (`path` fragment, or auto, which takes it here).
    pub settings: RenderSettings,
}

impl Default for GlyphPassDesc {
    /// An sRGB colour target and a float depth buffer of one sample, standard depth, two
    /// frames in flight, glyphcast's default settings.
    fn default() -> Self {
        GlyphPassDesc {
            color_format: wgpu::TextureFormat::Rgba8UnormSrgb,
            depth_format: wgpu::TextureFormat::Depth32Float,
            samples: 1,
            depth: DepthConvention::Standard,
            frames_in_flight: 2,
            settings: RenderSettings::default(),
        }
    }
}

/// The application's camera, in wgpu's conventions: a right-handed view matrix (world to
/// view: a rotation and a translation) and a projection to wgpu's clip space (y up, depth
/// 0 to 1 in the pass's depth convention), centred, perspective or orthographic: the
/// matrices its own shaders draw with.
#[derive(Clone, Copy, Debug)]
pub struct WgpuCamera {
    /// World to view space.
    pub view: DMat4,
    /// View to wgpu clip space.
    pub projection: DMat4,
}

impl WgpuCamera {
    /// The camera of an application's `f32` matrices (wgpu and Bevy hold `glam::Mat4`):
    /// world to view, and view to wgpu clip space.
    pub fn from_f32(view: glam::Mat4, projection: glam::Mat4) -> WgpuCamera {
        WgpuCamera {
            view: view.as_dmat4(),
            projection: projection.as_dmat4(),
        }
    }

    /// The camera of two column-major `f32` matrices, as any maths library gives them
    /// (`Mat4::to_cols_array_2d` of another glam version, nalgebra, cgmath): world to
    /// view, and view to wgpu clip space.
    pub fn from_columns(view: [[f32; 4]; 4], projection: [[f32; 4]; 4]) -> WgpuCamera {
        WgpuCamera::from_f32(
            glam::Mat4::from_cols_array_2d(&view),
            glam::Mat4::from_cols_array_2d(&projection),
        )
    }
}

/// The application's targets for one frame: views of a colour and a depth texture of the
/// formats and samples of [`GlyphPassDesc`], both `RENDER_ATTACHMENT` textures of one
/// size, viewing their first mip level and layer; with several samples, a one-sample
/// colour view the glyphs' frame is resolved into, if the application wants one.
#[derive(Clone, Copy, Debug)]
pub struct GlyphTarget<'a> {
    /// The colour the glyphs shade into (after what is already there).
    pub color: &'a wgpu::TextureView,
    /// The depth the glyphs test against and write.
    pub depth: &'a wgpu::TextureView,
    /// Where a multisampled colour is resolved to (averaged) at the end of the pass.
    pub resolve: Option<&'a wgpu::TextureView>,
}

/// One frame slot: whether its last commands may still run, and the views they draw
/// into, kept alive until then.
#[derive(Default)]
struct FrameSlot {
    in_flight: Arc<AtomicBool>,
    views: Vec<wgpu::TextureView>,
}

/// Clears its slot's flag when dropped: after the GPU finished (the callback ran), or
/// with a command buffer that was never submitted (which no GPU will run).
struct SlotRelease(Arc<AtomicBool>);

impl Drop for SlotRelease {
    fn drop(&mut self) {
        self.0.store(false, Ordering::Release);
    }
}

/// glyphcast's glyphs in a wgpu application: made once per target configuration from
/// the application's adapter and device; each frame, [`GlyphPass::encode`] gives the
/// command buffers that draw the glyphs into the application's colour and depth
/// textures, depth-tested against what it drew there and writing glyph depth for its
/// later passes.
pub struct GlyphPass {
    // Fields drop in order: the renderer's buffers and pipelines, then glyphcast's
    // context and its allocator (which frees its memory), and last the wgpu device,
    // which keeps the Vulkan device alive until then.
    renderer: GlyphRenderer,
    _context: DeviceContext,
    slots: Vec<FrameSlot>,
    next_slot: usize,
    /// The most views a frame has had: frame indices 0 to `views_per_frame` x frames in
    /// flight are in use (view v of slot k draws with index v x frames + k).
    views_per_frame: usize,
    formats: (vk::Format, vk::Format),
    desc: GlyphPassDesc,
    device: wgpu::Device,
}

impl GlyphPass {
    /// Glyphs for `device`'s targets of `desc`'s formats. Refuses a device of another
    /// backend than Vulkan, an adapter that lacks a feature glyphcast needs, and formats
    /// or samples that cannot be drawn into, with an [`Error`] that names them.
    ///
    /// # Safety
    /// `device` was created from `adapter` with the features of
    /// [`REQUIRED_VULKAN_FEATURES`](crate::REQUIRED_VULKAN_FEATURES) enabled: by
    /// [`request_device`](crate::request_device), or by a device-creation callback that
    /// called [`enable_features`](crate::enable_features). (wgpu keeps no record of the
    /// Vulkan features it enabled, so this cannot be checked.) The application keeps
    /// each frame's textures alive (it does not `destroy` them) until that frame's
    /// command buffers have run.
    pub unsafe fn new(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        desc: &GlyphPassDesc,
    ) -> Result<GlyphPass> {
        let features = device.features();
        crate::check_adapter(adapter, features)?;
        if desc.settings.path == RenderPath::Compute {
            return Err(Error::ComputePath);
        }
        if ![1, 2, 4, 8].contains(&desc.samples) {
            return Err(Error::Samples(desc.samples));
        }
        if desc.samples > 1 && !has_sample_rate_shading(adapter, features) {
            return Err(Error::MissingFeatures {
                adapter: adapter.get_info().name,
                missing: "sampleRateShading (for multisampled targets)".into(),
            });
        }
        let formats = vulkan_formats(adapter, desc)?;
        let context = context_of(adapter, device)?;
        let renderer_desc = RendererDesc {
            formats: TargetFormats {
                color: formats.0,
                depth: formats.1,
                distance: None,
            },
            options: PassOptions {
                samples: vk::SampleCountFlags::from_raw(desc.samples),
                depth: desc.depth,
                ..PassOptions::default()
            },
            frames_in_flight: desc.frames_in_flight,
            // The pass records the fragment path (`auto` takes it here: the compute path's
            // dispatches are not recorded in wgpu's frame).
            settings: RenderSettings {
                path: RenderPath::Fragment,
                ..desc.settings
            },
        };
        let renderer = GlyphRenderer::new(&context, &renderer_desc)?;
        Ok(GlyphPass {
            renderer,
            _context: context,
            slots: (0..desc.frames_in_flight)
                .map(|_| FrameSlot::default())
                .collect(),
            next_slot: 0,
            views_per_frame: 1,
            formats,
            desc: desc.clone(),
            device: device.clone(),
        })
    }

    /// Uploads new glyphs (and makes the pipelines they need) for the frames encoded
    /// after; frames already encoded keep the old ones, which are released once no slot
    /// can read them.
    pub fn set_glyphs(&mut self, sets: &[GlyphSetData]) -> Result<()> {
        Ok(self.renderer.set_glyphs(sets)?)
    }

    /// [`GlyphPass::set_glyphs`] of glyph sets as the application builds them
    /// ([`GlyphSet::from_arrays`](glyphcast::GlyphSet::from_arrays)), prepared with the
    /// pass's settings (their `offset`); no scene or camera is needed.
    pub fn set_glyph_sets(&mut self, sets: &[glyphcast::GlyphSet]) -> Result<()> {
        let offset = f64::from(self.renderer.settings().offset);
        let prepared = sets
            .iter()
            .enumerate()
            .map(|(index, set)| glyphcast::render::glyph_data::prepare_set(set, index, offset))
            .collect::<glyphcast::Result<Vec<_>>>()?;
        self.set_glyphs(&prepared)
    }

    /// The command buffers that draw the glyphs seen by `camera` into `target`: submit
    /// both, in this order, after the commands that drew the scene there and before
    /// those that read the result. The first has wgpu put the textures into the
    /// attachment states the second (raw Vulkan commands) expects; the second leaves
    /// them there, as wgpu then believes them to be. Waits first, if this frame's slot
    /// is still running from `frames_in_flight` frames ago. One view per frame; a frame
    /// of several views is [`GlyphPass::encode_views`].
    pub fn encode(
        &mut self,
        camera: &WgpuCamera,
        target: &GlyphTarget<'_>,
    ) -> Result<[wgpu::CommandBuffer; 2]> {
        self.encode_views(&[(*camera, *target)])
    }

    /// [`GlyphPass::encode`] of a frame of several views (a split screen, an editor's
    /// viewports, a picture-in-picture): each its own camera and target, drawn in turn
    /// by the second command buffer. Any number of views per frame, independent of
    /// `frames_in_flight`, which still counts frames: each view of a frame in flight
    /// keeps its own frame block (the pass adds blocks when a frame has more views than
    /// any before).
    pub fn encode_views(
        &mut self,
        views: &[(WgpuCamera, GlyphTarget<'_>)],
    ) -> Result<[wgpu::CommandBuffer; 2]> {
        let attachments = views
            .iter()
            .map(|(_, target)| self.attachments(target))
            .collect::<Result<Vec<_>>>()?;
        let k = self.next_slot;
        self.wait_for_slot(k)?;
        let frames = self.slots.len();
        if views.len() > self.views_per_frame {
            // View v of frame slot k draws with frame index v * frames + k: the indices
            // of the views before stay as they are, in flight or not.
            self.renderer.set_frames_in_flight(frames * views.len())?;
            self.views_per_frame = views.len();
        }
        let index = |v: usize| v * frames + k;
        for (v, ((camera, _), attachments)) in views.iter().zip(&attachments).enumerate() {
            let host_view = HostView::whole(
                camera.view,
                vulkan_projection(camera.projection),
                attachments.extent.width,
                attachments.extent.height,
            );
            self.renderer.set_view(index(v), &host_view)?;
        }
        let mut states = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("glyphcast: attachment states"),
            });
        let textures = views.iter().flat_map(|(_, target)| {
            [
                (target.color.texture(), wgpu::TextureUses::COLOR_TARGET),
                (
                    target.depth.texture(),
                    wgpu::TextureUses::DEPTH_STENCIL_WRITE,
                ),
            ]
            .into_iter()
            .chain(
                target
                    .resolve
                    .map(|view| (view.texture(), wgpu::TextureUses::COLOR_TARGET)),
            )
        });
        states.transition_resources(
            std::iter::empty(),
            textures.map(|(texture, state)| wgpu::TextureTransition {
                texture,
                selector: None,
                state,
            }),
        );
        let mut glyphs = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("glyphcast: glyphs"),
            });
        let slot = &mut self.slots[k];
        slot.in_flight.store(true, Ordering::Release);
        let release = SlotRelease(slot.in_flight.clone());
        glyphs.on_submitted_work_done(move || drop(release));
        slot.views = views
            .iter()
            .flat_map(|(_, target)| {
                [target.color, target.depth]
                    .into_iter()
                    .chain(target.resolve)
            })
            .cloned()
            .collect();
        let renderer = &self.renderer;
        let device = self._context.device();
        // SAFETY: the encoder is used for raw commands only (wgpu panics when one encoder
        // mixes the two); the command buffer is recording and not ended here; the views
        // are kept alive by the slot until the commands have run.
        let recorded: Result<()> = unsafe {
            glyphs.as_hal_mut::<Vulkan, _, _>(|encoder| {
                let encoder = encoder.ok_or_else(|| not_vulkan_target("command encoder"))?;
                let cmd = encoder.raw_handle();
                for (v, attachments) in attachments.iter().enumerate() {
                    record_glyph_pass(device, cmd, attachments, |cmd| {
                        Ok(renderer.record(cmd, index(v))?)
                    })?;
                }
                Ok(())
            })
        };
        recorded?;
        self.next_slot = (k + 1) % self.slots.len();
        Ok([states.finish(), glyphs.finish()])
    }

    /// The core's renderer: its settings ([`GlyphRenderer::set_settings`]) and
    /// pipelines made ahead of time ([`GlyphRenderer::prepare`]).
    pub fn renderer_mut(&mut self) -> &mut GlyphRenderer {
        &mut self.renderer
    }

    /// The description the pass was made with.
    pub fn desc(&self) -> &GlyphPassDesc {
        &self.desc
    }

    /// Waits until slot `k`'s last commands have run, and lets go of its views.
    fn wait_for_slot(&mut self, k: usize) -> Result<()> {
        let slot = &mut self.slots[k];
        if slot.in_flight.load(Ordering::Acquire) {
            // Runs the callbacks of every submission that has finished.
            self.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| Error::Device(e.to_string()))?;
        }
        if slot.in_flight.load(Ordering::Acquire) {
            return Err(Error::FramesHeld {
                frames: self.slots.len(),
            });
        }
        slot.views.clear();
        Ok(())
    }

    /// The target's Vulkan views, checked against the pass's formats and samples.
    fn attachments(&self, target: &GlyphTarget<'_>) -> Result<Attachments> {
        let (color, depth) = (target.color.texture(), target.depth.texture());
        let desc = &self.desc;
        let checks = [
            ("colour", color, desc.color_format, desc.samples),
            ("depth", depth, desc.depth_format, desc.samples),
        ];
        for (name, texture, format, samples) in checks {
            check_texture(name, texture, format, samples)?;
        }
        if color.size() != depth.size() {
            return Err(Error::Target {
                texture: "depth",
                expected: format!("the colour texture's size, {:?}", color.size()),
                found: format!("{:?}", depth.size()),
            });
        }
        if let Some(resolve) = target.resolve {
            if desc.samples == 1 {
                return Err(Error::Target {
                    texture: "resolve",
                    expected: "absent for a one-sample target".into(),
                    found: "given".into(),
                });
            }
            let texture = resolve.texture();
            check_texture("resolve", texture, desc.color_format, 1)?;
            if texture.size() != color.size() {
                return Err(Error::Target {
                    texture: "resolve",
                    expected: format!("the colour texture's size, {:?}", color.size()),
                    found: format!("{:?}", texture.size()),
                });
            }
        }
        let raw_view = |view: &wgpu::TextureView| {
            // SAFETY: only the handle is read; the slot keeps the view alive while the
            // commands that use it may run.
            unsafe { view.as_hal::<Vulkan>() }
                .map(|v| unsafe { v.raw_handle() })
                .ok_or_else(|| not_vulkan_target("texture view"))
        };
        let image = |texture: &wgpu::Texture| {
            // SAFETY: as above.
            unsafe { texture.as_hal::<Vulkan>() }
                .map(|t| unsafe { t.raw_handle() })
                .ok_or_else(|| not_vulkan_target("texture"))
        };
        Ok(Attachments {
            color: (image(color)?, raw_view(target.color)?),
            depth: (image(depth)?, raw_view(target.depth)?),
            resolve: match target.resolve {
                Some(view) => Some((image(view.texture())?, raw_view(view)?)),
                None => None,
            },
            depth_format: self.formats.1,
            extent: vk::Extent2D {
                width: color.width(),
                height: color.height(),
            },
        })
    }
}

impl Drop for GlyphPass {
    /// Waits for the frames still in flight, whose commands read the glyphs' buffers.
    fn drop(&mut self) {
        for k in 0..self.slots.len() {
            let _ = self.wait_for_slot(k);
        }
    }
}

/// The error for a wgpu object (`what`) of another backend than Vulkan.
fn not_vulkan_target(what: &'static str) -> Error {
    Error::Target {
        texture: "target's",
        expected: "a Vulkan object".into(),
        found: format!("a {what} of another backend"),
    }
}

/// A texture of the target refused unless it is a render attachment of `format` and
/// `samples`.
fn check_texture(
    name: &'static str,
    texture: &wgpu::Texture,
    format: wgpu::TextureFormat,
    samples: u32,
) -> Result<()> {
    if texture.format() != format {
        return Err(Error::Target {
            texture: name,
            expected: format!("{format:?} (the pass's format)"),
            found: format!("{:?}", texture.format()),
        });
    }
    if texture.sample_count() != samples {
        return Err(Error::Target {
            texture: name,
            expected: format!("{samples} sample(s) per pixel (the pass's)"),
            found: format!("{} sample(s)", texture.sample_count()),
        });
    }
    if !texture
        .usage()
        .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
    {
        return Err(Error::Target {
            texture: name,
            expected: "a texture with RENDER_ATTACHMENT usage".into(),
            found: format!("one with usage {:?}", texture.usage()),
        });
    }
    Ok(())
}

/// wgpu's clip space has y up; Vulkan's, which glyphcast's rays are built for, y down
/// (wgpu's Vulkan backend flips its viewports instead). Depth is alike.
fn vulkan_projection(projection: DMat4) -> DMat4 {
    DMat4::from_diagonal(glam::DVec4::new(1.0, -1.0, 1.0, 1.0)) * projection
}

/// The Vulkan formats wgpu gives `desc`'s textures on this adapter (`Depth24Plus` is
/// whichever depth format the device has), refusing formats glyphcast cannot draw.
fn vulkan_formats(
    adapter: &wgpu::Adapter,
    desc: &GlyphPassDesc,
) -> Result<(vk::Format, vk::Format)> {
    if desc.color_format.is_depth_stencil_format() || desc.color_format.is_compressed() {
        return Err(Error::Target {
            texture: "colour",
            expected: "of a colour-renderable format".into(),
            found: format!("{:?}", desc.color_format),
        });
    }
    if !desc.depth_format.has_depth_aspect() {
        return Err(Error::Target {
            texture: "depth",
            expected: "of a format with depth".into(),
            found: format!("{:?}", desc.depth_format),
        });
    }
    // SAFETY: the hal adapter is only read.
    let hal = unsafe { adapter.as_hal::<Vulkan>() }.ok_or_else(|| not_vulkan(adapter))?;
    Ok((
        hal.texture_format_as_raw(desc.color_format),
        hal.texture_format_as_raw(desc.depth_format),
    ))
}

/// glyphcast's context on wgpu's Vulkan device, with a gpu-allocator allocator of its own
/// for the glyphs' buffers.
fn context_of(adapter: &wgpu::Adapter, device: &wgpu::Device) -> Result<DeviceContext> {
    // SAFETY: the hal device is only read; its handles outlive the context because the
    // pass that holds the context holds a clone of `device`, dropped last.
    let hal = unsafe { device.as_hal::<Vulkan>() }.ok_or_else(|| not_vulkan(adapter))?;
    let instance = hal.shared_instance().raw_instance().clone();
    let physical_device = hal.raw_physical_device();
    let raw = hal.raw_device().clone();
    let allocator = Allocator::new(&AllocatorCreateDesc {
        instance: instance.clone(),
        device: raw.clone(),
        physical_device,
        debug_settings: Default::default(),
        buffer_device_address: false,
        allocation_sizes: Default::default(),
    })
    .map_err(|e| Error::Device(format!("glyphcast's memory allocator: {e}")))?;
    // SAFETY: the device was made from this physical device and instance (with the
    // features glyphcast needs: `GlyphPass::new`'s promise); the allocator allocates for
    // it; the pass drops the context and allocator before its clone of the wgpu device.
    let context = unsafe {
        DeviceContext::new(
            &instance,
            physical_device,
            raw,
            Arc::new(Mutex::new(allocator)),
        )
    };
    if crate::device::enables_fragment_stores(adapter, device.features()) {
        // SAFETY: wgpu-hal created the device with the core features it computes for
        // the device's wgpu features, which include fragmentStoresAndAtomics.
        return Ok(unsafe { context.with_fragment_stores() });
    }
    Ok(context)
}
