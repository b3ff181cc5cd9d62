//! The C API of glyphcast's engine component ([`glyphcast::GlyphRenderer`]): a C or C++
//! engine passes its Vulkan handles (instance, physical device, device, the loader's
//! `vkGetInstanceProcAddr`), formats, samples, depth convention, pipeline cache and frames
//! in flight once, then per frame its camera and an open command buffer. The header is
//! `include/glyphcast.h`, generated from this file by cbindgen.
//!
//! Every entry point returns a [`GlyphcastStatus`]; the message of the last failure is
//! kept per renderer ([`glyphcast_renderer_last_error`]) and per thread for calls with no
//! renderer ([`glyphcast_last_error`]). Every entry point catches panics, so none crosses
//! into C (it is reported as [`GlyphcastStatus::Panic`]). Memory comes from the host's
//! allocation callbacks ([`GlyphcastAllocator`]) if it gives them, else from a
//! gpu-allocator allocator that the renderer makes on the host's device.
#![warn(missing_docs)]
#![allow(non_camel_case_types)]
use ash::vk;
use ash::vk::Handle;
use glam::DMat4;
use glyphcast::vk::{MemoryAllocator, MemoryBlock, MemoryRequest, MemoryUse};
use glyphcast::{
    DepthConvention, DeviceContext, GlyphKind, GlyphRenderer, GlyphSet, HostView, PassOptions,
    RenderSettings, RendererDesc, ShBasis, TargetFormats,
};
use gpu_allocator::vulkan::Allocator;
use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Arc, Mutex};

// The Vulkan types as the C header names them (vulkan.h declares them; cbindgen.toml
// keeps these aliases out of the header).
/// A dispatchable Vulkan handle: a pointer.
pub type VkInstance = *mut c_void;
/// A dispatchable Vulkan handle: a pointer.
pub type VkPhysicalDevice = *mut c_void;
/// A dispatchable Vulkan handle: a pointer.
pub type VkDevice = *mut c_void;
/// A dispatchable Vulkan handle: a pointer.
pub type VkCommandBuffer = *mut c_void;
/// A non-dispatchable Vulkan handle: a 64-bit value, 0 for VK_NULL_HANDLE.
pub type VkPipelineCache = u64;
/// A non-dispatchable Vulkan handle: a 64-bit value, 0 for VK_NULL_HANDLE.
pub type VkRenderPass = u64;
/// A non-dispatchable Vulkan handle: a 64-bit value.
pub type VkDeviceMemory = u64;
/// A VkFormat enumerant.
pub type VkFormat = i32;
/// The loader's vkGetInstanceProcAddr, NULL when absent.
pub type PFN_vkGetInstanceProcAddr = Option<GetInstanceProcAddr>;
/// vkGetInstanceProcAddr with the instance as a plain pointer.
type GetInstanceProcAddr =
    unsafe extern "system" fn(VkInstance, *const c_char) -> Option<unsafe extern "system" fn()>;

/// What a call returns.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastStatus {
    /// Done.
    Ok = 0,
    /// An argument was refused (a null pointer, an out-of-range value, glyph data or a
    /// camera glyphcast cannot draw); the message says which.
    InvalidArgument = 1,
    /// A Vulkan call failed, or the device lacks something glyphcast needs.
    Vulkan = 2,
    /// glyphcast panicked (a bug); the renderer should not be used again.
    Panic = 3,
}

/// The host's depth convention.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastDepth {
    /// Near at 0, far at 1 (or infinity): cleared to 1, tested LESS.
    Standard = 0,
    /// Near at 1, far at 0 (or infinity): cleared to 0, tested GREATER.
    Reversed = 1,
}

/// How glyph surfaces are found ([`GlyphcastSettings::method`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastMethod {
    /// Exact intersection: the roots of the ray polynomial, isolated (the default).
    Exact = 0,
    /// The paper's fixed-step march with a sign test, refined.
    Fixed = 1,
    /// March over segments whose range is bounded by interval arithmetic.
    Interval = 2,
    /// March over segments whose range is bounded by affine arithmetic.
    Affine = 3,
}

/// How surface points are coloured ([`GlyphcastSettings::color`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastColor {
    /// The paper's |p|: absolute components of the direction from the glyph's centre.
    Direction = 0,
    /// A perceptual colour map of the distance from the centre over
    /// [`GlyphcastSettings::magnitude_range`].
    Magnitude = 1,
    /// One colour, [`GlyphcastSettings::uniform_color`].
    Uniform = 2,
    /// Red where the glyph function is positive, blue where it is negative.
    Sign = 3,
}

/// How negative values of a glyph's function are drawn ([`GlyphcastSettings::negative`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastNegative {
    /// As their absolute value (the default).
    Abs = 0,
    /// Not at all.
    Hide = 1,
}

/// The spherical-harmonic basis of [`glyphcast_renderer_set_sh_glyphs`]' coefficients.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastShBasis {
    /// DIPY's basis, `descoteaux07`; with `legacy` 1 the one DIPY uses by default.
    Descoteaux07 = 0,
    /// MRtrix3's basis, `tournier07`; with `legacy` 1 MRtrix's older variant, as DIPY
    /// names it.
    Tournier07 = 1,
}

