//! glyphcast's exact glyphs inside wgpu applications (Bevy, Rerun, any engine on wgpu's
//! Vulkan backend).
//!
//! A thin layer: wgpu's Vulkan objects (`as_hal`) are mapped onto glyphcast's engine
//! component ([`glyphcast::GlyphRenderer`]), which records the glyphs into a raw command
//! buffer of wgpu's. Nothing of the renderer is repeated here.
//!
//! 1. Create the device with the Vulkan features glyphcast needs
//!    ([`REQUIRED_VULKAN_FEATURES`]): [`request_device`] in place of
//!    `Adapter::request_device`, or [`enable_features`] in the application's own
//!    device-creation callback (Bevy's `raw_vulkan_init`).
//! 2. Make a [`GlyphPass`] for the target's formats and give it glyphs: from the
//!    application's arrays ([`GlyphSet::from_arrays`], then [`GlyphPass::set_glyph_sets`]),
//!    or prepared sets ([`GlyphPass::set_glyphs`], from [`prepare_scene`] of a scene file).
//! 3. Each frame, after drawing the scene into a colour and a depth texture, submit the
//!    two command buffers of [`GlyphPass::encode`]: the glyphs are depth-tested against
//!    the scene and write their depth for the passes after.
//!
//! Rules the crate follows (wgpu's raw-API pitfalls): the raw commands get an encoder of
//! their own (wgpu panics when one encoder mixes its own encoding with `as_hal_mut`);
//! wgpu tracks no state for raw commands, so a wgpu encoder first puts the textures into
//! the attachment states and the raw commands record their own barriers, leaving each
//! texture in the layout wgpu believes it is in; the ash that glyphcast and wgpu-hal use
//! is one crate version (0.38), so handles pass between them unchanged.
#![warn(missing_docs)]

// The wgpu this build is for, under one name (Cargo.toml's features).
/// The wgpu this build of glyphcast-wgpu draws with (30 by default, 29 with the feature
/// `wgpu29`): an application names its types through this, so that the two agree.
#[cfg(all(feature = "wgpu29", not(feature = "wgpu30")))]
pub extern crate wgpu29 as wgpu;
/// The wgpu this build of glyphcast-wgpu draws with (30 by default, 29 with the feature
/// `wgpu29`): an application names its types through this, so that the two agree.
#[cfg(feature = "wgpu30")]
pub extern crate wgpu30 as wgpu;
#[cfg(not(any(feature = "wgpu29", feature = "wgpu30")))]
compile_error!("glyphcast-wgpu needs one of its features wgpu30 (the default) or wgpu29");

mod device;
mod pass;
mod target;
pub mod validation;

pub use device::{REQUIRED_VULKAN_FEATURES, check_adapter, enable_features, request_device};
pub use pass::{GlyphPass, GlyphPassDesc, GlyphTarget, WgpuCamera};

// What an application uses of glyphcast's core beside the pass, so that it needs no
// dependency of its own on glyphcast (of a version that must match this crate's).
pub use glyphcast;
pub use glyphcast::glam;
pub use glyphcast::glyph::{GlyphShape, Symmetry, TensorLayout};
pub use glyphcast::render::glyph_data::prepare_set;
pub use glyphcast::{
    ColorMode, DepthConvention, GlyphKind, GlyphSet, GlyphSetData, Method, NegativeMode,
    RenderSettings, Scene, ShBasis, prepare_scene,
};

/// Why glyphs could not be drawn in a wgpu application.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The adapter or device is on another backend than Vulkan.
    NotVulkan {
        /// The backend it is on.
        backend: wgpu::Backend,
    },
    /// The adapter lacks what glyphcast needs.
    MissingFeatures {
        /// The adapter's name.
        adapter: String,
        /// What it lacks, comma-separated.
        missing: String,
    },
    /// wgpu could not create the device.
    CreateDevice(String),
    /// The device failed while waiting for a frame.
    Device(String),
    /// A target the pass cannot draw into: which texture (or format), what the pass
    /// expects of it, and what it is.
    Target {
        /// "colour", "depth", "resolve", or the format of a description.
        texture: &'static str,
        /// What the pass expects.
        expected: String,
        /// What it is.
        found: String,
    },
    /// Settings that ask for the compute ray caster (`path: compute`), whose dispatches
    /// the pass does not record (it records the fragment ray caster).
    ComputePath,
    /// Samples per pixel other than 1, 2, 4 or 8.
    Samples(u32),
    /// The command buffers of `frames` frames ago were neither submitted nor dropped
    /// when their frame slot's turn came again.
    FramesHeld {
        /// Frames in flight of the pass.
        frames: usize,
    },
    /// glyphcast's core refused or failed.
    Glyphcast(glyphcast::Error),
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::NotVulkan { backend } => write!(
                f,
                "glyphcast draws through wgpu's Vulkan backend; this adapter is on {backend:?} \
                 (ask for Backends::VULKAN)"
            ),
            Error::MissingFeatures { adapter, missing } => write!(
                f,
                "the Vulkan device '{adapter}' lacks what glyphcast needs: {missing}"
            ),
            Error::CreateDevice(e) => write!(f, "creating the wgpu device: {e}"),
            Error::Device(e) => write!(f, "the wgpu device: {e}"),
            Error::Target {
                texture,
                expected,
                found,
            } => write!(
                f,
                "glyph target: the {texture} texture should be {expected}; it is {found}"
            ),
            Error::ComputePath => write!(
                f,
                "glyphcast-wgpu draws with the fragment ray caster (path fragment or auto): \
                 it records no compute-path dispatches"
            ),
            Error::Samples(samples) => write!(
                f,
                "{samples} samples per pixel: glyphcast draws 1, 2, 4 or 8"
            ),
            Error::FramesHeld { frames } => write!(
                f,
                "the glyphs' command buffers of {frames} frames ago were neither submitted \
                 nor dropped: submit (or drop) each frame's before encoding {frames} more"
            ),
            Error::Glyphcast(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Glyphcast(e) => Some(e),
            _ => None,
        }
    }
}

impl From<glyphcast::Error> for Error {
    fn from(e: glyphcast::Error) -> Self {
        Error::Glyphcast(e)
    }
}

/// This crate's result.
pub type Result<T> = std::result::Result<T, Error>;
