#![warn(missing_docs)]
//! Diffusion MRI for glyphcast: NIfTI and MRtrix images in and out, slices of SH,
//! tensor and peak volumes as glyph scenes, the DWI fits (tensors, SH, fibre ODFs by
//! CSA, Q-ball, CSD and multi-shell CSD), fibre peaks, and one subject's
//! quality-control figure set.
//!
//! Everything here builds on the renderer core, the crate `glyphcast`: a volume becomes
//! a [`glyphcast::Scene`], drawn by [`glyphcast::HeadlessRenderer`] or by an engine's
//! [`glyphcast::GlyphRenderer`].
pub mod fit;
pub mod io;
pub mod qc;
pub mod setting;
pub mod volume;