/// The render settings of a renderer. Fill it with [`glyphcast_settings_default`], then
/// change what the host wants: fields the host's header did not have yet (a smaller
/// `size`) keep their defaults, so the struct can grow without breaking the ABI.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlyphcastSettings {
    /// `sizeof(GlyphcastSettings)` as the host compiled it.
    pub size: u32,
    /// A [`GlyphcastMethod`].
    pub method: u32,
    /// A [`GlyphcastColor`].
    pub color: u32,
    /// With [`GlyphcastColor::Uniform`]: linear RGB, each 0 to 1.
    pub uniform_color: [f32; 3],
    /// With [`GlyphcastColor::Magnitude`]: the distances (world units) at the two ends
    /// of the map, low below high; both 0: 0 to the largest glyph's radius.
    pub magnitude_range: [f32; 2],
    /// A [`GlyphcastNegative`]: how the glyphs of later `set_*_glyphs` calls draw their
    /// negative lobes.
    pub negative: u32,
    /// Direction towards the light in view coordinates (x right, y up, z towards the
    /// viewer), any length above 0.
    pub light: [f32; 3],
    /// The share of the base colour lit whatever the normal, 0 to 1.
    pub ambient: f32,
    /// Strength of the white highlight, 0 to 1.
    pub specular: f32,
    /// Blinn-Phong exponent of the highlight, 1 to 1024.
    pub shininess: f32,
    /// With [`GlyphcastMethod::Fixed`]: the march step in units of each glyph's bounding
    /// radius, 0.001 to 2.
    pub step: f32,
    /// With [`GlyphcastMethod::Interval`] or [`GlyphcastMethod::Affine`]: the segment
    /// length limit in pixels at the segment's depth, 0.01 to 64.
    pub precision: f32,
    /// With the marching methods (fixed, interval, affine): a [`GlyphcastRefine`], how
    /// the first sign change is refined.
    pub refine: u32,
    /// The steps of [`GlyphcastRefine::Secant`] or [`GlyphcastRefine::Bisect`], 0 to 16.
    pub refine_steps: u32,
    /// An isotropic offset added to every glyph, as a fraction of its bounding radius
    /// (0 or more; not with [`GlyphcastMethod::Exact`]).
    pub offset: f32,
    /// A [`GlyphcastShadows`]: shadows the glyphs cast on themselves and the other glyphs
    /// of their set (with [`GlyphcastMethod::Exact`] only).
    pub shadows: u32,
    /// With [`GlyphcastShadows::Soft`]: the light's angular radius in degrees, above 0
    /// and at most 30.
    pub shadow_radius: f32,
    /// Ambient occlusion (with [`GlyphcastMethod::Exact`] only): 0 none (the default),
    /// else how far the 16 occlusion rays of each hit reach, in bounding radii of the hit
    /// glyph, above 0 and at most 16 (1 reaches the neighbours of glyphs that touch).
    pub ambient_occlusion: f32,
    /// A [`GlyphcastPath`]: the ray caster the renderer records (with
    /// [`GlyphcastMethod::Exact`] only for the compute ray caster).
    pub path: u32,
    /// A [`GlyphcastProxy`]: what the fragment path draws around each glyph (the box's
    /// image with the hull; the same surface with the pieces). A host compiled before
    /// this field draws boxes.
    pub proxy: u32,
}

/// What the fragment path draws around each glyph ([`GlyphcastSettings::proxy`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastProxy {
    /// The default: the front faces of the glyph's oriented box, the paper's proxy.
    Box = 0,
    /// An octagon around the outline of the glyph's guaranteed 26-sided polytope, at its
    /// nearest depth: fewer fragments than the box, pipelines slower to create.
    Hull = 1,
    /// An octagon around each of the glyph's eight pieces, each ray clipped to its piece
    /// (the exact method's polynomial glyphs; the others draw the hull): fewer root
    /// isolations, eight times the vertices. The renderer cuts each glyph's 26-sided
    /// polytope into its box's octants.
    Pieces = 2,
}

/// The ray caster a renderer records ([`GlyphcastSettings::path`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastPath {
    /// The default: on a GPU (one sample, no shadows or occlusion), the compute path in
    /// the frames whose dispatches the host records with
    /// [`glyphcast_renderer_record_compute`] before its rendering, from the
    /// `set_view` after its first call; the fragment path in every other frame and on
    /// other devices (lavapipe).
    Auto = 0,
    /// Proxy boxes drawn in the host's rendering by [`glyphcast_renderer_record`].
    Fragment = 1,
    /// The compute ray caster: [`glyphcast_renderer_record_compute`] records its
    /// dispatches before the host's rendering, [`glyphcast_renderer_record`] draws their
    /// outputs into the host's attachments inside it, depth-tested.
    Compute = 2,
}

/// Shadows the glyphs cast ([`GlyphcastSettings::shadows`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastShadows {
    /// None (the default).
    Off = 0,
    /// One exact ray from each hit towards the light.
    Hard = 1,
    /// 16 exact rays towards a disc light of angular radius
    /// [`GlyphcastSettings::shadow_radius`].
    Soft = 2,
}

/// How the marching methods refine the first sign change ([`GlyphcastSettings::refine`]).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastRefine {
    /// Regula falsi (Illinois) steps from the bracket (the default, 4 steps).
    Secant = 0,
    /// Bisection steps, then the bracket's midpoint.
    Bisect = 1,
    /// One linear interpolation of the bracket.
    Interp = 2,
    /// The first sample inside the glyph.
    None = 3,
}

