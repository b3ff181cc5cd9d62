//! Accuracy of the GPU methods against the float64 reference: the comparison of depth
//! maps, the suite of hard scenes, and the report `glyphcast accuracy` prints.
mod compare;
pub mod report;
pub mod suite;

pub use compare::{DepthComparison, compare_depth, silhouette_band};
