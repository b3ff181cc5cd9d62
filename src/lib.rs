//! glyphcast: GPU ray casting of higher-order tensor and spherical-harmonic glyphs.
pub mod accuracy;
pub mod bench;
pub mod camera;
pub mod demo;
pub mod error;
pub mod fit;
pub mod glyph;
pub mod io;
pub mod render;
pub mod vk;
pub mod volume;

pub use error::{Error, Result};