/// What the host passes once.
#[repr(C)]
pub struct GlyphcastRendererDesc {
    /// The loader's vkGetInstanceProcAddr (glyphcast loads every function through it).
    pub get_instance_proc_addr: PFN_vkGetInstanceProcAddr,
    /// The host's instance, which the host keeps until the renderer is destroyed.
    pub instance: VkInstance,
    /// The physical device `device` was made from.
    pub physical_device: VkPhysicalDevice,
    /// A Vulkan 1.3 device with dynamicRendering (and sampleRateShading when samples > 1). Its glyphs are drawn without culling hidden ones, by fragment shaders that write no buffer, whether or not it enabled fragmentStoresAndAtomics.
    pub device: VkDevice,
    /// The colour attachment's format.
    pub color_format: VkFormat,
    /// The depth attachment's format.
    pub depth_format: VkFormat,
    /// Samples per pixel of the attachments: 1, 2, 4 or 8.
    pub samples: u32,
    /// Which way the host's depth runs.
    pub depth: GlyphcastDepth,
    /// A pipeline cache of the host's, or VK_NULL_HANDLE.
    pub pipeline_cache: VkPipelineCache,
    /// How many frames the host records ahead of the GPU (frame indices 0 to n - 1).
    pub frames_in_flight: u32,
    /// A render pass of the host's and the subpass the glyphs are drawn in (attachments
    /// of the formats and samples above), or VK_NULL_HANDLE for dynamic rendering.
    pub render_pass: VkRenderPass,
    /// The subpass of `render_pass`.
    pub subpass: u32,
    /// The host's allocation callbacks, copied at creation, or NULL: glyphcast then makes
    /// a gpu-allocator allocator on the device.
    pub allocator: *const GlyphcastAllocator,
    /// The render settings, copied at creation, or NULL for the defaults
    /// ([`glyphcast_settings_default`]).
    pub settings: *const GlyphcastSettings,
}

/// What a block of memory is for.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphcastMemoryUse {
    /// Read by the GPU only (images).
    DeviceLocal = 0,
    /// Written by the host through `mapped`, read by the GPU (glyph data, frame blocks).
    Upload = 1,
    /// Written by the GPU, read by the host through `mapped`.
    Readback = 2,
}

/// One allocation glyphcast asks the host for.
#[repr(C)]
pub struct GlyphcastMemoryRequest {
    /// A label (NUL-terminated, valid during the call).
    pub name: *const c_char,
    /// Bytes needed (the buffer's or image's VkMemoryRequirements::size).
    pub size: u64,
    /// The block's offset must be a multiple of this (VkMemoryRequirements::alignment).
    pub alignment: u64,
    /// The memory types that may hold it, one bit per type index
    /// (VkMemoryRequirements::memoryTypeBits).
    pub memory_type_bits: u32,
    /// Who writes and reads the memory.
    pub usage: GlyphcastMemoryUse,
    /// VkMemoryPropertyFlags the memory type must have (host-visible memory must be
    /// coherent: glyphcast neither flushes nor invalidates).
    pub required_flags: u32,
    /// VkMemoryPropertyFlags the memory type should have where one offers them.
    pub preferred_flags: u32,
    /// 1 for a buffer, 0 for an optimal-tiling image (bufferImageGranularity).
    pub linear: u32,
}

/// A block of memory the host hands out.
#[repr(C)]
pub struct GlyphcastMemoryBlock {
    /// The VkDeviceMemory the block lies in.
    pub memory: VkDeviceMemory,
    /// A multiple of the request's alignment.
    pub offset: u64,
    /// At least the request's size.
    pub size: u64,
    /// The host address of the block's first byte for the Upload and Readback uses
    /// (mapped until the block is freed); NULL for DeviceLocal.
    pub mapped: *mut c_void,
    /// The host's own name for the block, handed back to `free`.
    pub token: u64,
}

/// The host's allocation callbacks. glyphcast calls them only inside
/// `glyphcast_renderer_create`, `_set_sh_glyphs`, `_set_tensor_glyphs`, `_set_view`
/// (which frees retired glyphs) and `_destroy`, on the calling thread.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct GlyphcastAllocator {
    /// Passed to both callbacks.
    pub user: *mut c_void,
    /// Fills `*block` for `*request` and returns GLYPHCAST_STATUS_OK, or returns another
    /// status (out of memory: GLYPHCAST_STATUS_VULKAN).
    pub allocate: Option<
        unsafe extern "C" fn(
            user: *mut c_void,
            request: *const GlyphcastMemoryRequest,
            block: *mut GlyphcastMemoryBlock,
        ) -> GlyphcastStatus,
    >,
    /// Takes back a block (its buffer or image is destroyed, and the GPU is done with it).
    pub free: Option<unsafe extern "C" fn(user: *mut c_void, block: *const GlyphcastMemoryBlock)>,
}

/// The host's callbacks as glyphcast's [`MemoryAllocator`].
struct HostMemory(GlyphcastAllocator);

// SAFETY: glyphcast calls the callbacks only from the C entry points listed on
// `GlyphcastAllocator`, which the host calls for one renderer from one thread at a time
// (they take the renderer mutably); the host vouches for `user` on that thread.
unsafe impl Send for HostMemory {}
// SAFETY: as above.
unsafe impl Sync for HostMemory {}

impl MemoryAllocator for HostMemory {
    fn allocate(&self, request: &MemoryRequest<'_>) -> glyphcast::Result<MemoryBlock> {
        let allocate = self.0.allocate.ok_or(glyphcast::Error::Setup {
            missing: "allocate callback of the host's allocator (it is NULL)",
            found: None,
        })?;
        let name = message(request.name);
        let usage = match request.usage {
            MemoryUse::DeviceLocal => GlyphcastMemoryUse::DeviceLocal,
            MemoryUse::Upload => GlyphcastMemoryUse::Upload,
            MemoryUse::Readback => GlyphcastMemoryUse::Readback,
        };
        let c_request = GlyphcastMemoryRequest {
            name: name.as_ptr(),
            size: request.requirements.size,
            alignment: request.requirements.alignment,
            memory_type_bits: request.requirements.memory_type_bits,
            usage,
            required_flags: request.usage.required_flags().as_raw(),
            preferred_flags: request.usage.preferred_flags().as_raw(),
            linear: u32::from(request.linear),
        };
        let mut block = GlyphcastMemoryBlock {
            memory: 0,
            offset: 0,
            size: 0,
            mapped: std::ptr::null_mut(),
            token: 0,
        };
        // SAFETY: the host's callback, with valid pointers for the call.
        let status = unsafe { allocate(self.0.user, &c_request, &mut block) };
        if status != GlyphcastStatus::Ok {
            return Err(glyphcast::Error::setup(
                "memory from the host's allocator",
                format_args!(
                    "{}: it refused {} bytes ({status:?})",
                    request.name, request.requirements.size
                ),
            ));
        }
        Ok(MemoryBlock {
            memory: vk::DeviceMemory::from_raw(block.memory),
            offset: block.offset,
            size: block.size,
            mapped: block.mapped.cast(),
            token: block.token,
        })
    }

