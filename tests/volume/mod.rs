//! Volume input: NIfTI volumes of tensor and SH coefficients as scenes. The volumes are
//! written by the tests (`fixtures`) with a known affine; the expected centres, axes and
//! errors are computed here independently of the library.
//!
//! Run with lavapipe for the rendering tests:
//! `VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json cargo test -p glyphcast-cli --test integration volume::`.

mod cli;
mod fixtures;
mod geometry;
mod real_data;
mod selection;
mod sh;
