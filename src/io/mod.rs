//! Files in and out: scene JSON, NIfTI and MRtrix volumes, Voigt stiffness files, PNG
//! images and NumPy depth maps.
pub mod atomic;
pub mod folder;
#[cfg(feature = "volume")]
pub mod image;
#[cfg(feature = "volume")]
pub mod input_limit;
#[cfg(feature = "volume")]
pub mod mif;
#[cfg(feature = "volume")]
pub mod nifti;
pub mod npy;
pub mod png;
pub mod scene;
pub mod stiffness;