    fn free(&self, block: MemoryBlock) {
        let Some(free) = self.0.free else {
            return;
        };
        let c_block = GlyphcastMemoryBlock {
            memory: block.memory.as_raw(),
            offset: block.offset,
            size: block.size,
            mapped: block.mapped.cast(),
            token: block.token,
        };
        // SAFETY: the host's callback, with a block it handed out.
        unsafe { free(self.0.user, &c_block) };
    }
}

/// The rectangle a frame is drawn in (viewport and scissor), in framebuffer pixels.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GlyphcastViewport {
    /// Left edge.
    pub x: i32,
    /// Top edge.
    pub y: i32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// The renderer: opaque to C.
pub struct GlyphcastRenderer {
    // Dropped in order: the renderer before the context, the allocator last.
    renderer: GlyphRenderer,
    /// How the glyphs of `set_*_glyphs` draw their negative lobes.
    negative: glyphcast::NegativeMode,
    _context: DeviceContext,
    _allocator: Option<Arc<Mutex<Allocator>>>,
    last_error: Mutex<CString>,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn message(text: &str) -> CString {
    CString::new(text.replace('\0', " ")).unwrap_or_default()
}

/// The status of a failure, and its message kept for the thread.
fn fail(status: GlyphcastStatus, text: &str) -> GlyphcastStatus {
    LAST_ERROR.with(|e| *e.borrow_mut() = message(text));
    status
}

fn status_of(error: &glyphcast::Error) -> GlyphcastStatus {
    match error {
        glyphcast::Error::Vulkan { .. } | glyphcast::Error::Setup { .. } => GlyphcastStatus::Vulkan,
        _ => GlyphcastStatus::InvalidArgument,
    }
}

/// Runs `body` with panics caught; a failure's message goes to the thread's last error
/// and, with a renderer, to its own.
fn guarded(
    renderer: Option<&GlyphcastRenderer>,
    body: impl FnOnce() -> Result<(), (GlyphcastStatus, String)>,
) -> GlyphcastStatus {
    let outcome = catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|_| {
        Err((
            GlyphcastStatus::Panic,
            "glyphcast panicked (a bug; please report it)".into(),
        ))
    });
    match outcome {
        Ok(()) => GlyphcastStatus::Ok,
        Err((status, text)) => {
            if let Some(r) = renderer
                && let Ok(mut last) = r.last_error.lock()
            {
                *last = message(&text);
            }
            fail(status, &text)
        }
    }
}

fn from_glyphcast(e: glyphcast::Error) -> (GlyphcastStatus, String) {
    (status_of(&e), e.to_string())
}

fn invalid(text: impl Into<String>) -> (GlyphcastStatus, String) {
    (GlyphcastStatus::InvalidArgument, text.into())
}

/// The default settings, as `glyphcast render` draws: exact intersection, colour by
/// direction, negative lobes as their absolute value, the light above, right and in
/// front of the viewer. Sets `size` to this library's `sizeof(GlyphcastSettings)`.
///
/// # Safety
/// `settings` is NULL (then nothing happens) or points to a writable struct.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_settings_default(settings: *mut GlyphcastSettings) {
    // SAFETY: the caller's promise.
    if let Some(out) = unsafe { settings.as_mut() } {
        *out = default_settings();
    }
}

fn default_settings() -> GlyphcastSettings {
    let defaults = RenderSettings::default();
    let lighting = defaults.lighting;
    GlyphcastSettings {
        size: std::mem::size_of::<GlyphcastSettings>() as u32,
        method: GlyphcastMethod::Exact as u32,
        color: GlyphcastColor::Direction as u32,
        uniform_color: [0.8, 0.8, 0.8],
        magnitude_range: [0.0, 0.0],
        negative: GlyphcastNegative::Abs as u32,
        light: lighting.direction,
        ambient: lighting.ambient,
        specular: lighting.specular,
        shininess: lighting.shininess,
        step: defaults.step,
        precision: defaults.precision_px,
        refine: GlyphcastRefine::Secant as u32,
        refine_steps: 4,
        offset: 0.0,
        shadows: GlyphcastShadows::Off as u32,
        shadow_radius: 5.0,
        ambient_occlusion: 0.0,
        path: GlyphcastPath::Auto as u32,
        proxy: GlyphcastProxy::Box as u32,
    }
}

