//! Files in and out: scene JSON, Voigt stiffness files, PNG images, NumPy depth maps
//! and all-or-nothing output sets. NIfTI and MRtrix images are `glyphcast_dmri::io`.
pub mod atomic;
pub mod folder;
pub mod npy;
pub mod png;
pub mod scene;
pub mod stiffness;
