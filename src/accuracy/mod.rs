//! Accuracy of the GPU methods against the float64 reference: the comparison of depth
//! maps, the geometric error of a render in pixels (surface and silhouettes), the suite
//! of hard scenes, and the report `glyphcast accuracy` prints.
mod compare;
mod geometric;
pub mod report;
pub mod suite;

pub use compare::{DepthComparison, compare_depth, silhouette_band};
pub use geometric::{GeometricError, geometric_error, pixel_size};