/// The library's settings from the host's struct (NULL: the defaults): the first `size`
/// bytes are the host's, the rest keep their defaults. Values are checked where every
/// front end's are, by [`GlyphRenderer::new`].
///
/// # Safety
/// `settings` is NULL or points to `settings.size` readable bytes.
unsafe fn read_settings(
    settings: *const GlyphcastSettings,
) -> Result<(RenderSettings, glyphcast::NegativeMode), (GlyphcastStatus, String)> {
    let mut given = default_settings();
    if !settings.is_null() {
        // SAFETY: `size` is the struct's first field; the caller's promise.
        let size = unsafe { settings.cast::<u32>().read_unaligned() } as usize;
        if size < std::mem::size_of::<u32>() {
            return Err(invalid(format!(
                "settings.size {size}: fill the settings with glyphcast_settings_default"
            )));
        }
        let known = size.min(std::mem::size_of::<GlyphcastSettings>());
        // SAFETY: the host's struct holds `size` bytes; ours at least `known`.
        unsafe {
            std::ptr::copy_nonoverlapping(
                settings.cast::<u8>(),
                (&mut given as *mut GlyphcastSettings).cast::<u8>(),
                known,
            )
        };
    }
    use glyphcast::render::Method;
    let method = match given.method {
        0 => Method::Exact,
        1 => Method::Fixed,
        2 => Method::Interval,
        3 => Method::Affine,
        other => {
            return Err(invalid(format!(
                "settings.method {other} is no GlyphcastMethod"
            )));
        }
    };
    use glyphcast::render::settings::SIGN_COLORS;
    use glyphcast::render::table::{Direction, RenderOptions, Span};
    use glyphcast::render::{ColorMode, Refinement};
    let [low, high] = given.magnitude_range;
    let color = match given.color {
        0 => ColorMode::Direction,
        1 => ColorMode::Magnitude { range: None },
        2 if given.uniform_color.iter().all(|c| (0.0..=1.0).contains(c)) => {
            ColorMode::Uniform(given.uniform_color)
        }
        2 => {
            return Err(invalid(format!(
                "settings.uniform_color {:?}: each component 0 to 1",
                given.uniform_color
            )));
        }
        3 => ColorMode::Sign {
            positive: SIGN_COLORS.0,
            negative: SIGN_COLORS.1,
        },
        other => {
            return Err(invalid(format!(
                "settings.color {other} is no GlyphcastColor"
            )));
        }
    };
    let negative = match given.negative {
        0 => glyphcast::NegativeMode::Abs,
        1 => glyphcast::NegativeMode::Hide,
        other => {
            return Err(invalid(format!(
                "settings.negative {other} is no GlyphcastNegative"
            )));
        }
    };
    let k = given.refine_steps;
    let refinement = match given.refine {
        0 => Refinement::Secant(k),
        1 => Refinement::Bisect(k),
        2 => Refinement::Interpolate,
        3 => Refinement::None,
        other => {
            return Err(invalid(format!(
                "settings.refine {other} is no GlyphcastRefine"
            )));
        }
    };
    if k > 16 {
        return Err(invalid(format!("settings.refine_steps {k}: 0 to 16")));
    }
    use glyphcast::render::Shadows;
    let shadows = match given.shadows {
        0 => Shadows::Off,
        1 => Shadows::Hard,
        2 => Shadows::Soft {
            radius_deg: given.shadow_radius,
        },
        other => {
            return Err(invalid(format!(
                "settings.shadows {other} is no GlyphcastShadows"
            )));
        }
    };
    let path = match given.path {
        0 => glyphcast::RenderPath::Auto,
        1 => glyphcast::RenderPath::Fragment,
        2 => glyphcast::RenderPath::Compute,
        other => {
            return Err(invalid(format!(
                "settings.path {other} is no GlyphcastPath"
            )));
        }
    };
    let proxy = match given.proxy {
        0 => glyphcast::render::Proxy::Box,
        1 => glyphcast::render::Proxy::Hull,
        2 => glyphcast::render::Proxy::Pieces,
        other => {
            return Err(invalid(format!(
                "settings.proxy {other} is no GlyphcastProxy"
            )));
        }
    };
    // The struct's fields are the render table's settings: the library checks them as
    // it checks the command line's flags and Python's keywords, and its errors are
    // spelled as fields here.
    let marching = method != Method::Exact;
    let options = RenderOptions {
        method: Some(method),
        color: Some(color),
        magnitude_range: (given.color == 1 && (low, high) != (0.0, 0.0))
            .then_some(Span([low, high])),
        negative: Some(negative),
        light: Some(Direction(given.light)),
        ambient: Some(given.ambient),
        specular: Some(given.specular),
        shininess: Some(given.shininess),
        step: (method == Method::Fixed).then_some(given.step),
        precision: matches!(method, Method::Interval | Method::Affine).then_some(given.precision),
        refine: marching.then_some(refinement),
        offset: Some(given.offset),
        shadows: Some(shadows),
        ambient_occlusion: Some(if given.ambient_occlusion == 0.0 {
            glyphcast::render::AmbientOcclusion::Off
        } else {
            glyphcast::render::AmbientOcclusion::On {
                reach: given.ambient_occlusion,
            }
        }),
        path: Some(path),
        proxy: Some(proxy),
        ..RenderOptions::default()
    };
    let settings = options
        .settings()
        .map_err(|e| invalid(e.spelled(&|setting, value| field(setting.key(), value))))?;
    Ok((settings, negative))
}

/// A setting as the C struct spells it: `settings.ambient 2`.
fn field(key: &str, value: Option<&str>) -> String {
    match value {
        Some(value) => format!("settings.{key} {value}"),
        None => format!("settings.{key}"),
    }
}

