//! Files in and out: scene JSON, NIfTI volumes, PNG images and NumPy depth maps.
pub mod atomic;
pub mod nifti;
pub mod npy;
pub mod png;
pub mod scene;
