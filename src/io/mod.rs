//! Files in and out: scene JSON, NIfTI and MRtrix volumes, PNG images and NumPy depth maps.
pub mod atomic;
pub mod image;
pub mod input_limit;
pub mod mif;
pub mod nifti;
pub mod npy;
pub mod png;
pub mod scene;