/// Creates a renderer on the host's device. `*out` receives it (or NULL on failure).
///
/// # Safety
/// `desc` points to a valid description whose handles are live and belong together; the
/// host keeps the instance and device (and its allocator's `user`, if it gave callbacks)
/// until `glyphcast_renderer_destroy`. `out` is writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_renderer_create(
    desc: *const GlyphcastRendererDesc,
    out: *mut *mut GlyphcastRenderer,
) -> GlyphcastStatus {
    if out.is_null() {
        return fail(GlyphcastStatus::InvalidArgument, "out is NULL");
    }
    // SAFETY: `out` is writable (the caller's promise).
    unsafe { *out = std::ptr::null_mut() };
    let mut created = None;
    let status = guarded(None, || {
        // SAFETY: the caller's promise about `desc`.
        let desc = unsafe { desc.as_ref() }.ok_or_else(|| invalid("desc is NULL"))?;
        // SAFETY: as above: the handles are live and belong together.
        created = Some(unsafe { create(desc) }?);
        Ok(())
    });
    if let Some(renderer) = created {
        // SAFETY: `out` is writable.
        unsafe { *out = Box::into_raw(Box::new(renderer)) };
    }
    status
}

/// # Safety
/// As [`glyphcast_renderer_create`].
unsafe fn create(
    desc: &GlyphcastRendererDesc,
) -> Result<GlyphcastRenderer, (GlyphcastStatus, String)> {
    let get = desc
        .get_instance_proc_addr
        .ok_or_else(|| invalid("get_instance_proc_addr is NULL"))?;
    if desc.instance.is_null() || desc.physical_device.is_null() || desc.device.is_null() {
        return Err(invalid(
            "instance, physical_device and device must not be NULL",
        ));
    }
    let static_fn = ash::StaticFn {
        // SAFETY: the loader's vkGetInstanceProcAddr has this signature (vulkan.h).
        get_instance_proc_addr: unsafe {
            std::mem::transmute::<GetInstanceProcAddr, vk::PFN_vkGetInstanceProcAddr>(get)
        },
    };
    let instance_handle = vk::Instance::from_raw(desc.instance as u64);
    // SAFETY: the host's live instance, loaded through its own loader.
    let instance = unsafe { ash::Instance::load(&static_fn, instance_handle) };
    let physical_device = vk::PhysicalDevice::from_raw(desc.physical_device as u64);
    // SAFETY: the host's live device of that instance.
    let device =
        unsafe { ash::Device::load(instance.fp_v1_0(), vk::Device::from_raw(desc.device as u64)) };
    // SAFETY: the caller's promise: NULL or valid callbacks.
    let callbacks = unsafe { desc.allocator.as_ref() }.copied();
    let (context, allocator) = match callbacks {
        Some(callbacks) => {
            if callbacks.allocate.is_none() || callbacks.free.is_none() {
                return Err(invalid("allocator: allocate and free must not be NULL"));
            }
            // SAFETY: the device comes from that physical device and instance; the
            // host's callbacks allocate for it and outlive the renderer (its promise).
            let context = unsafe {
                DeviceContext::with_memory(
                    &instance,
                    physical_device,
                    device,
                    Arc::new(HostMemory(callbacks)),
                )
            };
            (context, None)
        }
        None => {
            let allocator = glyphcast::vk::default_allocator(&instance, &device, physical_device)
                .map_err(|e| {
                (
                    GlyphcastStatus::Vulkan,
                    format!("creating the allocator: {e}"),
                )
            })?;
            let allocator = Arc::new(Mutex::new(allocator));
            // SAFETY: the device comes from that physical device and instance; the
            // allocator is ours and dropped after the renderer and context (field order).
            let context = unsafe {
                DeviceContext::new(&instance, physical_device, device, Arc::clone(&allocator))
            };
            (context, Some(allocator))
        }
    };
    // SAFETY: the caller's promise: NULL or `size` readable bytes.
    let (settings, negative) = unsafe { read_settings(desc.settings) }?;
    let depth = match desc.depth {
        GlyphcastDepth::Standard => DepthConvention::Standard,
        GlyphcastDepth::Reversed => DepthConvention::Reversed,
    };
    let renderer_desc = RendererDesc {
        formats: TargetFormats {
            color: vk::Format::from_raw(desc.color_format),
            depth: vk::Format::from_raw(desc.depth_format),
            distance: None,
        },
        options: PassOptions {
            samples: vk::SampleCountFlags::from_raw(desc.samples),
            depth,
            pipeline_cache: vk::PipelineCache::from_raw(desc.pipeline_cache),
            render_pass: vk::RenderPass::from_raw(desc.render_pass),
            subpass: desc.subpass,
        },
        frames_in_flight: desc.frames_in_flight as usize,
        settings,
    };
    let renderer = GlyphRenderer::new(&context, &renderer_desc).map_err(from_glyphcast)?;
    Ok(GlyphcastRenderer {
        renderer,
        negative,
        _context: context,
        _allocator: allocator,
        last_error: Mutex::new(CString::default()),
    })
}

/// Destroys a renderer (NULL is ignored).
///
/// # Safety
/// `renderer` came from `glyphcast_renderer_create` and is not used again; the device has
/// finished every frame recorded with it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_renderer_destroy(renderer: *mut GlyphcastRenderer) {
    if renderer.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: made by Box::into_raw in create; not used again (the caller's promise).
        drop(unsafe { Box::from_raw(renderer) });
    }));
}

/// Replaces the glyphs (for every frame in flight, without waiting) with `count` glyphs
/// of a spherical-harmonic series of even bands 0 to `band` in the basis `basis` (a
/// [`GlyphcastShBasis`]) and its legacy variant when `legacy` is 1 (DIPY's own default is
/// descoteaux07 with legacy 1; MRtrix3's is tournier07 with legacy 0), as the scene
/// format's `sh` kind stores them: `centers` holds 3 doubles per glyph, `scales` one,
/// `coefficients` (band + 1)(band + 2) / 2 per glyph.
///
/// # Safety
/// `renderer` is live; the arrays hold `count` glyphs' values.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_renderer_set_sh_glyphs(
    renderer: *mut GlyphcastRenderer,
    band: u32,
    basis: u32,
    legacy: u32,
    count: u32,
    centers: *const f64,
    scales: *const f64,
    coefficients: *const f64,
) -> GlyphcastStatus {
    let basis = match basis {
        0 => Ok(ShBasis::Descoteaux07),
        1 => Ok(ShBasis::Tournier07),
        other => Err(format!("basis {other} is no GlyphcastShBasis")),
    };
    let kind = match (basis, legacy) {
        (Err(e), _) => Err(e),
        (_, 2..) => Err(format!("legacy {legacy}: 0 or 1")),
        (Ok(_), _) if !band.is_multiple_of(2) || band > glyphcast::catalog::MAX_SH_BAND => {
            Err(format!(
                "band {band}: glyphcast draws even bands 0 to {}",
                glyphcast::catalog::MAX_SH_BAND
            ))
        }
        (Ok(basis), _) => Ok(GlyphKind::Sh {
            band,
            basis,
            legacy: legacy == 1,
        }),
    };
    // SAFETY: the caller's promise.
    unsafe { set_glyphs(renderer, kind, count, (centers, scales, coefficients)) }
}

/// Replaces the glyphs (for every frame in flight, without waiting) with `count`
/// Cartesian tensors of order `order`, as the scene format's `tensor` kind stores them:
/// `symmetric` 1 for the (order + 1)(order + 2) / 2 unique entries in lexicographic
/// order of their sorted index tuples (orders 1 to 12), 0 for all 3^order entries with
/// the last index running fastest (orders 1 to 4). `centers` holds 3 doubles per glyph,
/// `scales` one, `coefficients` the entries of each glyph in turn.
///
/// # Safety
/// `renderer` is live; the arrays hold `count` glyphs' values.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_renderer_set_tensor_glyphs(
    renderer: *mut GlyphcastRenderer,
    order: u32,
    symmetric: u32,
    count: u32,
    centers: *const f64,
    scales: *const f64,
    coefficients: *const f64,
) -> GlyphcastStatus {
    use glyphcast::glyph::{Symmetry, TensorLayout};
    let kind = match symmetric {
        0 | 1 => {
            let largest = glyphcast::catalog::max_order(symmetric == 1);
            let symmetry = if symmetric == 1 {
                Symmetry::Symmetric
            } else {
                Symmetry::NonSymmetric
            };
            if (1..=largest).contains(&order) {
                Ok(GlyphKind::Tensor(TensorLayout { order, symmetry }))
            } else {
                Err(format!(
                    "order {order}: glyphcast draws {} tensors of orders 1 to {largest}",
                    if symmetric == 1 {
                        "symmetric"
                    } else {
                        "non-symmetric"
                    }
                ))
            }
        }
        _ => Err(format!("symmetric {symmetric}: 1 or 0")),
    };
    // SAFETY: the caller's promise.
    unsafe { set_glyphs(renderer, kind, count, (centers, scales, coefficients)) }
}

/// The glyph arrays of the `set_*_glyphs` calls: centres, scales, coefficients.
type GlyphArrays = (*const f64, *const f64, *const f64);

/// Replaces the renderer's glyphs with one set of `kind` (or fails with `kind`'s error).
///
/// # Safety
/// `renderer` is live or NULL; the arrays hold `count` glyphs of `kind`.
unsafe fn set_glyphs(
    renderer: *mut GlyphcastRenderer,
    kind: Result<GlyphKind, String>,
    count: u32,
    (centers, scales, coefficients): GlyphArrays,
) -> GlyphcastStatus {
    // SAFETY: the caller's promise.
    let Some(r) = (unsafe { renderer.as_mut() }) else {
        return fail(GlyphcastStatus::InvalidArgument, "renderer is NULL");
    };
    let n = count as usize;
    let negative = r.negative;
    let mut sets = Vec::new();
    let status = guarded(None, || {
        let kind = kind.map_err(invalid)?;
        let per_glyph = kind.coefficient_count();
        if centers.is_null() || scales.is_null() || coefficients.is_null() {
            return Err(invalid("centers, scales and coefficients must not be NULL"));
        }
        // SAFETY: the caller's promise about the arrays' lengths.
        let (c, s, w) = unsafe {
            (
                std::slice::from_raw_parts(centers, 3 * n),
                std::slice::from_raw_parts(scales, n),
                std::slice::from_raw_parts(coefficients, per_glyph * n),
            )
        };
        let mut set = GlyphSet::from_arrays("the glyph arrays", kind, c, s, w)
            .map_err(|e| invalid(e.to_string()))?;
        set.negative = negative;
        sets.push(
            glyphcast::render::glyph_data::prepare_set(&set, 0, 0.0).map_err(from_glyphcast)?,
        );
        Ok(())
    });
    if status != GlyphcastStatus::Ok {
        return record_error(r, status);
    }
    let glyphs = &mut r.renderer;
    let status = guarded(None, || glyphs.set_glyphs(&sets).map_err(from_glyphcast));
    record_error(r, status)
}

/// Copies the thread's last message into the renderer's after a failure.
fn record_error(r: &GlyphcastRenderer, status: GlyphcastStatus) -> GlyphcastStatus {
    if status != GlyphcastStatus::Ok {
        let text = LAST_ERROR.with(|e| e.borrow().clone());
        if let Ok(mut last) = r.last_error.lock() {
            *last = text;
        }
    }
    status
}

/// Begins frame `frame_index`: its camera (column-major 4 x 4 doubles: `view` world to
/// view, a rigid motion; `projection` view to Vulkan clip space, y down, centred, in the
/// renderer's depth convention) and the rectangle it is drawn in. Call it once the
/// host's previous submission of this frame index has completed.
///
/// # Safety
/// `renderer` is live; `view` and `projection` point to 16 doubles; `viewport` is valid.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_renderer_set_view(
    renderer: *mut GlyphcastRenderer,
    frame_index: u32,
    view: *const f64,
    projection: *const f64,
    viewport: *const GlyphcastViewport,
) -> GlyphcastStatus {
    // SAFETY: the caller's promise.
    let Some(r) = (unsafe { renderer.as_mut() }) else {
        return fail(GlyphcastStatus::InvalidArgument, "renderer is NULL");
    };
    let glyphs = &mut r.renderer;
    let status = guarded(None, || {
        if view.is_null() || projection.is_null() || viewport.is_null() {
            return Err(invalid("view, projection and viewport must not be NULL"));
        }
        // SAFETY: the caller's promise: 16 doubles each, and a viewport.
        let (view, projection, rect) = unsafe {
            (
                &*(view as *const [f64; 16]),
                &*(projection as *const [f64; 16]),
                *viewport,
            )
        };
        let scissor = vk::Rect2D {
            offset: vk::Offset2D {
                x: rect.x,
                y: rect.y,
            },
            extent: vk::Extent2D {
                width: rect.width,
                height: rect.height,
            },
        };
        let host = HostView {
            view: DMat4::from_cols_array(view),
            projection: DMat4::from_cols_array(projection),
            viewport: vk::Viewport {
                x: rect.x as f32,
                y: rect.y as f32,
                width: rect.width as f32,
                height: rect.height as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            },
            scissor,
        };
        glyphs
            .set_view(frame_index as usize, &host)
            .map_err(from_glyphcast)
    });
    record_error(r, status)
}

/// Records frame `frame_index`'s glyphs into `command_buffer`, which is inside dynamic
/// rendering with the renderer's formats and samples (or inside the render pass's
/// subpass the renderer was made for). Records only; several threads may
/// call it at once with their own command buffers.
///
/// # Safety
/// `renderer` is live; `command_buffer` is recording.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_renderer_record(
    renderer: *const GlyphcastRenderer,
    command_buffer: VkCommandBuffer,
    frame_index: u32,
) -> GlyphcastStatus {
    // SAFETY: the caller's promise.
    let Some(r) = (unsafe { renderer.as_ref() }) else {
        return fail(GlyphcastStatus::InvalidArgument, "renderer is NULL");
    };
    let cmd = vk::CommandBuffer::from_raw(command_buffer as u64);
    guarded(Some(r), || {
        r.renderer
            .record(cmd, frame_index as usize)
            .map_err(from_glyphcast)
    })
}

/// With [`GlyphcastPath::Compute`]: records frame `frame_index`'s dispatches of the
/// compute ray caster into `command_buffer`, outside any rendering and before the
/// rendering in which [`glyphcast_renderer_record`] draws their outputs. It writes only
/// glyphcast's own buffers, with the barriers they need; the host's images need nothing
/// more than for the fragment path. On the fragment path it records the clearing of the
/// frame's per-pixel known depths where the frame culls hidden glyphs by early outs (the
/// default on a device that jumps over code no pixel runs, one sample per pixel), which
/// the frame's next [`glyphcast_renderer_record`] takes; nothing otherwise.
///
/// # Safety
/// `renderer` is live; `command_buffer` is recording, outside any rendering.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_renderer_record_compute(
    renderer: *mut GlyphcastRenderer,
    command_buffer: VkCommandBuffer,
    frame_index: u32,
) -> GlyphcastStatus {
    // SAFETY: the caller's promise.
    let Some(r) = (unsafe { renderer.as_mut() }) else {
        return fail(GlyphcastStatus::InvalidArgument, "renderer is NULL");
    };
    let cmd = vk::CommandBuffer::from_raw(command_buffer as u64);
    let glyphs = &mut r.renderer;
    let status = guarded(None, || {
        glyphs
            .record_compute(cmd, frame_index as usize)
            .map_err(from_glyphcast)
    });
    record_error(r, status)
}

/// The message of the renderer's last failure ("" if none); valid until its next call.
///
/// # Safety
/// `renderer` is live or NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_renderer_last_error(
    renderer: *const GlyphcastRenderer,
) -> *const c_char {
    // SAFETY: the caller's promise.
    match unsafe { renderer.as_ref() } {
        Some(r) => match r.last_error.lock() {
            Ok(last) => last.as_ptr(),
            Err(_) => c"the renderer's error lock is poisoned".as_ptr(),
        },
        None => glyphcast_last_error(),
    }
}

/// The message of this thread's last failure ("" if none), for calls that have no
/// renderer (creation); valid until the thread's next call.
#[unsafe(no_mangle)]
pub extern "C" fn glyphcast_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Writes `width` x `height` RGBA8 pixels (sRGB, row-major from the top-left) as a PNG.
///
/// # Safety
/// `path` is a NUL-terminated string; `rgba` holds 4 * width * height bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn glyphcast_write_png(
    path: *const c_char,
    width: u32,
    height: u32,
    rgba: *const u8,
) -> GlyphcastStatus {
    guarded(None, || {
        if path.is_null() || rgba.is_null() {
            return Err(invalid("path and rgba must not be NULL"));
        }
        // SAFETY: the caller's promise.
        let path = unsafe { CStr::from_ptr(path) }
            .to_str()
            .map_err(|_| invalid("path is not UTF-8"))?;
        let len = 4 * width as usize * height as usize;
        // SAFETY: the caller's promise.
        let pixels = unsafe { std::slice::from_raw_parts(rgba, len) };
        glyphcast::io::png::write_png_rgba8(path.as_ref(), width, height, pixels)
            .map_err(from_glyphcast)
    })
}
